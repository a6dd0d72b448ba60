"""The card's store of program messages (SEND, TSRM p470; sim/pmac/host/messages.py) keeps
the last MAX_LINES (256) lines: an older unread line sent to a host port is dropped with a
``host_message_dropped`` event naming its port letter ("host" for a plain SEND); lines for
ports the simulated card does not have are dropped silently."""

from __future__ import annotations

from motionsim.sim.pmac.host.messages import MAX_LINES


def test_lines_beyond_the_store_drop_the_oldest_naming_the_port(rig):
    port = rig.c.open_port("host")
    rig.ok("P1", port)  # the active response port (PSRM p347)
    store = rig.c.messages
    assert MAX_LINES == 256
    store.send("plc1", "", "first")
    store.send("plc1", "P", "second")
    for n in range(MAX_LINES - 1):
        store.send("plc1", "", f"line {n}")
    assert len(store.lines) == MAX_LINES
    dropped = [(f["port"], f["text"]) for _, _, f in rig.events("host_message_dropped")]
    assert dropped == [("host", "first")]
    store.send("plc1", "", "one more")
    dropped = [(f["port"], f["text"]) for _, _, f in rig.events("host_message_dropped")]
    assert dropped == [("host", "first"), ("P", "second")]


def test_lines_for_a_port_the_card_lacks_drop_silently(rig):
    store = rig.c.messages
    for n in range(MAX_LINES + 10):
        store.send("plc1", "S", f"serial {n}")
    assert len(store.lines) == MAX_LINES
    assert store.lines[0].text == "serial 10"
    assert rig.events("host_message_dropped") == []
