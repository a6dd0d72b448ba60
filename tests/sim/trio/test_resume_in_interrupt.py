"""A program waiting at a move line whose process buffer was full goes on when the servo
interrupt writes its move into the buffer (TN20-16; TRM MC206 p. 8-130, PMOVE). When nothing
else can happen at that instant, the resumption runs inside the interrupt's own SimPy event
instead of a wake-up of its own (``MotionBuffers._resume_placed``, issue 35): the differential
pin of that short cut against the wake-up it replaces — the same event log, byte for byte, for
programs that block at every move line, several processes, statement times of 1 µs and
of 600 µs, a STOP queued at the placement and a log someone listens to. Virtual time only."""

from __future__ import annotations

import pytest
from motionsim.sim.simpy_adapter import triggered_at

from tests.sim.trio.conftest import make

FOUR_AXES = """FOR i=1 TO 40
  MOVE(1) AXIS(0)
  MOVE(1) AXIS(1)
  MOVE(1) AXIS(2)
  MOVE(1) AXIS(3)
NEXT i
"""

MIXED = """BASE(0,1)
FOR i=1 TO 12
  MOVE(1,2)
  MOVE(0.5) AXIS(2)
  MOVEABS(i, -i)
  IF i=6 THEN CANCEL AXIS(0)
  MOVECIRC(2,0,1,0,0)
NEXT i
WAIT IDLE
PRINT "done"
"""

OTHER = """FOR j=1 TO 30
  MOVE(2) AXIS(3)
  VR(10)=VR(10)+1
NEXT j
"""

#: ``short`` for the 1-ms moves of FOUR_AXES (a triangle of exactly one servo period).
SHORT = {"speed": 2000.0, "accel": 4e6, "decel": 4e6}


def _log(programs: dict[int, str], resume_in_interrupt: bool, config: dict | None = None,
         stop_at: float | None = None, listen: bool = False) -> tuple[str, int]:
    """The JSON Lines log of ``programs`` (process -> text) run 0.5 s, and the number of SimPy
    events processed."""
    c = make(**(config or {}))
    c.buffers.resume_in_interrupt = resume_in_interrupt
    if listen:
        c.log.listen(lambda _e: None)
    for process, text in programs.items():
        c.store_program(f"P{process}", text)
        c.run_program(f"P{process}", process)
    if stop_at is not None:  # a STOP queued for the instant of a placement, half a servo
        # period before it: after that period's interrupt was queued (URGENT, behind it)
        triggered_at(c.env, stop_at - 0.0005, lambda _e: triggered_at(
            c.env, stop_at, lambda _e2: c.stop_process(1)))
    steps = 0
    while c.env.peek() <= 0.5:
        c.env.step()
        steps += 1
    return c.log.to_jsonl(), steps


CASES = {
    "four axes, a move line blocking each period": ({1: FOUR_AXES}, SHORT),
    "four axes, statement time 1 us": ({1: FOUR_AXES}, {**SHORT, "statement_us": 1.0}),
    "four axes, statement time 600 us": ({1: FOUR_AXES},
                                                   {**SHORT, "statement_us": 600.0}),
    "mixed moves, cancel, wait idle": ({1: MIXED}, None),
    "two processes placed in one period": ({1: FOUR_AXES, 2: OTHER}, SHORT),
    "three processes": ({1: MIXED, 2: OTHER, 3: FOUR_AXES.replace("AXIS(3)", "AXIS(2)")},
                        None),
}


@pytest.mark.parametrize("name", list(CASES))
def test_the_resumption_inside_the_interrupt_logs_what_its_own_wake_up_does(name):
    """TN20-16: every move line of these programs waits for its process buffer; the log with
    the short cut is the log of the wake-up per resumption, byte for byte."""
    programs, config = CASES[name]
    fast, fast_steps = _log(programs, True, config)
    slow, slow_steps = _log(programs, False, config)
    assert fast == slow
    assert '"blocked"' in fast


def test_the_short_cut_saves_one_simpy_event_per_blocked_move_line():
    """One process, one move line blocked per servo period: each resumption is one SimPy event
    less (the four-axis program blocks at 160 move lines, 159 of them behind a full buffer)."""
    fast, fast_steps = _log({1: FOUR_AXES}, True, SHORT)
    slow, slow_steps = _log({1: FOUR_AXES}, False, SHORT)
    blocked = fast.count('"state":"blocked"')
    assert fast == slow and blocked == 159
    assert slow_steps - fast_steps == blocked


def test_a_stop_queued_at_the_placement_is_not_overtaken():
    """A STOP queued for the interrupt's instant (URGENT, queued after it) comes before the
    program's turn: the wake-up is kept (something is due), the program reports ``stopped``
    and not ``running`` — the same log both ways (spec: ``test_blocked_line_resume.py``)."""
    fast, _ = _log({1: FOUR_AXES}, True, SHORT, stop_at=0.004)
    slow, _ = _log({1: FOUR_AXES}, False, SHORT, stop_at=0.004)
    assert fast == slow
    assert fast.count('"state":"stopped"') == 1
    at_stop = [line for line in fast.splitlines() if '"t":0.004,' in line]
    assert any('"type":"process_buffer"' in line for line in at_stop)  # the placement
    states = [line.split('"state":"')[1].split('"')[0] for line in at_stop if '"state"' in line]
    assert states == ["stopped"]


def test_a_log_someone_listens_to_keeps_the_wake_up():
    """A listener (the REST wait for an event, a WebSocket) follows the log event by event: the
    program resumes through its own wake-up then, as many SimPy events as without the short
    cut, and the same log."""
    fast, fast_steps = _log({1: FOUR_AXES}, True, SHORT, listen=True)
    slow, slow_steps = _log({1: FOUR_AXES}, False, SHORT, listen=True)
    assert fast == slow and fast_steps == slow_steps
