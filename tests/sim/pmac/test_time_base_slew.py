"""Time-base slew (TSRM p191; PSRM Ix95; spec §4.3, §9.7): the actual ``%`` moves towards the
commanded one by Isx94 (``%n``) or Isx95 (``H``, and ``R`` after it) 2**-23 ms per servo cycle,
one step per servo cycle starting with the command's own cycle. Moves follow the actual time
base; the default 1644 takes ≈ 1 s from 0 to 100 %."""

from __future__ import annotations

import math

import pytest

LINE = "TM4000 TA100 TS0 X4000"  # 1 unit per ms between the ramps


def step_pct(rig, rate: float = 1644) -> float:
    """% per servo cycle: 100 % is one servo period (in 2**-23 ms) per cycle."""
    return 100.0 * rate / (rig.period * 1000.0 * 2**23)


def start_move(rig) -> tuple[int, float]:
    """Run :data:`LINE` from rest; its move_start cycle and its unscaled end instant."""
    rig.rotary_setup()
    rig.c.load_lines(1, [LINE])
    rig.ok("R")
    rig.run_for(0.01)
    (k0,) = [k for k, _, f in rig.events("move_start")]
    return k0, k0 * rig.period + 4.1  # TM + Ta


def move_end_cycle(rig) -> int:
    rig.run_until_idle()
    (k,) = [k for k, _, _ in rig.events("move_end")]
    return k


def test_default_rate_is_one_second_from_100_to_0(rig):
    s = step_pct(rig)
    n = math.ceil(100 / s)
    assert n * rig.period == pytest.approx(1.0, abs=0.002)  # the TSRM p191 note
    cs = rig.c.coord_system(1)
    k_c = rig.cyc(rig.cmd("%0").t_done)
    assert cs.feed_override == pytest.approx(100 - s)  # first step in the command's cycle
    rig.c.env.run(until=(k_c + n - 2) * rig.period + rig.period / 2)
    assert cs.feed_override == pytest.approx(100 - (n - 1) * s)
    assert cs.commanded_override == 0
    rig.c.env.run(until=(k_c + n) * rig.period)
    assert rig.ok("%") == "0"


def test_percent_50_on_a_running_move_follows_the_ramp(rig):
    k0, t_end = start_move(rig)
    rig.run_for(1.0)
    k_c = rig.cyc(rig.cmd("%50").t_done)
    s = step_pct(rig)
    m = math.ceil(50 / s)  # steps 100 - s, 100 - 2s, ..., then 50 from cycle k_c + m - 1
    consumed = rig.period * sum(1 - i * s / 100 for i in range(1, m))
    remaining = t_end - k_c * rig.period - consumed
    expected = (k_c + m - 1) * rig.period + remaining / 0.5
    assert move_end_cycle(rig) == math.ceil(expected / rig.period - 1e-6)
    assert rig.c.positions(1)["X"] == pytest.approx(4000.0)


def test_h_ramps_down_at_isx95_and_r_ramps_back(rig):
    rig.ok("I5195=3288")  # twice the default: 0.5 s ramps (Isx94 stays at 1644)
    k0, t_end = start_move(rig)
    rig.run_for(1.0)
    k_h = rig.cyc(rig.cmd("H").t_done)
    x_h = rig.c.positions(1)["X"]
    s = step_pct(rig, 3288)
    n = math.ceil(100 / s)
    down = rig.period * sum(1 - i * s / 100 for i in range(1, n))  # program ms while stopping
    rig.c.env.run(until=(k_h + n - 1) * rig.period)
    assert rig.c.positions(1)["X"] == pytest.approx(x_h + 1000 * down, abs=1e-6)
    rig.run_for(1.0)
    assert rig.c.positions(1)["X"] == pytest.approx(x_h + 1000 * down, abs=1e-6)
    k_r = rig.cyc(rig.cmd("R").t_done)
    up = rig.period * sum(i * s / 100 for i in range(1, n))
    rig.c.env.run(until=(k_r + n - 1) * rig.period)
    assert rig.c.positions(1)["X"] == pytest.approx(x_h + 1000 * (down + up), abs=1e-6)
    # The two ramps are mirror images: the move ends exactly the time held later.
    assert move_end_cycle(rig) == math.ceil(t_end / rig.period - 1e-6) + (k_r - k_h)
    assert rig.ok("%") == "100"


