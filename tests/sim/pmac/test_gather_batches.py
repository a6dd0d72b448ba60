"""Batched data gathering is the per-cycle gathering, sample for sample (issue 34 speed).

:mod:`motionsim.sim.pmac.tasks.gather` records samples in batches, just before each event,
computing motor registers from the trajectory (:mod:`motionsim.sim.pmac.tasks.gather_readers`);
the reference is the per-cycle sampler (``Gather.per_cycle``: one wake-up per sample, every
source read through card memory, :mod:`motionsim.sim.pmac.card.registers`). Each scenario
runs on two cards, one of each, and asserts the same samples (servo cycles and raw words),
the same ``LIST GATHER`` answer and the same event log. The rules sampled are those of
TSRM p170-171 (I5000-I5051) and p307 / p315 (DEFINE / DELETE GATHER).
"""

from __future__ import annotations

from collections.abc import Callable

import pytest

from .conftest import Rig

MOTOR = 0x80  # motor register step (registers.py)


def pos(motor: int, actual: bool = False) -> str:
    return f"${0x800088 + MOTOR * (motor - 1) + (3 if actual else 0):06X}"


def fe(motor: int) -> str:
    return f"${0x800091 + MOTOR * (motor - 1):06X}"


def vel(motor: int) -> str:
    return f"${0x40009D + MOTOR * (motor - 1):06X}"


SERVO_COUNTER = "$400000"
MOTOR_STATUS_1 = "$4000B0"  # X:$0000B0, motor 1 status word 1 (per-sample reads)
CS_STATUS_1 = "$402040"  # X:$002040, CS 1 status word 1
PLAIN_Y = "$001000"  # Y:$001000, plain memory (an M-variable's target below)


def both(scenario: Callable[[Rig], None]) -> tuple[Rig, Rig]:
    """``scenario`` on a per-cycle card and on a batched one; asserts they recorded the
    same and logged the same."""
    rigs = []
    for per_cycle in (True, False):
        rig = Rig()
        rig.c.gather.per_cycle = per_cycle
        scenario(rig)
        rigs.append(rig)
    ref, fast = rigs
    r, f = ref.c.gather.recording(), fast.c.gather.recording()
    assert len(r.cycles) > 0
    assert f.cycles == r.cycles
    assert f.values == r.values
    assert (f.running, f.wrapped, f.capacity) == (r.running, r.wrapped, r.capacity)
    assert fast.ok("LIST GATHER") == ref.ok("LIST GATHER")
    log = [(e.t, e.type, dict(e.fields)) for e in ref.c.log.read(0, None).events]
    assert [(e.t, e.type, dict(e.fields)) for e in fast.c.log.read(0, None).events] == log
    return ref, fast


def setup(rig: Rig, sources: list[str], period: int = 1, wrap: int = 0,
          words: int | None = None) -> None:
    for n, spec in enumerate(sources, 1):
        rig.ok(f"I{5000 + n}={spec}")
    mask = (1 << len(sources)) - 1
    rig.ok(f"I5050=${mask:X} I5051=0 I5049={period} I5000={wrap}")
    rig.ok("DEFINE GATHER" if words is None else f"DEFINE GATHER {words}")


def axes(rig: Rig) -> None:
    """Motors 1-4 on X, Y, Z, A of CS 1 and its rotary buffer (before the gather buffer:
    DEFINE ROT needs none, TUM p337)."""
    rig.ok("&1 #1->X #2->Y #3->Z #4->A")
    rig.c.define_rotary(1, 3000)


def stream(rig: Rig, lines: list[str]) -> None:
    rig.c.load_lines(1, lines)
    rig.c.run(1)


POSITIONS = [pos(m, a) for m in range(1, 5) for a in (False, True)]


def test_a_blended_stream_wrapping_the_buffer():
    """The bench's case: 8 position registers every cycle of a blended LINEAR stream,
    I5000 = 1 wrapping a small buffer (TSRM p170)."""
    def scenario(rig: Rig) -> None:
        axes(rig)
        setup(rig, POSITIONS, wrap=1, words=6000)
        rig.ok("GATHER")
        stream(rig, ["TA1 TS0 TM5"] + [f"X{i} Y{i / 2} Z{-i} A{i % 7}" for i in range(250)]
               + ["TA20 TS5 TM40 X3.3 Y-7.1", "DWELL 30", "X0 Y0 Z0 A0"])
        rig.run_for(1.2)
    ref, _ = both(scenario)
    assert ref.c.gather.recording().wrapped


