"""The special lookahead's horizon (TSRM p181, p308; spec §9.2): with Isx13 > 0, ``DEFINE
LOOKAHEAD`` and Isx20 > 0 calculation stays Isx20 segments of Isx13 ms ahead — here counted in
move time ``[INF]`` — and without a lookahead buffer segmented LINEAR calculates one move
ahead, whatever Isx20 says."""

from __future__ import annotations


def _setup(rig, isx20: int, lookahead: bool = True) -> None:
    rig.ok("I5113=10")
    rig.ok(f"I5120={isx20}")
    if lookahead:
        rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    rig.rotary_setup()


def _calculated_at_first_rti(rig) -> int:
    ks = [k for k, _, _ in rig.events("line_calculated")]
    return sum(1 for k in ks if k == ks[0])


def _first_rti(rig, tm_ms: float, moves: int = 12) -> int:
    rig.c.load_lines(1, [f"LINEAR ABS TA10 TS0 TM{tm_ms}"] + [f"X{i}" for i in range(1, moves)])
    rig.ok("R")
    rig.run_for(0.01)
    return _calculated_at_first_rti(rig)


def test_tsrm_p181_the_horizon_is_isx20_times_isx13_ms_moves_just_short_of_it_get_one_more(rig):
    """Isx20 = 20 segments of 10 ms: 200 ms. Four TM49.96 moves cover 199.84 ms, short of
    it, so a fifth is calculated (the mode line and five moves at the first RTI)."""
    _setup(rig, 20)
    assert _first_rti(rig, 49.96) == 6


def test_tsrm_p181_moves_that_cover_the_horizon_exactly_stop_calculation_there(rig):
    """Four TM50 moves cover the 200 ms exactly: no fifth (the mode line and four moves)."""
    _setup(rig, 20)
    assert _first_rti(rig, 50) == 5


def test_without_define_lookahead_isx20_does_not_make_segmented_linear_look_further(rig):
    """No lookahead buffer: segmented LINEAR keeps one move beyond the executing one (from
    rest: the mode line and two moves), Isx20 = 20 notwithstanding."""
    _setup(rig, 20, lookahead=False)
    assert _first_rti(rig, 49.96) == 3


def test_tsrm_p181_a_one_segment_lookahead_of_200_ms_segments(rig):
    """Isx20 = 1 segment of Isx13 = 200 ms is a 200 ms horizon too: four TM49.96 moves are
    short of it, a fifth is calculated."""
    rig.ok("I5113=200")
    rig.ok("I5120=1")
    rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    rig.rotary_setup()
    assert _first_rti(rig, 49.96) == 6


def test_tsrm_p181_one_ms_segments_look_ahead_too(rig):
    """Isx13 = 1 ms, Isx20 = 200: a 200 ms horizon, the same five moves calculated."""
    rig.ok("I5113=1")
    rig.ok("I5120=200")
    rig.ok("&1 DEFINE LOOKAHEAD 250,10")
    rig.rotary_setup()
    assert _first_rti(rig, 49.96) == 6
