"""Scenario files: bad input names the field and the line, and nothing runs."""

from __future__ import annotations

import random
import textwrap

import pytest
from motionsim.app.scenarios.errors import ScenarioError
from motionsim.app.scenarios.model import load_scenario, loads_scenario

GOOD = """\
name: ok
seed: 3
duration_s: 1
controllers:
  pmac:
    kind: pmac
    config: {i16: 5, i17: 10}
    rotary:
      - {cs: 1, size_words: 600}
hosts:
  - type: breq_interrupt
    latency: {dist: normal, mean_ms: 2, sd_ms: 1, jitter_ms: 3}
    lines_per_interrupt: 5
    program:
      generate: {moves: 3, move_ms: 1, axes: 2}
"""


def bad(text: str) -> ScenarioError:
    with pytest.raises(ScenarioError) as info:
        loads_scenario(textwrap.dedent(text), file="s.yaml")
    return info.value


def test_a_good_scenario_validates():
    s = loads_scenario(GOOD)
    h = s.hosts[0]
    assert h.program.to_lines() == ["LINEAR", "ABS", "TA1", "TS0", "TM1", "X1 Y1", "X2 Y2", "X3 Y3"]
    d = h.latency.to_delay()
    assert (d.kind, d.a, d.b, d.jitter_s) == ("normal", 0.002, 0.001, 0.003)
    assert s.host_names() == ["breq_interrupt0"]


def test_unknown_field_names_field_and_line():
    e = bad(GOOD.replace("    lines_per_interrupt: 5\n", "    lines_per_interupt: 5\n"))
    assert e.field == "hosts[0].lines_per_interupt"
    assert e.line == 13
    assert "s.yaml:13" in str(e)


def test_wrong_type_names_field_and_line():
    e = bad(GOOD.replace("size_words: 600", "size_words: lots"))
    assert e.field == "controllers.pmac.rotary[0].size_words"
    assert e.line == 9


def test_negative_latency_is_refused():
    e = bad(GOOD.replace("mean_ms: 2", "mean_ms: -2"))
    assert e.field == "hosts[0].latency.mean_ms" and e.line == 12
    assert "greater than or equal to 0" in e.message


def test_i16_above_i17_is_refused_at_the_i16_line():
    e = bad(GOOD.replace("i16: 5", "i16: 12"))
    assert e.field == "controllers.pmac.config.i16"
    assert e.line == 7
    assert "above" in e.message


def test_i16_above_default_i17_is_refused_too():
    e = bad(GOOD.replace("{i16: 5, i17: 10}", "{i16: 11}"))
    assert "i17 = 10" in e.message


def test_every_problem_is_listed():
    e = bad(GOOD.replace("mean_ms: 2", "mean_ms: -2").replace("seed: 3", "seed: x"))
    fields = {x["field"] for x in e.errors}
    assert fields == {"seed", "hosts[0].latency.mean_ms"}
    assert e.to_dict()["code"] == "validation_error"


def test_host_for_a_missing_rotary_buffer_is_refused():
    e = bad(GOOD.replace("    lines_per_interrupt: 5\n", "    lines_per_interrupt: 5\n    cs: 2\n"))
    assert e.field == "hosts[0].cs" and "no rotary buffer for &2" in e.message


def test_trio_host_on_a_pmac_is_refused():
    e = bad(
        GOOD.replace(
            "  - type: breq_interrupt",
            "  - type: trio_blind\n    moves: {per_axis: {0: [1]}}\n  - type: breq_interrupt",
        )
    )
    assert e.field == "hosts[0].type"


def test_distribution_fields_must_fit_the_distribution():
    e = bad(GOOD.replace("{dist: normal, mean_ms: 2, sd_ms: 1, jitter_ms: 3}",
                         "{dist: uniform, low_ms: 3, high_ms: 1}"))  # fmt: skip
    assert "high_ms must be >= low_ms" in e.message and e.field == "hosts[0].latency"
    e = bad(GOOD.replace("{dist: normal, mean_ms: 2, sd_ms: 1, jitter_ms: 3}",
                         "{dist: fixed, ms: 1, sd_ms: 2}"))  # fmt: skip
    assert "sd_ms not used" in e.message


def test_yaml_syntax_error_has_a_line():
    e = bad("controllers:\n  pmac: {kind: pmac\n")
    assert e.line is not None and "not valid YAML" in e.message


def _with_empirical_latency(path, file: str) -> None:
    """Write :data:`GOOD` to ``path`` with the host latency drawn from ``file``."""
    path.write_text(GOOD.replace("{dist: normal, mean_ms: 2, sd_ms: 1, jitter_ms: 3}",
                                 f"{{dist: empirical, file: {file}}}"))


def test_empirical_latencies_from_a_file(tmp_path):
    (tmp_path / "lat.csv").write_text("latency_ms\n1.5\n2.5\n# comment\n4\n")
    _with_empirical_latency(tmp_path / "s.yaml", "lat.csv")
    s = load_scenario(tmp_path / "s.yaml")
    d = s.hosts[0].latency.to_delay()
    assert d.values == (0.0015, 0.0025, 0.004)
    rng = random.Random(1)
    assert {d.draw(rng) for _ in range(200)} == {0.0015, 0.0025, 0.004}


def test_empirical_file_with_a_negative_latency_names_its_line(tmp_path):
    (tmp_path / "lat.txt").write_text("1\n-2\n")
    _with_empirical_latency(tmp_path / "s.yaml", "lat.txt")
    with pytest.raises(ScenarioError) as info:
        load_scenario(tmp_path / "s.yaml")
    assert "lat.txt line 2" in info.value.message
    assert info.value.line == 12


def test_program_from_a_file_drops_comments(tmp_path):
    (tmp_path / "prog.pmc").write_text("X10 ; first\n\nM1==1\nX20\n")
    text = GOOD.replace("generate: {moves: 3, move_ms: 1, axes: 2}", "file: prog.pmc")
    (tmp_path / "s.yaml").write_text(text)
    s = load_scenario(tmp_path / "s.yaml")
    assert s.hosts[0].program.to_lines() == ["X10", "M1==1", "X20"]