def test_velocity_following_error_and_servo_counter_through_moves_and_jogs():
    """Velocity (X:$9D), following error (D:$91) and the servo counter (X:$000000) with a
    program of LINEAR, RAPID and CIRCLE-free moves, a jog of a motor outside the CS and a
    time-base change mid-move (I5049 = 2)."""
    def scenario(rig: Rig) -> None:
        axes(rig)
        setup(rig, [vel(1), fe(1), SERVO_COUNTER, pos(1), pos(5), vel(5), pos(2, True)],
              period=2)
        rig.ok("GATHER")
        stream(rig, ["TA30 TS10 F100", "X10 Y5", "RAPID X-3", "LINEAR X7 Y-2", "X0 Y0"])
        rig.ok("#5J=2500")
        rig.run_for(0.15)
        rig.ok("&1%40")
        rig.run_for(0.3)
        rig.ok("&1%100")
        rig.run_for(0.6)
        rig.ok("ENDGATHER")
    both(scenario)


def test_words_a_plc_and_the_host_change_mid_gather():
    """A plain-memory word an M-variable points at, incremented by a background PLC on every
    scan and written by the host with ``W`` and through the M-variable, mid gather; with
    the motor and CS status words (read at every sample) and I5000 = 0 stopping when full."""
    def scenario(rig: Rig) -> None:
        axes(rig)
        setup(rig, [PLAIN_Y, MOTOR_STATUS_1, CS_STATUS_1, pos(1)], words=300)
        rig.ok("M1->Y:$1000,0,24")
        rig.ok("OPEN PLC 1 CLEAR")
        rig.ok("M1=M1+1")
        rig.ok("CLOSE")
        rig.ok("I5=3")
        rig.ok("GATHER")
        rig.ok("ENABLE PLC 1")
        stream(rig, ["TA10 TS0 TM20", "X2 Y1", "X-1 Y3", "X0 Y0"])
        rig.run_for(0.05)
        rig.ok("WY:$1000,$123456")
        rig.run_for(0.05)
        rig.ok("M1=7")
        rig.run_for(0.4)
    ref, _ = both(scenario)
    assert not ref.c.gather.running  # filled up


def test_host_calls_between_runs_and_a_single_shot():
    """Writes from outside the simulation between two runs (an I-variable the position
    register is scaled by, a motor position set through Mxx62) are seen from the next
    sample on; then I5049 = 0 takes one sample per GATHER (TSRM p171)."""
    def scenario(rig: Rig) -> None:
        rig.ok("WY:$1000,1")
        setup(rig, [pos(1), pos(1, True), PLAIN_Y])
        rig.ok("GATHER")
        rig.run_for(0.01)
        rig.c.set_variable("I108", 48)
        rig.c.vars.mvars.store_word("Y", 0x1000, 99)
        rig.run_for(7.3 * rig.period)
        rig.c.set_motor_position(1, 1234.5)
        rig.run_for(0.01)
        rig.ok("ENDGATHER")
        rig.ok("I5049=0")
        rig.ok("GATHER")
        rig.run_for(0.01)
    both(scenario)


@pytest.mark.parametrize("period", [1, 3])
def test_a_run_that_stops_exactly_on_a_sample_instant(period):
    """``env.run(until=t)`` with ``t`` a sample's own servo instant leaves that sample for
    the next run in both (the run stops before the events of its last instant); a host
    write in between is in it."""
    def scenario(rig: Rig) -> None:
        rig.ok("WY:$1000,1")
        setup(rig, [PLAIN_Y], period=period)
        rig.ok("GATHER")
        clock = rig.c.scheduler.clock
        k = clock.after(rig.c.env.now) + 6
        rig.c.env.run(until=clock.t(k))
        rig.c.vars.mvars.store_word("Y", 0x1000, 5)
        rig.run_for(0.005)
    both(scenario)


def test_the_stream_takes_the_array_path(monkeypatch):
    """The blended stream's batches are computed as arrays (so the scenario above pins that
    path, not only the sample-by-sample one)."""
    from motionsim.sim.pmac.tasks import gather_readers

    calls = []
    real = gather_readers.Plan._vector

    def spy(self, items):
        calls.append(len(items))
        return real(self, items)

    monkeypatch.setattr(gather_readers.Plan, "_vector", spy)
    test_a_blended_stream_wrapping_the_buffer()
    assert calls and sum(calls) > 10


