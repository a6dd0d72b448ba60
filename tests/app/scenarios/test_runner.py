"""Runner details: faults, set-up errors mapped to the scenario line, seeds per host."""

from __future__ import annotations

import pytest
from motionsim.app.scenarios.errors import ScenarioError
from motionsim.app.scenarios.model import loads_scenario
from motionsim.app.scenarios.runner import host_rng, run

from tests.app.scenarios.fragments import breq_stream

BASE = breq_stream("name: faults\nduration_s: 0.3\n", latency="1", moves=400, host="h")


def test_host_stall_fault_starves_the_program_for_its_length():
    scn = loads_scenario(
        BASE + "faults:\n  - {type: host_stall, host: h, at_ms: 100, duration_ms: 50}\n"
    )
    result = run(scn)
    from motionsim.app.scenarios.report import report

    rep = report(result)
    (s,) = rep["starvations"]
    assert s["cause"] == "host_latency"
    assert 0.100 < s["start_s"] < 0.150 < s["end_s"] < 0.152
    writes = [e.t for e in result.events("pmac") if e.type == "host_write"]
    assert not any(0.1 < t < 0.15 for t in writes)


def test_terminal_and_set_variable_faults_act_at_their_time():
    scn = loads_scenario(
        BASE
        + "faults:\n"
        + "  - {type: set_variable, at_ms: 50, name: P7, value: 3}\n"
        + "  - {type: terminal, at_ms: 100, command: '&1 A'}\n"
    )
    result = run(scn)
    ctl = result.controllers["pmac"]
    assert ctl.get_variable("P7") == 3
    states = [(e.t, e["state"]) for e in result.events("pmac") if e.type == "program"]
    assert any(st == "aborted" and 0.1 <= t < 0.11 for t, st in states)


def test_core_error_at_setup_names_the_scenario_field():
    scn = loads_scenario(BASE.replace("i17: 10}", "q99: 1}"))
    with pytest.raises(ScenarioError) as info:
        run(scn)
    assert info.value.field == "controllers.pmac.config"
    assert info.value.line == 6
    assert "q99" in info.value.message


def test_rotary_buffer_bigger_than_memory_names_its_line():
    scn = loads_scenario(BASE.replace("size_words: 400", "size_words: 99999999"))
    with pytest.raises(ScenarioError) as info:
        run(scn)
    assert info.value.field == "controllers.pmac.rotary[0]" and info.value.line == 8


def test_each_host_has_its_own_stream_of_draws():
    assert host_rng(1, "a").random() == host_rng(1, "a").random()
    assert host_rng(1, "a").random() != host_rng(1, "b").random()
    assert host_rng(1, "a").random() != host_rng(2, "a").random()


def test_a_too_small_log_is_reported_not_hidden():
    from motionsim.app.scenarios.report import report

    scn = loads_scenario(BASE + "log_capacity: 1000\n")
    rep = report(run(scn))
    m = rep["controllers"]["pmac"]
    assert m["events_lost"] > 0 and m["events"] > 1000
