"""Compiled PLCs (``OPEN PLCC n``): the source a host downloads is stored and run with the
compiled-PLC scheduling (TUM p376; PUM-V p238; TSRM p39; spec §9.3, §9.5), on the event log.

PLCC 0 runs in the RTI after PLC 0; between two interpreted background-PLC scans every active
PLCC 1-31 runs one scan, low to high; I5 bit 0 permits PLC 0 / PLCC 0, bit 1 the others.
"""

from __future__ import annotations

import pytest


def enter(rig, *lines: str, n: int = 1, compiled: bool = True) -> None:
    rig.ok(f"OPEN {'PLCC' if compiled else 'PLC'} {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def cycles_of(rig, name: str) -> list[int]:
    return [k for k, _, f in rig.events("mvar") if f["name"] == name]


def test_pum_p245_open_plcc_stores_the_source_and_runs_nothing_on_line(rig):
    enter(rig, "M1=M1+1", "P1=5", n=4)
    assert cycles_of(rig, "M1") == [] and rig.ok("P1") == "0"
    assert [ln for ln in rig.c.plcs.compiled[4].program.lines] == ["M1=M1+1", "P1=5"]
    assert rig.c.plcs.plcs[4].program is None  # PLCC 4 is not PLC 4


def test_tum_p376_plcc0_runs_every_rti_after_plc0(rig):
    rig.ok("I5=1")
    enter(rig, "M1=M1+1", n=0, compiled=False)
    enter(rig, "M2=M2+1", n=0)
    rig.ok("ENABLE PLC 0 ENABLE PLCC 0")
    rig.run_for(rig.period * 30)
    plc0, plcc0 = cycles_of(rig, "M1"), cycles_of(rig, "M2")
    assert plcc0 == plc0 and len(plcc0) >= 9
    assert all(k % 3 == 0 for k in plcc0)  # RTIs: every I8+1 = 3 servo cycles
    names = [f["name"] for _, _, f in rig.events("mvar")]
    assert names[:4] == ["M1", "M2", "M1", "M2"]  # PLC 0 first, then PLCC 0


def test_pum_v_p238_every_active_plcc_scans_between_two_interpreted_plc_scans(rig):
    rig.ok("I5=2")
    enter(rig, "M1=M1+1", n=1, compiled=False)
    enter(rig, "M2=M2+1", n=2, compiled=False)
    enter(rig, "M5=M5+1", n=5)
    enter(rig, "M3=M3+1", n=3)
    rig.ok("ENABLE PLC 1,2 ENABLE PLCC 3,5")
    rig.run_for(rig.period * 40)
    m1, m2, m3, m5 = (cycles_of(rig, m) for m in ("M1", "M2", "M3", "M5"))
    # one interpreted PLC per background cycle, in turn; both PLCCs on every cycle
    assert sorted(m1 + m2) == m3 == m5
    assert len(m3) == len(m1) + len(m2) and abs(len(m1) - len(m2)) <= 1
    names = [f["name"] for _, _, f in rig.events("mvar")]
    first = names.index("M3")
    assert names[first - 1] in ("M1", "M2") and names[first + 1] == "M5"  # low to high


@pytest.mark.parametrize(("i5", "runs"), [(0, set()), (1, {"M0"}), (2, {"M7"}),
                                          (3, {"M0", "M7"})])
def test_tsrm_p39_i5_permits_compiled_plcs_like_interpreted_ones(rig, i5, runs):
    rig.ok(f"I5={i5}")
    enter(rig, "M10=M10+1", n=0)
    enter(rig, "M17=M17+1", n=7)
    rig.ok("ENABLE PLCC 0 ENABLE PLCC 7")
    rig.run_for(rig.period * 12)
    ran = {f"M{int(f['name'][1:]) - 10}" for _, _, f in rig.events("mvar")}
    assert ran == runs


def test_enable_and_disable_plcc_emit_plc_events_marked_compiled(rig):
    rig.ok("I5=2")
    enter(rig, "M1=1", n=2)
    enter(rig, "DISABLE PLCC 2 DISPLC1", n=1, compiled=False)
    rig.ok("ENABLE PLCC 2")
    rig.ok("ENABLE PLC 1")
    rig.run_for(rig.period * 10)
    got = [(f["plc"], f["state"], f.get("compiled", False)) for _, _, f in rig.events("plc")]
    assert got == [(2, "enabled", True), (1, "enabled", False), (2, "disabled", True),
                   (1, "disabled", False)]


def test_a_plcc_waits_at_endwhile_on_a_timer_like_a_plc(rig):
    rig.ok("I5=2")
    enter(rig, "M1=1", "I5112=40", "WHILE(I5112>0)", "ENDWHILE", "M1=0", "DIS PLCC 3", n=3)
    rig.ok("ENA PLCC 3")
    rig.run_for(rig.period * 60)
    (k1, k0) = cycles_of(rig, "M1")
    assert k0 - k1 == 40


def test_tsrm_p424_ctrl_d_disables_compiled_plcs_too(rig):
    rig.ok("I5=3")
    enter(rig, "M1=M1+1", n=1)
    enter(rig, "M2=M2+1", n=0)
    rig.ok("ENABLE PLCC 0,1")
    rig.run_for(rig.period * 6)
    rig.ok("\x04")
    since = rig.c.log.last_seq
    rig.run_for(rig.period * 10)
    assert [f["name"] for _, _, f in rig.events("mvar", since=since)] == []
    assert [(f["plc"], f["state"]) for _, _, f in rig.events("plc")][-2:] == [
        (0, "disabled"), (1, "disabled")]


def test_pum_v_p245_saved_plccs_come_back_after_a_reset_and_unsaved_ones_do_not(rig):
    rig.ok("I5=2")
    enter(rig, "M1=M1+1", n=1)
    rig.ok("SAVE")
    enter(rig, "M2=M2+1", n=2)
    rig.ok("$$$")
    rig.run_for(rig.period * 10)
    assert rig.c.plcs.compiled[1].program is not None and rig.c.plcs.compiled[2].program is None
    assert [f["name"] for _, _, f in rig.events("mvar")][-1] == "M1"


def test_pum_v_p245_delete_plcc_erases_that_compiled_plc_and_stops_it(rig):
    rig.ok("I5=2")
    enter(rig, "M1=M1+1", n=3)
    enter(rig, "M2=M2+1", n=5)
    rig.ok("ENABLE PLCC 3,5")
    rig.run_for(rig.period * 6)
    rig.ok("DELETE PLCC 3")
    k_deleted = rig.cyc(rig.c.env.now)
    rig.run_for(rig.period * 6)
    assert max(cycles_of(rig, "M1")) < k_deleted < max(cycles_of(rig, "M2"))
    (k, _, f), = [e for e in rig.events("plc") if e[2]["state"] == "disabled"]
    assert f == {"plc": 3, "state": "disabled", "compiled": True}
    assert rig.c.plcs.compiled[3].program is None
    rig.ok("ENABLE PLCC 3")  # nothing left to run: no event
    assert len(rig.events("plc")) == 3
    assert [p["plc"] for p in rig.c.plcs.to_list(compiled=True)] == [5]


def test_pum_v_p245_delete_plcc_alone_erases_every_compiled_plc(rig):
    enter(rig, "M1=M1+1", n=0)
    enter(rig, "M2=M2+1", n=31)
    enter(rig, "M3=M3+1", n=2, compiled=False)
    rig.ok("DEL PLCC")
    assert rig.c.plcs.to_list(compiled=True) == []
    assert [p["plc"] for p in rig.c.plcs.to_list()] == [2]  # interpreted PLCs stay


def test_delete_plcc_while_another_port_has_it_open_is_err007_and_keeps_it(rig):
    enter(rig, "M1=M1+1", n=3)
    other = rig.c.open_port("tcp")
    rig.ok("OPEN PLCC 3", other)
    reply = rig.cmd("DELETE PLCC 3")
    assert reply.error == "ERR007"
    rig.ok("CLOSE", other)
    assert rig.c.plcs.compiled[3].program is not None


def test_list_plcc_is_err003_naming_that_the_card_keeps_no_source(rig):
    enter(rig, "M1=M1+1", n=3)
    reply = rig.cmd("LIST PLCC 3")
    assert reply.error == "ERR003"
    assert "no source" in reply.detail[1] and "column 6" in reply.detail[1]



def test_delete_plcc_of_the_plcc_open_for_entry_is_err007_naming_it(rig):
    """``DELETE PLCC n`` while PLCC n is open for entry on another port: ERR007, the message
    names the PLCC ``[INF]``, and the PLCC stays open and stored."""
    port = rig.c.open_port("editor")
    rig.ok("OPEN PLCC 3 CLEAR", port)
    rig.ok("P1=1", port)
    reply = rig.cmd("DELETE PLCC 3")
    assert reply.error == "ERR007"
    assert reply.detail == ("conflict", "PLCC 3 is open for entry")
    rig.ok("CLOSE", port)
    assert [ln for ln in rig.c.plcs.compiled[3].program.lines] == ["P1=1"]


def test_the_plcc_open_for_entry_is_listed_open_and_plc_n_is_not(rig):
    """``OPEN PLCC 2`` on a port: the compiled list shows PLCC 2 ``open``; the interpreted
    list has no PLC 2 (PLCC 2 is not PLC 2); closing a port that holds no PLC changes
    nothing, and closing the editing port drops the entry."""
    port = rig.c.open_port("editor")
    rig.ok("OPEN PLCC 2 CLEAR", port)
    rig.ok("P1=1", port)
    assert [(p["plc"], p["state"]) for p in rig.c.plcs.to_list(compiled=True)] == [(2, "open")]
    assert rig.c.plcs.to_list() == []
    rig.c.close_port(rig.c.open_port("idle"))  # no PLC open there
    assert [p["state"] for p in rig.c.plcs.to_list(compiled=True)] == ["open"]
    rig.c.close_port(port)
    assert rig.c.plcs.editing() is None and rig.c.buffer_holder is None
