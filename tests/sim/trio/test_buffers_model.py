"""The buffers against a list model, driven by Hypothesis (random moves, random waits).

Model: per axis a FIFO of the moves issued on it (single-axis moves from processes 0..2).
Invariants checked from the public surface and the event log after every step:

* MTYPE / NTYPE of each axis match the last ``axis`` event for it;
* a move command is refused (BufferFull) exactly when its process buffer is full, and then
  nothing changes;
* every issued move runs exactly once, in issue order per axis, each starting in the servo
  period after its predecessor on the axis ended (or later) — never overlapping.
"""

from __future__ import annotations

from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, invariant, rule
from motionsim.sim.errors import BufferFull

from tests.sim.trio.conftest import cycle, fields, make, run_to

AXES = 3


class BuffersMachine(RuleBasedStateMachine):
    def __init__(self) -> None:
        super().__init__()
        self.c = make(axes=AXES)
        self.issued: dict[int, list[float]] = {a: [] for a in range(AXES)}
        self.processes: dict[int, set[int]] = {a: set() for a in range(AXES)}

    @rule(axis=st.integers(0, AXES - 1), process=st.integers(0, 2),
          dist=st.sampled_from([1.0, 10.0, 25.0]))
    def issue(self, axis, process, dist):
        c = self.c
        full = any(f["mtype"] for f in self._pb_state(process))
        seq = c.log.last_seq
        try:
            placed = c.move(axis, "MOVE", [dist], process=process)
        except BufferFull:
            assert full
            assert c.log.last_seq == seq
            return
        assert not full
        assert placed in ("mtype", "ntype", "process_buffer")
        self.issued[axis].append(dist)
        self.processes[axis].add(process)

    @rule(ms=st.integers(1, 60))
    def wait(self, ms):
        run_to(self.c, self.c.now + ms / 1000.0)

    def _pb_state(self, process):
        last = [f for _, f in fields(self.c, "process_buffer", process=process)]
        return last[-1:] if last else []

    @invariant()
    def buffers_match_the_last_axis_event(self):
        for a in range(AXES):
            evs = fields(self.c, "axis", axis=a)
            want = (evs[-1][1]["mtype"], evs[-1][1]["ntype"]) if evs else (0, 0)
            ax = self.c.axis(a)
            assert (ax["mtype"], ax["ntype"]) == want

    @invariant()
    def moves_run_in_order_one_at_a_time(self):
        c = self.c
        for a in range(AXES):
            starts = [cycle(c, t) for t, _ in fields(c, "move_start", axis=a)]
            ends = [cycle(c, t) for t, _ in fields(c, "move_end", axis=a)]
            assert len(starts) <= len(self.issued[a])
            assert len(ends) in (len(starts), len(starts) - 1)
            for i, s in enumerate(starts[1:], start=1):
                assert s >= ends[i - 1] + 1
            for s, e in zip(starts, ends, strict=False):
                assert e > s

    def teardown(self) -> None:
        c = self.c
        run_to(c, c.now + 5.0)
        for a in range(AXES):
            assert c.axis(a)["dpos"] == sum(self.issued[a])
            assert len(fields(c, "move_end", axis=a)) == len(self.issued[a])
            if len(self.processes[a]) == 1:
                self._check_issue_order(a)

    def _check_issue_order(self, a: int) -> None:
        """Issue order of one process's moves: each runs from rest to rest, so its duration
        grows with its distance (1 unit: ~7 servo periods, 10: 20, 25: 35) and the n-th move
        to run must take the time of the n-th move issued. (Moves of different processes
        queue in different process buffers: their relative order is not issue order.)"""
        c = self.c
        starts = [cycle(c, t) for t, _ in fields(c, "move_start", axis=a)]
        ends = [cycle(c, t) for t, _ in fields(c, "move_end", axis=a)]
        took = [e - s for s, e in zip(starts, ends, strict=True)]
        pairs = list(zip(self.issued[a], took, strict=True))
        for d1, t1 in pairs:
            for d2, t2 in pairs:
                if d1 == d2:
                    assert abs(t1 - t2) <= 1, pairs
                elif d1 < d2:
                    assert t1 < t2, pairs

TestBuffersModel = BuffersMachine.TestCase
TestBuffersModel.settings = settings(max_examples=40, stateful_step_count=30, deadline=None)
