"""Stateful property test: any sequence of host actions keeps the PMAC consistent.

Hypothesis drives a controller with random loads, R / S / Q / A / H, buffer open/close and time
steps; after every step the rotary buffer's word count and line count match a trivial model,
events stay time-ordered, every move that starts ends before another starts, and program
states only take legal transitions (an illegal one raises inside the core).
"""

from __future__ import annotations

import contextlib

from hypothesis import settings
from hypothesis import strategies as hs
from hypothesis.stateful import RuleBasedStateMachine, invariant, rule
from motionsim.sim.errors import BufferFull
from motionsim.sim.pmac import PmacController

LINES = ["TM20 TA10 TS0 X1", "X2 Y1", "M1==1", "DWELL5", "DELAY5", "P1=P1+1", "INC X1",
         "ABS", "RAPID X0", "LINEAR", "CIRCLE1 I1", "M2=1"]


class PmacMachine(RuleBasedStateMachine):
    def __init__(self) -> None:
        super().__init__()
        self.c = PmacController("m", {"i5113": 0})
        self.c.define_rotary(1, 40)
        self.c.point_program(1, 0)
        self.words = 0

    @rule(lines=hs.lists(hs.sampled_from(LINES), min_size=1, max_size=4))
    def load(self, lines):
        with contextlib.suppress(BufferFull):
            self.c.load_lines(1, lines)

    @rule(cmd=hs.sampled_from(["R", "S", "Q", "A", "H", "OPEN ROT", "CLOSE", "X5", "PR",
                               "??", "I5113=5", "I5113=0", "I11=3", "I11=0",
                               "%50", "%0", "%100", "%200", "I5192=1", "I5192=0"]))
    def terminal(self, cmd):
        reply = self.c.terminal(cmd)
        while not reply.done:
            self.c.env.step()

    @rule(run=hs.sampled_from(["run", "quit", "abort"]))
    def rest(self, run):
        getattr(self.c, run)(1)

    @rule(dt=hs.floats(min_value=1e-4, max_value=0.2))
    def advance(self, dt):
        self.c.env.run(until=self.c.env.now + dt)

    @invariant()
    def buffer_consistent(self):
        rot = self.c.coord_system(1).rotary
        assert 0 <= rot.used_words <= rot.size_words
        held = sum(line.words for _, line in rot.pending) + sum(w for _, w in rot.calculated)
        assert held == rot.used_words

    @invariant()
    def events_ordered_and_moves_paired(self):
        last_t = -1.0
        open_move = None
        for e in self.c.log.events():
            assert e.t >= last_t
            last_t = e.t
            if e.type == "move_start":
                assert open_move is None, f"move {e['n']} starts while {open_move} runs"
                open_move = e["n"]
            elif e.type == "move_end":
                assert open_move == e["n"]
                open_move = None


TestPmacMachine = PmacMachine.TestCase
TestPmacMachine.settings = settings(max_examples=60, stateful_step_count=30, deadline=None)
