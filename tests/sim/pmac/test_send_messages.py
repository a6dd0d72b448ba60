"""``SEND{port}"text"`` reaching the host (TSRM p470, p37, p67; PSRM p347; spec §12.2, §2).

A plain ``SEND`` (and ``SENDP``) goes to the active response port — the host port whose
command line ran last — framed like a reply's data line per I3, with ``<STX>`` first when
I64=1 and never the ACK of a host command. ``SENDS`` / ``SENDA`` / ``SENDR`` name ports the
simulated card does not have: no wire port gets them. Every line is in the REST terminal's
``output``; the store keeps the last ``MAX_LINES`` and counts the unread lines it drops.
"""

from __future__ import annotations

import pytest
from motionsim.sim.pmac.host.messages import MAX_LINES


def enter(rig, *lines: str, n: int = 1) -> None:
    rig.ok(f"OPEN PLC {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def test_psrm_p347_send_goes_to_the_active_response_port_only(rig):
    """Two host ports: the one that sent the last command line receives the line."""
    a, b = rig.c.open_port("tcp:a"), rig.c.open_port("tcp:b")
    rig.ok("I5=2", a)
    enter(rig, 'SEND"HOMED 3"', "DIS PLC 1")
    rig.ok("ENA PLC 1", b)
    rig.run_for(rig.period * 5)
    (k, _, f), = rig.events("plc_send")
    assert f == {"plc": 1, "port": "host", "text": "HOMED 3"}
    assert rig.c.host_messages(a) == []
    assert rig.c.host_messages(b) == [(b"HOMED 3\r", "HOMED 3")]
    assert rig.c.host_messages(b) == []  # delivered once


@pytest.mark.parametrize(("i3", "i64", "wire"), [
    (2, 0, b"DONE\r"), (2, 1, b"\x02DONE\r"), (0, 0, b"DONE\r"), (1, 0, b"\nDONE\r"),
    (3, 1, b"\n\x02DONE\r"),
])
def test_tsrm_p37_p67_program_line_framing_has_no_ack_and_stx_with_i64(rig, i3, i64, wire):
    port = rig.c.open_port("tcp")
    rig.ok(f"I5=2 I64={i64}", port)
    enter(rig, 'SENDP"DONE"', "DIS PLC 1")
    rig.ok("ENA PLC 1", port)
    rig.ok(f"I3={i3}", port)  # framed with the I3 and I64 of delivery
    rig.run_for(rig.period * 5)
    assert rig.c.host_messages(port) == [(wire, "DONE")]


@pytest.mark.parametrize("word", ["SENDS", "SENDA", "SENDR"])
def test_tsrm_p470_serial_and_dpram_sends_reach_no_wire_port_but_the_rest_output(rig, word):
    port = rig.c.open_port("tcp")
    rig.ok("I5=2", port)
    assert rig.c.unread_output("rest") == []
    enter(rig, f'{word}"FE WARNING"', "DIS PLC 1")
    rig.ok("ENA PLC 1", port)
    rig.run_for(rig.period * 5)
    assert rig.c.host_messages(port) == []
    assert rig.c.unread_output("rest") == ["FE WARNING"]
    assert rig.c.unread_output("rest") == []


def test_psrm_p347_unread_lines_beyond_the_store_are_dropped_oldest_first_and_counted(rig):
    """A PLC that sends every scan to a port that never reads: the store keeps the last
    MAX_LINES lines; each unread line dropped is a ``host_message_dropped`` event."""
    port = rig.c.open_port("tcp")
    rig.ok("I5=2", port)
    enter(rig, "P1=P1+1", "IF (P1!>300)", 'SEND"TICK"', "ELSE", "DIS PLC 1", "ENDIF")
    rig.ok("ENA PLC 1", port)
    rig.run_for(rig.period * 400)
    assert len(rig.events("plc_send")) == 300
    dropped = rig.events("host_message_dropped")
    assert [f["dropped"] for _, _, f in dropped] == list(range(1, 300 - MAX_LINES + 1))
    assert all(f["text"] == "TICK" and f["source"] == "plc1" for _, _, f in dropped)
    assert len(rig.c.host_messages(port)) == MAX_LINES


def test_psrm_p347_a_port_that_reads_loses_nothing(rig):
    port = rig.c.open_port("tcp")
    rig.ok("I5=2", port)
    enter(rig, "P1=P1+1", "IF (P1!>300)", 'SEND"TICK"', "ELSE", "DIS PLC 1", "ENDIF")
    rig.ok("ENA PLC 1", port)
    got = 0
    for _ in range(40):
        rig.run_for(rig.period * 10)
        got += len(rig.c.host_messages(port))
    assert got == 300
    assert rig.events("host_message_dropped") == []


def test_tsrm_p470_send_in_a_motion_program_reaches_the_host_when_its_line_is_calculated(rig):
    port = rig.c.open_port("tcp")
    rig.ok("#1->1000X", port)
    rig.ok("OPEN PROG 5 CLEAR", port)
    rig.ok('SEND"START"', port)
    rig.ok("LINEAR TA100 TS0 TM500 X10", port)
    rig.ok('SEND"DONE"', port)
    rig.ok("CLOSE", port)
    rig.ok("&1 B5 R", port)
    rig.run_for(2.0)
    sends = rig.events("program_send")
    assert [(f["cs"], f["line"], f["port"], f["text"]) for _, _, f in sends] == [
        (1, 1, "host", "START"), (1, 3, "host", "DONE")]
    assert [t for _, t in rig.c.host_messages(port)] == ["START", "DONE"]
    assert rig.c.unread_output("rest") == ["START", "DONE"]


def test_after_a_reset_send_lines_reach_the_port_again(rig):
    """A reset ($$$) empties the card's output; later lines still reach the port that read
    lines before it."""
    port = rig.c.open_port("tcp")
    rig.ok("I5=2", port)
    enter(rig, 'SEND"ONE"', "DIS PLC 1")
    rig.ok("ENA PLC 1", port)
    rig.run_for(rig.period * 5)
    assert [t for _, t in rig.c.host_messages(port)] == ["ONE"]
    rig.c.reset()
    rig.ok("I5=2", port)
    enter(rig, 'SEND"TWO"', "DIS PLC 1")
    rig.ok("ENA PLC 1", port)
    rig.run_for(rig.period * 5)
    assert [t for _, t in rig.c.host_messages(port)] == ["TWO"]


def test_pum_v_p238_a_compiled_plcs_send_is_marked_compiled(rig):
    port = rig.c.open_port("tcp")
    rig.ok("I5=2", port)
    rig.ok("OPEN PLCC 4 CLEAR", port)
    rig.ok('SEND"FROM PLCC"', port)
    rig.ok("DIS PLCC 4", port)
    rig.ok("CLOSE", port)
    rig.ok("ENA PLCC 4", port)
    rig.run_for(rig.period * 5)
    (_, _, f), = rig.events("plc_send")
    assert f == {"plc": 4, "port": "host", "text": "FROM PLCC", "compiled": True}
    assert [t for _, t in rig.c.host_messages(port)] == ["FROM PLCC"]


def test_every_event_type_the_simulator_emits_can_be_asked_for_before_it_happens():
    """A host subscribes to ``program_send`` / ``host_message_dropped`` before any SEND ran:
    each type any controller emits is a known type of its kind (API.md's event table), not
    a 422 / 4422 until the first one is logged. Read from the sources' ``emit("...")`` calls."""
    import re
    from pathlib import Path

    from motionsim.sim.pmac.controller import PmacController
    from motionsim.sim.trio.controller import TrioController

    root = Path(__file__).resolve().parents[3]
    emitted = {m for package in ("sim", "app", "api") for path in (root / package).rglob("*.py")
               for m in re.findall(r'emit\(\s*"([a-z_]+)"', path.read_text())}
    known = set(PmacController("k").known_event_types()) | set(
        TrioController("t").known_event_types())
    assert {"program_send", "host_message_dropped"} <= emitted
    assert emitted - known == set()
