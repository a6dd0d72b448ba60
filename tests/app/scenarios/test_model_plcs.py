"""The ``plcs:`` section of a PMAC controller: PLC programs validated before anything runs,
errors naming the field and the file line (of the bad PLC line itself)."""

from __future__ import annotations

import textwrap

import pytest
from motionsim.app.scenarios.errors import ScenarioError
from motionsim.app.scenarios.model import loads_scenario
from motionsim.app.scenarios.runner import run

HEAD = """\
name: plcs
duration_s: 0.1
controllers:
  p:
    kind: pmac
    config: {i5: 3}
    plcs:
"""


def scenario(plcs: str, head: str = HEAD):
    return loads_scenario(head + textwrap.indent(textwrap.dedent(plcs), "      "), file="s.yaml")


def bad(plcs: str, head: str = HEAD) -> ScenarioError:
    with pytest.raises(ScenarioError) as info:
        scenario(plcs, head)
    return info.value


def test_plc_programs_inline_enabled_and_enabled_later_run():
    scn = scenario("""\
        - plc: 0
          text: |
            P1=P1+1
            M7=P1
        - {plc: 3, text: "P3=P3+1", enabled: false}
        - {plc: 4, text: "P4=P4+1", enable_at_ms: 20}
    """)
    p0, p3, p4 = scn.controllers["p"].plcs
    assert (p0.enabled_at_start, p3.enabled_at_start, p4.enabled_at_start) == (True, False, False)
    result = run(scn)
    ctl = result.controllers["p"]
    enabled = [(e.t, e.fields["plc"]) for e in ctl.log.events("plc")]
    assert enabled[0] == (0.0, 0)
    assert [n for _, n in enabled] == [0, 4] and 0.02 <= enabled[1][0] < 0.021
    assert ctl.get_variable("P1") > 10 and ctl.get_variable("P3") == 0
    assert ctl.get_variable("P4") > 10
    assert ctl.log.events("cpu_sample")  # PLCs: the processor load is sampled (50 ms)


def test_a_bad_plc_line_names_the_file_line_of_that_line():
    e = bad("""\
        - plc: 0
          text: |
            P1=P1+1
            IF (P1>10)
              P2=
            ENDIF
    """)
    assert e.field == "controllers.p.plcs[0].text"
    assert e.line == 12  # the line "P2=" in the file
    assert e.message.startswith("PLC 0 line 3, column 6:")
    assert "'P2='" in e.message
    assert str(e).startswith("s.yaml:12: controllers.p.plcs[0].text: PLC 0 line 3")


def test_an_unclosed_if_is_a_structure_error_at_the_last_line():
    e = bad("""\
        - plc: 1
          text: |
            IF (P1>10)
            P2=1
    """)
    assert e.field == "controllers.p.plcs[0].text" and e.line == 11
    assert "IF of line 1 (column 1) is not closed" in e.message  # ERR009, buffers/flow.py


def test_a_plc_file_error_names_the_plc_file_and_its_line(tmp_path):
    (tmp_path / "bad.plc").write_text("P1=1\nP2=(3\n")
    text = HEAD + "      - {plc: 2, file: bad.plc}\n"
    with pytest.raises(ScenarioError) as info:
        loads_scenario(text, file="s.yaml", base_dir=tmp_path)
    e = info.value
    assert e.field == "controllers.p.plcs[0].file" and e.line == 8
    assert e.message.startswith("bad.plc line 2, column")


def test_a_missing_plc_file_is_refused(tmp_path):
    with pytest.raises(ScenarioError) as info:
        loads_scenario(HEAD + "      - {plc: 2, file: nope.plc}\n", base_dir=tmp_path)
    assert "cannot read PLC file 'nope.plc'" in info.value.message


@pytest.mark.parametrize(
    ("plcs", "field", "words"),
    [
        ("- {plc: 32, text: P1=1}", "controllers.p.plcs[0].plc", "less than or equal to 31"),
        ("- {plc: 1}", "controllers.p.plcs[0]", "exactly one of text, file"),
        ("- {plc: 1, text: P1=1, file: a.plc}", "controllers.p.plcs[0]", "exactly one"),
        ("- {plc: 1, text: P1=1, enable_at_ms: -1}", "controllers.p.plcs[0].enable_at_ms",
         "greater than or equal to 0"),
        ("- {plc: 1, text: P1=1, enabled: true, enable_at_ms: 5}", "controllers.p.plcs[0]",
         "drop enable_at_ms"),
        ("- {plc: 1, text: P1=1, run: true}", "controllers.p.plcs[0].run", "Extra inputs"),
        ("- {plc: 1, text: P1=1}\n- {plc: 1, text: P2=1}", "controllers.p",
         "one entry per PLC number"),
    ],
)
def test_bad_plc_entries_are_refused_with_their_field(plcs, field, words):
    e = bad(plcs)
    assert e.field == field
    assert words in e.message
    assert e.line is not None


def test_a_plc_that_i5_does_not_let_run_is_refused():
    head = HEAD.replace("config: {i5: 3}", "config: {i5: 1}")
    e = bad("- {plc: 5, text: P1=1, enabled: true}", head)
    assert e.field == "controllers.p.plcs[0].enabled" and e.line == 8
    assert "PLC 5 (background) is enabled but I5 = 1" in e.message
    e = bad("- {plc: 0, text: P1=1}", HEAD.replace("config: {i5: 3}", "config: {i5: 2}"))
    assert "PLC 0 (foreground)" in e.message and e.field == "controllers.p.plcs[0].plc"
    scenario("- {plc: 5, text: P1=1, enabled: false}", head)  # stored, not run: fine


def test_plcs_are_for_pmac_only():
    e = bad("- {plc: 0, text: P1=1}", HEAD.replace("kind: pmac", "kind: trio").replace(
        "config: {i5: 3}", "config: {}"))
    assert "plcs is for kind pmac, not trio" in e.message


def test_cpu_sampling_period():
    scn = scenario("- {plc: 0, text: P1=1}")
    assert scn.controllers["p"].sample_period_s() == 0.05
    every_10 = HEAD.replace("config:", "cpu_sample_ms: 10\n    config:")
    scn = scenario("- {plc: 0, text: P1=1}", every_10)
    assert scn.controllers["p"].sample_period_s() == 0.01
    e = bad("- {plc: 0, text: P1=1}", HEAD.replace("config:", "cpu_sample_ms: 0\n    config:"))
    assert e.field == "controllers.p.cpu_sample_ms"