def test_round_to_a_tenth_on_arrays_is_pythons_round():
    """``_round1`` against ``round(x, 1)`` on halves that binary cannot hold exactly, their
    neighbours, negative values and large counts."""
    import numpy as np
    from motionsim.sim.pmac.tasks.gather_readers import _round1

    rng = np.random.default_rng(34)
    base = [0.05, 0.15, 0.25, 0.35, 2.675, -0.05, -0.15, -2.25, 1e13 + 0.05, 0.0, -0.0,
            123456.75, 7.949999999999999, 7.95, 1e15]
    xs = base + [np.nextafter(x, np.inf) for x in base] + [np.nextafter(x, -np.inf)
                                                            for x in base]
    xs += list(rng.uniform(-1e7, 1e7, 2000)) + list(np.round(rng.uniform(-1e4, 1e4, 2000), 2))
    arr = np.array(xs, dtype=np.float64)
    assert _round1(arr).tolist() == [round(float(x), 1) for x in arr]


def test_linear_positions_on_arrays_are_position_at():
    """``_linear_positions`` against :func:`position_at` in the ramp in, the steady part and
    the ramp out, with and without an end, and zero-length ramps."""
    import numpy as np
    from motionsim.sim.pmac.buffers.motion import position_at
    from motionsim.sim.pmac.tasks.gather_readers import _linear_positions

    rng = np.random.default_rng(7)
    rows = []
    for _ in range(3000):
        b0 = float(rng.uniform(0, 1))
        ta_in = float(rng.choice([0.0, rng.uniform(0, 0.05)]))
        ta_out = float(rng.choice([0.0, rng.uniform(0, 0.05)]))
        b_end = None if rng.random() < 0.3 else b0 + float(rng.uniform(0, 0.1))
        args = (float(rng.uniform(-1e4, 1e4)), float(rng.uniform(-1e5, 1e5)), b0, ta_in,
                float(rng.uniform(-1e5, 1e5)), b_end, ta_out)
        t = b0 + float(rng.uniform(-0.06, 0.2))
        rows.append((t, args))
    t = np.array([r[0] for r in rows])
    cols = [np.array([r[1][i] if r[1][i] is not None else 0.0 for r in rows])
            for i in range(7)]
    has_end = np.array([r[1][5] is not None for r in rows])
    got = _linear_positions(t, cols[0], cols[1], cols[2], cols[3], cols[4], has_end,
                            cols[5], cols[6])
    assert got.tolist() == [position_at(tt, *a) for tt, a in rows]


def test_gather_trigger_set_by_a_plc_mid_stream():
    """``GATHER TRIGGER`` armed before a stream; a PLC raises the trigger input when X has
    passed 20 (the trigger input and the poll of it ``[INF]``, docs/pmac.md): the first
    sample is the same servo cycle on both cards."""
    def scenario(rig: Rig) -> None:
        axes(rig)
        setup(rig, POSITIONS[:4] + [vel(1)], words=4000)
        rig.ok("M10->Y:$078800,0,1")
        rig.ok("M161->D:$000088")
        rig.ok("OPEN PLC 2 CLEAR")
        rig.ok("IF (M161 > 20 * I108 * 32) M10=1 ENDIF")
        rig.ok("CLOSE")
        rig.ok("I5=3")
        rig.ok("ENABLE PLC 2")
        rig.ok("GATHER TRIGGER")
        stream(rig, ["TA1 TS0 TM5"] + [f"X{i} Y{i / 2} Z{-i} A{i % 7}" for i in range(60)])
        rig.run_for(0.6)
    ref, _ = both(scenario)
    assert [f["state"] for _, _, f in ref.events("gather")][:2] == ["armed", "started"]


@pytest.mark.parametrize("words", [37, 200, 1001])
def test_a_buffer_filling_up_between_two_events(words):
    """I5000 = 0 (TSRM p170: stop when full) with only batch-form sources: the sample that
    fills the buffer and the ``stopped`` event are at that sample's servo cycle, wherever
    it falls between two events."""
    def scenario(rig: Rig) -> None:
        axes(rig)
        setup(rig, POSITIONS[:3], words=words)
        rig.ok("GATHER")
        stream(rig, ["TA1 TS0 TM13"] + [f"X{i} Y{-i}" for i in range(40)])
        rig.run_for(0.6)
    ref, _ = both(scenario)
    (k, _, stopped), = ref.events("gather")[-1:]
    assert stopped["reason"] == "full" and k == ref.c.gather.recording().cycles[-1]
