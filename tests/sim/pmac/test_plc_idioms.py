"""PLC statements of real programs (spec §12.2; TSRM p421-424; seed 003), on the event log.

``ADDRESS&n`` / ``ADDRESS#n``, ``COMMAND"..."`` / ``CMD^letter``, ``SEND``/``SENDS``/``SENDP``,
``ENABLE``/``DISABLE PLC`` written without blanks, ``END IF`` / ``END WHILE`` with a blank, and
the background scan rule across a loop's exit. Times in servo cycles.
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError


def enter(rig, *lines: str, n: int = 1) -> None:
    rig.ok(f"OPEN PLC {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def m_events(rig, name: str) -> list[tuple[int, float]]:
    return [(k, f["value"]) for k, _, f in rig.events("mvar") if f["name"] == name]


def test_seed003_scan_ends_at_endwhile_and_holds_across_the_loop_exit(rig):
    """Seed 003: a scan runs to the end or to an ENDWHILE. The statement before the loop runs
    once per pass from the top; the scan that leaves the loop runs only what follows it, and
    every later scan runs both once: before == after on every cycle once the loop is done."""
    rig.ok("I5=2")
    enter(rig, "M1=M1+1", "WHILE (P5<3)", "P5=P5+1", "END WHILE", "M2=M2+1")
    rig.ok("ENABLE PLC 1")
    rig.run_for(rig.period * 30)
    before, after = m_events(rig, "M1"), m_events(rig, "M2")
    k0 = before[0][0]
    # scans k0 (P5 -> 1), k0+1 (-> 2), k0+2 (-> 3) end at the ENDWHILE; k0+3 leaves the loop
    assert before[:2] == [(k0, 1), (k0 + 4, 2)]
    assert after[:2] == [(k0 + 3, 1), (k0 + 4, 2)]
    last = min(before[-1][0], after[-1][0])
    assert [k for k, _ in before[1:] if k <= last] == [k for k, _ in after[1:] if k <= last]
    assert all(v == i + 1 for i, (_, v) in enumerate(before))
    assert all(v == i + 1 for i, (_, v) in enumerate(after))


def test_tsrm_p421_address_cs_selects_the_plcs_q_variables(rig):
    rig.ok("I5=2")
    enter(rig, "ADDRESS&3", "Q77=Q77+1", "ADR&1", "Q77=Q77+10", "DISPLC1")
    rig.ok("ENAPLC1")
    rig.run_for(rig.period * 10)
    assert rig.ok("&3 Q77") == "1"
    assert rig.ok("&1 Q77") == "10"


def test_tsrm_p421_cmd_after_address_goes_to_that_motor_and_cs(rig):
    rig.ok("I5=2")
    enter(rig, "ADDRESS#4 ADDRESS&2", 'COMMAND"P10=Q5"', 'CMD"I5213=7"', "DISABLE PLC 1")
    rig.ok("&2 Q5=42")
    rig.ok("ENABLE PLC 1")
    rig.run_for(rig.period * 10)
    assert rig.ok("P10") == "42"
    assert rig.ok("I5213") == "7"


def test_tsrm_p424_cmd_control_letter_d_disables_all_plcs(rig):
    rig.ok("I5=2")
    enter(rig, "M3=M3+1", n=2)
    enter(rig, "IF (P1=1)", "CMD^D", "P1=0", "ENDIF")
    rig.ok("ENABLE PLC 1,2")
    rig.run_for(rig.period * 6)
    rig.ok("P1=1")
    rig.run_for(rig.period * 10)
    states = [(f["plc"], f["state"]) for _, _, f in rig.events("plc")]
    assert states[-2:] == [(1, "disabled"), (2, "disabled")]
    assert rig.c.plcs.to_list()[0]["enabled"] is False


@pytest.mark.parametrize("word", ["SEND", "SENDS", "SENDP", "sendr", "SENDA"])
def test_tsrm_p421_send_reaches_the_host_output_and_the_log(rig, word):
    rig.ok("I5=2")
    enter(rig, f'{word}"HOMED 3"', "DIS PLC 1")
    rig.ok("ENA PLC 1")
    rig.run_for(rig.period * 5)
    (k, _, f), = rig.events("plc_send")
    port = word[4:].upper() or "host"
    assert (f["plc"], f["port"], f["text"]) == (1, port, "HOMED 3")
    sent = [(m.source, m.port, m.text) for m in rig.c.messages.lines]
    assert sent == [("plc1", word[4:].upper(), "HOMED 3")]


def test_a_plc_enables_another_and_disables_itself_written_without_blanks(rig):
    """Diamond's start-up PLC form: DISPLC2..31, ENAPLC6, then DISPLC1 (listing spelling)."""
    rig.ok("I5=2")
    enter(rig, "M6=M6+1", n=6)
    enter(rig, "M7=M7+1", n=7)
    enter(rig, "DISPLC2..31", "ENAPLC6", "DISPLC1")
    rig.ok("ENABLE PLC 7 ENABLE PLC 1")
    rig.run_for(rig.period * 10)
    states = [(f["plc"], f["state"]) for _, _, f in rig.events("plc")]
    assert states == [(7, "enabled"), (1, "enabled"), (7, "disabled"), (6, "enabled"),
                      (1, "disabled")]


def test_end_if_with_a_blank_closes_the_if(rig):
    enter(rig, "IF (P1=0)", "M1=5", "End If", n=0)
    rig.ok("ENABLE PLC 0")
    rig.run_for(rig.period * 4)
    assert m_events(rig, "M1")[0][1] == 5


@pytest.mark.parametrize(("line", "column"), [
    ("ADDRESS&17", 9), ("ADDRESS", 8), ('CMD P1', 4), ("SEND", 5),
])
def test_bad_idiom_argument_is_err003_with_its_column(rig, line, column):
    with pytest.raises(ParseError) as e:
        rig.c.plcs.load(1, line)
    assert (e.value.column, e.value.pmac_error) == (column, "ERR003")
    assert rig.c.plcs.describe(1)["program"] == []

