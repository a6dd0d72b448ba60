"""Settings: defaults, environment, config file, overrides; default controllers."""

from __future__ import annotations

import logging

import pytest
from motionsim.app.service import build_registry
from motionsim.app.settings import Settings, build_settings
from pydantic import ValidationError

import tests.dummy_kind  # noqa: F401


def test_defaults_are_the_documented_ones():
    s = Settings()
    assert (s.host, s.port, s.clock.mode, s.clock.factor) == ("127.0.0.1", 8000, "realtime", 1.0)
    assert s.controllers is None and s.pmac_port is None and s.trio_port is None


def test_environment_then_file_then_overrides(tmp_path, monkeypatch):
    monkeypatch.setenv("MOTIONSIM_PORT", "9001")
    monkeypatch.setenv("MOTIONSIM_HOST", "0.0.0.0")
    f = tmp_path / "ms.yaml"
    f.write_text("port: 9002\nclock: {mode: virtual}\npmac_port: auto\n"
                 "controllers:\n  - {id: a, kind: dummy, config: {tick_s: 0.5}}\n")
    s = build_settings(f, port=9003, trio_port=0)
    assert (s.host, s.port, s.clock.mode, s.pmac_port, s.trio_port) == (
        "0.0.0.0", 9003, "virtual", "auto", 0)
    assert s.controllers[0].config == {"tick_s": 0.5}


@pytest.mark.parametrize("data", [{"colour": 1}, {"clock": {"mode": "x"}},
                                  {"clock": {"factor": -1}}, {"pmac_port": 70000},
                                  {"pmac_port": "sometimes"}, {"controllers": [{"id": "a"}]}])
def test_bad_settings_are_rejected(data):
    with pytest.raises(ValidationError):
        Settings(**data)


def test_default_controllers_skip_kinds_that_are_not_installed(caplog, monkeypatch):
    import motionsim.app.service as service

    monkeypatch.setattr(service, "kinds", lambda: {"trio": object})
    with caplog.at_level(logging.WARNING):
        reg = build_registry(Settings(controllers=None))
    assert "pmac" not in reg
    assert "default controller 'pmac' skipped" in caplog.text


def test_explicit_controller_with_unknown_kind_is_an_error():
    from motionsim.sim.errors import InvalidValue

    with pytest.raises(InvalidValue):
        build_registry(Settings(controllers=[{"id": "a", "kind": "zz"}]))


def test_controller_clock_defaults_to_the_service_clock():
    reg = build_registry(Settings(clock={"mode": "virtual"}, controllers=[
        {"id": "a", "kind": "dummy"},
        {"id": "b", "kind": "dummy", "clock": {"mode": "realtime", "factor": 5}}]))
    assert reg.get("a").clock.mode == "virtual"
    assert (reg.get("b").clock.mode, reg.get("b").clock.factor) == ("realtime", 5.0)


def test_plugins_are_imported_first():
    reg = build_registry(Settings(plugins=["tests.dummy_kind"],
                                  controllers=[{"id": "a", "kind": "dummy_cmdline"}]))
    assert reg.get("a").kind == "dummy_cmdline"
