"""MOVEMODIFY and CONNECT at sequencing: which buffered move they change, and when they wait.

MOVEMODIFY(p) (spec §10.2, MC4 help text CNB-MM): changes the end of the axis' last buffered
single-axis linear move to the absolute position ``p``; with nothing such to modify it loads
as a move of its own (MTYPE 5); a new end that needs a change of direction cancels the MTYPE
move at DECEL first. CONNECT (spec §10.3, TJ2P-71): a new CONNECT on an axis CONNECTed to the
same driving axis changes the ratio at once; one naming another driving axis, or any other
move, waits behind the first until that is CANCELled. Axis settings as in conftest (SPEED
1000, ACCEL = DECEL = 100 000, servo period 1 ms): MOVE(100) from rest at period 1 is at 45
units at period 51 (5 ramping up, 40 at speed).
"""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, make, moves, next_period, run_to


def _starts(c, axis: int) -> list[tuple[int, int]]:
    return [(cycle(c, t), f["mtype"]) for t, f in fields(c, "move_start", axis=axis)]


def _modified(c) -> list[tuple[int, float]]:
    return [(cycle(c, t), f["end"]) for t, f in fields(c, "move_modify")]


# -- MOVEMODIFY: what it may change ----------------------------------------------------------


def test_movemodify_of_a_group_move_loads_as_a_move_of_its_own(trio):
    """The move in MTYPE drives axes 0 and 1: not a single-axis move, so MOVEMODIFY(50) AXIS(0)
    waits in NTYPE and runs as MTYPE 5 after the group move, which keeps its end."""
    trio.move(0, "MOVE", [100, 100])
    run_to(trio, 0.0505)
    trio.move(0, "MOVEMODIFY", [50])
    run_to(trio, 0.0515)
    assert (trio.axis(0)["mtype"], trio.axis(0)["ntype"]) == (1, 5)
    run_to(trio, 1.0)
    (group_end, _), *_ = fields(trio, "move_end", axis=0)
    assert _starts(trio, 0) == [(1, 1), (cycle(trio, group_end) + 1, 5)]
    assert _modified(trio) == []
    assert (trio.axis(0)["dpos"], trio.axis(1)["dpos"]) == pytest.approx((50.0, 100.0))


def test_movemodify_during_forward_loads_as_a_move_of_its_own(trio):
    """FORWARD is not a linear move with an end: MOVEMODIFY waits in NTYPE behind it and the
    FORWARD runs on."""
    trio.terminal("FORWARD AXIS(0)")
    run_to(trio, 0.0505)
    trio.move(0, "MOVEMODIFY", [50])
    run_to(trio, 0.2)
    a = trio.axis(0)
    assert (a["mtype"], a["ntype"]) == (10, 5) and a["dpos"] > 150.0
    assert _modified(trio) == []


def test_movesp_after_a_move_is_a_move_of_its_own(trio):
    """Only MOVEMODIFY modifies: MOVESP(10) behind MOVEABS(100) is buffered and runs after it."""
    trio.move(0, "MOVEABS", [100])
    run_to(trio, 0.0505)
    trio.move(0, "MOVESP", [10])
    run_to(trio, 1.0)
    assert [m for _, m in _starts(trio, 0)] == [2, 6]
    assert _modified(trio) == [] and trio.axis(0)["dpos"] == pytest.approx(110.0)


def test_movemodify_of_the_ntype_move_leaves_the_process_buffer_at_once(trio):
    """MOVEMODIFY rewriting the move waiting in NTYPE is consumed at the servo interrupt that
    takes it from the process buffer: PMOVE is 0 again one period later (M206-320), and the
    change is reported like that of an executing move (API.md ``move_modify``: the end of a
    buffered or executing move)."""
    moves(trio, 0, 2, [10])
    trio.move(0, "MOVEMODIFY", [50])  # at 2.5 ms
    assert trio.pmove(0) == 1
    next_period(trio)
    assert (trio.pmove(0), trio.axis(0)["ntype"]) == (0, 1)
    assert [cycle(trio, t) for t, _ in fields(trio, "process_buffer", mtype=0)] == [1, 2, 3]
    assert [(cycle(trio, t), f) for t, f in fields(trio, "move_modify")] == [
        (3, {"axis": 0, "mtype": 1, "end": 50.0})
    ]


# -- MOVEMODIFY: ahead or behind -------------------------------------------------------------


