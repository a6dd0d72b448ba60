"""A suite that shares one motionsim: a fresh controller per test, one service per session.

``motionsim_pmac`` / ``motionsim_trio`` are new controllers (virtual clock) on the session's
service, deleted after the test; each call takes the controller's id already. Run it with
``pytest examples/pytest`` — or against a server already running (``make run``, or
``docker compose up motionsim``) with ``pytest examples/pytest --motionsim-url
http://127.0.0.1:8000`` (or ``MOTIONSIM_URL=...``).
"""

from __future__ import annotations

from motionsim.app.pytest_plugin import assert_fed


def stream(pmac, lines: int, ahead: int = 10, reaction_s: float = 0.002) -> None:
    """A host that tops the rotary buffer up to ``ahead`` lines at each BREQ (100 ms moves)."""
    pmac.define_rotary(1, 600)
    sent = 0
    while sent < lines:
        have = pmac.coord(1)["rotary"]["lines_ahead"]
        batch = [f"TM100 TA10 TS0 X{(n % 2) * 10}" for n in range(sent, min(lines, sent + ahead
                                                                             - have))]
        pmac.load_lines(1, batch)
        sent += len(batch)
        if pmac.coord(1)["program"]["state"] == "idle":
            pmac.run(1)
        pmac.run_until("breq", 5.0, cs=1, level=True)
        pmac.advance(reaction_s)                       # the host's reaction time


def test_a_fresh_pmac_for_this_test(motionsim_pmac):
    assert motionsim_pmac.clock().t == 0.0             # nothing left over from another test
    motionsim_pmac.set_variable("I16", 5)
    motionsim_pmac.set_variable("I17", 10)
    stream(motionsim_pmac, lines=60)
    assert_fed(motionsim_pmac, cs=1, total_lines={1: 60})   # else: when, where and why


def test_another_fresh_pmac_sees_factory_defaults(motionsim_pmac):
    assert motionsim_pmac.get_variable("P1") == 0
    motionsim_pmac.set_variable("P1", 42)              # gone with this controller


def test_a_fresh_trio(motionsim_trio):
    motionsim_trio.move(0, "MOVE", [10.0])
    motionsim_trio.advance(0.5)
    assert [e["type"] for e in motionsim_trio.all_events(types=["move_start"])] == ["move_start"]