def test_isx94_zero_never_moves_the_time_base(rig):
    """[INF] The manual gives 0 no special meaning: a slew of 0 per cycle never arrives."""
    rig.ok("I5194=0")
    k0, t_end = start_move(rig)
    rig.run_for(1.0)
    rig.ok("%50")
    assert move_end_cycle(rig) == math.ceil(t_end / rig.period - 1e-6)
    assert rig.ok("%") == "100"


def test_isx94_maximum_changes_within_the_commands_cycle(rig):
    rig.ok("I5194=8388607")
    k0, t_end = start_move(rig)
    rig.run_for(1.0)
    k_c = rig.cyc(rig.cmd("%50").t_done)
    assert rig.ok("%") == "50"
    expected = k_c * rig.period + 2 * (t_end - k_c * rig.period)
    assert move_end_cycle(rig) == math.ceil(expected / rig.period - 1e-6)


def test_dwell_stays_real_time_during_a_slew(rig):
    """TSRM p429: DWELL is not scaled by the time base, slewing or not."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["DWELL1000"])
    rig.ok("R")
    rig.run_for(0.01)
    rig.ok("%10")
    rig.run_until_idle()
    (start,), (end,) = [k for k, _, _ in rig.events("move_start")], [
        k for k, _, _ in rig.events("move_end")
    ]
    assert end - start == math.ceil(rig.ms_cycles(1000) - 1e-6)


def real_time_of(rig, tau: float, k_c: int, target: float, s: float) -> float:
    """The real instant program time ``tau`` is reached when a slew from 100 % to ``target``
    (steps of ``s`` %) starts at cycle ``k_c`` (program time = real time before it)."""
    p = rig.period
    acc = k_c * p
    if tau <= acc:
        return tau
    j = 0
    while True:
        j += 1
        pct = max(target, 100 - j * s)
        if acc + p * pct / 100 >= tau:
            return (k_c + j - 1) * p + (tau - acc) / (pct / 100)
        acc += p * pct / 100


def test_percent_50_on_a_blended_sequence_moves_every_hand_off(rig):
    """Six blended 500 ms moves; ``%50`` in the second: each hand-off (blend start) happens
    when the slewing time base reaches its program instant."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM500 TA100 TS0 X500"] + [f"X{500 * i}" for i in range(2, 7)])
    rig.ok("R")
    rig.run_for(0.7)
    k0 = min(k for k, _, f in rig.events("move_start"))
    k_c = rig.cyc(rig.cmd("%50").t_done)
    rig.run_until_idle()
    s = step_pct(rig)
    starts = {f["n"]: k for k, _, f in rig.events("move_start")}
    t0 = k0 * rig.period
    for n in range(3, 7):  # moves 1 and 2 started before the change
        t = real_time_of(rig, t0 + (n - 1) * 0.5, k_c, 50.0, s)
        assert starts[n] == math.ceil(t / rig.period - 1e-6), n
    (k_end,) = [k for k, _, f in rig.events("move_end") if f["n"] == 6]
    t = real_time_of(rig, t0 + 6 * 0.5 + 0.1, k_c, 50.0, s)
    assert k_end == math.ceil(t / rig.period - 1e-6)
    assert rig.c.positions(1)["X"] == pytest.approx(3000.0)


def test_a_new_isx94_acts_on_a_slew_in_progress(rig):
    """[INF] The rate is read every servo cycle: Isx94 = 0 half-way ends the slew; the time
    base stays there until the next ``%`` command."""
    cs = rig.c.coord_system(1)
    rig.ok("%0")
    rig.run_for(0.5)
    rig.ok("I5194=0")
    stuck = cs.feed_override
    assert 30 < stuck < 70
    rig.run_for(1.0)
    assert cs.feed_override == stuck
    rig.ok("I5194=1644")
    assert cs.feed_override == stuck  # the write alone does not re-arm the slew
    rig.ok("%0")
    rig.run_for(1.0)
    assert cs.feed_override == 0