@pytest.mark.parametrize(
    ("end", "cancels"), [(44.5, True), (-60.0, False), (-30.0, True)], ids=["half-unit-back",
                                                                          "minus-ahead",
                                                                          "minus-behind"],
)
def test_movemodify_cancels_only_when_the_new_end_needs_a_reversal(end, cancels):
    """At period 51 MOVE(100) is at 45 (MOVE(-100) at -45): an end half a unit behind needs a
    reversal (CANCEL at DECEL, then MTYPE 5 back to the end); on a move in the negative
    direction -60 lies ahead (the same move now ends there) and -30 behind (UNITS 10: the
    half unit is 5 whole edges)."""
    c = make(units=10)
    sign = 1.0 if end > 0 else -1.0
    c.move(0, "MOVE", [100.0 * sign])
    run_to(c, 0.0505)
    c.move(0, "MOVEMODIFY", [end])
    run_to(c, 1.0)
    if cancels:
        assert [m for _, m in _starts(c, 0)] == [1, 5] and _modified(c) == []
    else:
        assert _starts(c, 0) == [(1, 1)] and _modified(c) == [(51, end)]
    assert c.axis(0)["dpos"] == pytest.approx(end)


def _position_at(k: int, hold: bool, speed: float = 1000.0) -> float:
    """DPOS at servo period ``k`` of MOVE(100) issued at 0 (SPEED 0 written at 50.5 ms when
    ``hold``): read on a twin controller, the run being deterministic."""
    c = _modify_setup(hold, speed)
    run_to(c, c.clock.t(k))
    return c.axis(0)["dpos"]


def _modify_setup(hold: bool, speed: float = 1000.0):
    c = make(speed=speed, units=1e6)
    c.move(0, "MOVE", [100])
    run_to(c, 0.0505)
    if hold:
        c.set_axis(0, speed=0)
    return c


@pytest.mark.parametrize("speed", [1000.0, 0.5])
def test_movemodify_to_where_a_moving_axis_is_needs_a_reversal(speed):
    """The axis passes its position at period 51 moving (at 1000 or at 0.5 units/s): it cannot
    stop there without turning back, so MOVEMODIFY to that position cancels the move and
    runs back as MTYPE 5."""
    here = _position_at(51, hold=False, speed=speed)
    c = _modify_setup(hold=False, speed=speed)
    c.move(0, "MOVEMODIFY", [here])
    run_to(c, 1.0)
    assert [m for _, m in _starts(c, 0)] == [1, 5] and _modified(c) == []
    assert c.axis(0)["dpos"] == pytest.approx(here, abs=1e-6)  # on the nearest whole edge


@pytest.mark.parametrize("ahead", [0.0, 0.5])
def test_movemodify_of_a_held_move_at_or_just_ahead_of_the_axis_modifies_it(ahead):
    """Held by SPEED 0 (at rest, still MTYPE 1), the move is modified to end where the axis is
    or half a unit ahead: no reversal, so no CANCEL and no MTYPE 5 (spec §10.2); the
    MOVEMODIFY leaves the process buffer in the period it is applied."""
    here = _position_at(100, hold=True)
    c = _modify_setup(hold=True)
    run_to(c, 0.0995)
    c.move(0, "MOVEMODIFY", [here + ahead])
    run_to(c, 0.2)
    assert _starts(c, 0) == [(1, 1)] and _modified(c) == [(100, here + ahead)]
    pb = [(round(t * 1e4), f["mtype"]) for t, f in fields(c, "process_buffer")]
    assert pb[-2:] == [(995, 5), (1000, 0)]


def test_a_movemodify_consumed_does_not_hold_up_another_process(trio):
    """Sequencing takes every process buffer in the same interrupt: process 1's MOVEMODIFY is
    applied at 51 and process 2's move on axis 1 starts at 51 too."""
    trio.move(0, "MOVEABS", [100])
    run_to(trio, 0.0505)
    trio.move(0, "MOVEMODIFY", [200], process=1)
    trio.move(1, "MOVE", [10], process=2)
    run_to(trio, 0.06)
    assert _modified(trio) == [(51, 200.0)]
    assert _starts(trio, 1) == [(51, 1)]


# -- CONNECT ---------------------------------------------------------------------------------


def _connect_then_forward(c, line: str = "CONNECT(1,0) AXIS(1)") -> None:
    c.terminal(line)
    next_period(c)
    c.terminal("FORWARD AXIS(0)")
    next_period(c)


def test_a_new_connect_on_the_same_driving_axis_leaves_nothing_buffered(trio):
    """The second CONNECT only changes the ratio (TJ2P-71): it leaves the process buffer at the
    next interrupt and is never buffered, so a CANCEL then leaves the axis idle."""
    _connect_then_forward(trio)
    run_to(trio, 0.1005)
    trio.terminal("CONNECT(3,0) AXIS(1)")
    run_to(trio, 0.1015)
    assert (trio.axis(1)["mtype"], trio.axis(1)["ntype"], trio.pmove(0)) == (21, 0, 0)
    trio.terminal("CANCEL AXIS(1)")
    run_to(trio, 0.2)
    assert trio.axis(1)["mtype"] == 0
    assert _starts(trio, 1) == [(1, 21)]


