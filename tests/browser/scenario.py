"""What the browser test and ``make screenshot`` run against a served motionsim over REST.

* :func:`stream_rotary`: a PMAC host streaming a rotary program the way the manual's BREQ
  procedure does — a first batch up to I17, ``B0 R``, then a line each time the buffer falls
  below I16 (BREQ high), with synchronous M writes in the program; it stops feeding near the
  end, so the program runs out of lines (``waiting``).
* :func:`run_tn20`: Trio application note TN20-16's program on a virtual-clock Trio (short
  moves on axis 0, long ones on axis 1, one process buffer), the ``examples/trio`` settings.
"""

from __future__ import annotations

from pathlib import Path

from motionsim.app.client import MotionSimClient

ROOT = Path(__file__).resolve().parents[2]
TN20 = ROOT / "examples" / "trio" / "tn20_blocking.bas"


def _line(i: int) -> str:
    if i % 5 == 4:
        return f"M1=={i % 2}"  # a synchronous M write, at the start of the next move
    return f"TM{20 + 10 * (i % 3)} TA10 TS0 X{i + 1}"


def stream_rotary(ms: MotionSimClient, cid: str = "p", lines: int = 60,
                  step_s: float = 0.01, until_s: float = 1.2, cs2_lines: int = 0) -> None:
    """Create a virtual PMAC ``cid`` and stream ``lines`` lines into &1's rotary buffer;
    with ``cs2_lines``, &2 also runs that many lines loaded at once (and then waits)."""
    ms.create_controller("pmac", id=cid, clock="virtual", config={"i16": 5, "i17": 10})
    if cs2_lines:   # buffers are defined from the highest CS down (TUM p337)
        ms.define_rotary(cid, 2, 300)
        ms.load_lines(cid, 2, [f"TM40 TA10 TS0 Y{i + 1}" for i in range(cs2_lines)])
        ms.run(cid, 2)
    ms.define_rotary(cid, 1, 600)
    first = [_line(i) for i in range(9)]
    ms.load_lines(cid, 1, first, first_seq=1)
    sent = len(first)
    ms.run(cid, 1)
    t = 0.0
    while t < until_s:
        breq = ms.coord(cid, 1)["rotary"]["breq"]
        while breq and sent < lines:
            breq = ms.load_lines(cid, 1, [_line(sent)], first_seq=sent + 1).breq
            sent += 1
        ms.advance(cid, step_s)
        t += step_s


def run_tn20(ms: MotionSimClient, cid: str = "t", seconds: float = 0.3, moves: int = 50) -> None:
    """Create a virtual Trio ``cid``, load TN20-16's program and run it for ``seconds``."""
    ms.create_controller("trio", id=cid, clock="virtual",
                         config={"speed": 1000, "accel": 100000, "decel": 100000})
    for n in range(1, moves + 1):
        ms.set_variable(cid, f"VR({n})", 10)
        ms.set_variable(cid, f"VR({100 + n})", 200)
    ms.store_program(cid, "tn20", TN20.read_text())
    ms.run_program(cid, "tn20", process=1)
    ms.advance(cid, seconds)
