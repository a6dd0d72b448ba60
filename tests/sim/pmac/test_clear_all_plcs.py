"""``CLEAR ALL PLCS``: every PLC program buffer erased (sim/pmac/tasks/plc.py ``clear_all``)."""

from __future__ import annotations


def test_clear_all_plcs_erases_every_plc_buffer_and_stops_the_running_ones(rig):
    rig.c.plcs.load(1, "P1=P1+1")
    rig.c.plcs.load(7, "P2=1")
    rig.ok("ENABLE PLC 1")
    since = rig.c.log.last_seq
    rig.ok("CLEAR ALL PLCS")
    assert [e for _, _, e in rig.events("plc", since=since)] == [
        {"plc": 1, "state": "disabled"}]
    for n in (1, 7):
        assert rig.cmd(f"LIST PLC {n}").error is not None  # nothing left to list
    rig.ok("ENABLE PLC 1")  # an empty PLC cannot be enabled
    assert not rig.c.plcs.plc(1).enabled


def test_clear_all_plcs_with_a_plc_open_for_entry_is_err007_and_changes_nothing(rig):
    rig.c.plcs.load(2, "P1=1")
    port = rig.c.open_port("host")
    rig.ok("OPEN PLC 3", port)
    reply = rig.cmd("CLEAR ALL PLCS")
    assert reply.error is not None and "ERR007" in str(reply.error)
    assert rig.ok("LIST PLC 2") == "P1=1\rRET"


def test_clear_all_alone_is_valid_but_not_simulated(rig):
    reply = rig.cmd("CLEAR ALL")
    assert reply.error is not None and "ERR003" in str(reply.error)
    assert reply.detail is not None and reply.detail[0] == "not_simulated"