def test_a_new_connect_waits_behind_a_move_in_ntype(trio):
    """With a move already in NTYPE of the CONNECTed axis, a new CONNECT cannot overtake it:
    it stays in the process buffer and the ratio stays 1."""
    trio.terminal("CONNECT(1,0) AXIS(1)")
    next_period(trio)
    trio.terminal("MOVE(10) AXIS(1)")
    next_period(trio)
    trio.terminal("FORWARD AXIS(0)")
    next_period(trio)
    trio.terminal("CONNECT(3,0) AXIS(1)")
    run_to(trio, 0.1005)
    assert (trio.axis(1)["ntype"], trio.pmove(0)) == (1, 1)
    assert trio.axis(1)["dpos"] == pytest.approx(trio.axis(0)["dpos"])


def test_a_connect_naming_another_driving_axis_waits_until_the_first_is_cancelled(trio):
    """TJ2P-71: a CONNECT naming a different driving axis waits (in NTYPE) until the first is
    CANCELled; then it follows its own driving axis at its own ratio."""
    _connect_then_forward(trio, "CONNECT(1,0) AXIS(2)")
    trio.terminal("CONNECT(2,1) AXIS(2)")
    next_period(trio)
    trio.terminal("FORWARD AXIS(1)")
    run_to(trio, 0.1005)
    assert (trio.axis(2)["mtype"], trio.axis(2)["ntype"]) == (21, 21)
    assert trio.axis(2)["dpos"] == pytest.approx(trio.axis(0)["dpos"])
    trio.terminal("CANCEL AXIS(2)")
    run_to(trio, 0.1505)
    a1, a2 = trio.axis(1)["dpos"], trio.axis(2)["dpos"]
    run_to(trio, 0.2505)
    assert trio.axis(2)["dpos"] - a2 == pytest.approx(2.0 * (trio.axis(1)["dpos"] - a1))
    assert [m for _, m in _starts(trio, 2)] == [21, 21]


@pytest.mark.parametrize(
    ("line", "code"),
    [("CAMBOX(10,12,1,200,0) AXIS(1)", 20), ("MOVELINK(100,200,50,50,0) AXIS(1)", 22)],
)
def test_a_connect_on_an_axis_running_a_linked_move_waits_for_its_end(trio, line, code):
    """Only a CONNECT changes a CONNECT's ratio: behind a CAMBOX or MOVELINK linked to the same
    axis the CONNECT waits in NTYPE and loads the period after that move ends."""
    trio.terminal("TABLE(10,0,50,100)")
    trio.terminal(line)
    next_period(trio)
    trio.terminal("CONNECT(2,0) AXIS(1)")
    next_period(trio)
    assert (trio.axis(1)["mtype"], trio.axis(1)["ntype"]) == (code, 21)
    trio.terminal("MOVE(400) AXIS(0)")
    run_to(trio, 1.0)
    ((end, _),) = fields(trio, "move_end", axis=1)
    assert _starts(trio, 1) == [(1, code), (cycle(trio, end) + 1, 21)]


@pytest.mark.parametrize(
    ("line", "code"),
    [("MOVELINK(100,200,50,50,0) AXIS(1)", 22), ("CAMBOX(10,12,1,200,0) AXIS(1)", 20)],
)
def test_a_linked_move_on_a_connected_axis_waits_for_the_connect(trio, line, code):
    """CONNECT never ends by itself: a MOVELINK or CAMBOX on the same driving axis waits in
    NTYPE and the axis keeps following at the CONNECT's ratio."""
    trio.terminal("TABLE(10,0,50,100)")
    trio.terminal("CONNECT(1,0) AXIS(1)")
    next_period(trio)
    trio.terminal(line)
    next_period(trio)
    trio.terminal("FORWARD AXIS(0)")
    run_to(trio, 0.1005)
    assert (trio.axis(1)["mtype"], trio.axis(1)["ntype"]) == (21, code)
    assert trio.axis(1)["dpos"] == pytest.approx(trio.axis(0)["dpos"])


def test_defpos_of_the_driving_axis_does_not_step_the_connected_axis(trio):
    """DEFPOS redefines where the driving axis is, it does not move it (TRM MC216 p. 220):
    the CONNECTed axis follows the motion, so it runs on without a step."""
    _connect_then_forward(trio)
    run_to(trio, 0.1005)
    a0, a1 = trio.axis(0)["dpos"], trio.axis(1)["dpos"]
    trio.terminal("DEFPOS(0) AXIS(0)")
    run_to(trio, 0.1105)
    assert trio.axis(0)["dpos"] < a0 / 2  # the driving axis was declared 0 at period 101
    assert trio.axis(1)["dpos"] == pytest.approx(a1 + 10.0)
