"""Synchronous M-variable writes in segmentation mode (TUM p250; spec §4.4, §11.4): with
Isx13 > 0 a write runs "at the start of the first Isx13 spline segment after the start of
blending into the programmed move", and the queue is checked every RTI (I8+1 servo cycles),
so it lands on the first RTI at or after that segment start. Segments start when the
sequence starts from rest and follow every Isx13 ms ``[INF]``. Times are servo cycles.
"""

from __future__ import annotations

import math


def _first_segment_at_or_after(k: float, k0: int, seg: float) -> float:
    """The first segment boundary (in cycles, segments of ``seg`` cycles from ``k0``) at or
    after cycle ``k``."""
    return k0 + math.ceil((k - k0) / seg - 1e-9) * seg


def _rti_at_or_after(k: float, rti: int) -> int:
    return -(-math.ceil(k - 1e-6) // rti) * rti


def test_tum_p250_a_blend_starting_exactly_on_a_segment_boundary_writes_on_that_boundary(
    make_rig,
):
    """Servo period 0.5 ms (I10 = 4194304), Isx13 = 10 ms (20 cycles), I8 = 0 (an RTI every
    cycle): the blend into ``X20`` begins exactly 50 segments after the sequence started, so
    that segment is "the first after the start of blending" and the write lands on it — not a
    segment later."""
    rig = make_rig(i10=4194304, i8=0, i5113=10)
    assert rig.period == 0.0005
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM500 TA100 TS0 X10", "M1==1", "X20"])
    rig.ok("R")
    rig.run_until_idle()
    starts = {f["n"]: k for k, _, f in rig.events("move_start")}
    (k_m,) = [k for k, _, f in rig.events("mvar") if f["name"] == "M1"]
    # from rest: programmed start at +50 ms (TA/2), end at +550, decision and blend at +500
    assert starts[3] == starts[1] + 1000
    assert k_m == starts[3]
    assert rig.ok("M1") == "1"


def test_tum_p250_each_segmented_write_lands_on_the_rti_after_the_first_segment_after_its_blend(
    make_rig,
):
    """Short moves run Isx20 segments ahead with the special lookahead (TSRM p181), RTIs every
    10 cycles (I8 = 9), Isx13 = 10 ms: several writes wait at once, some for the next segment
    and some for the one after; each lands on the first RTI at or after the first segment
    boundary at or after its move's blend start, in program order."""
    rig = make_rig(i8=9, i5113=10, i5120=20)
    rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    rig.rotary_setup(words=2000)
    lines = ["TM3 TA2 TS0 X1"]
    for k in range(1, 30):
        lines += [f"M{k}=={k}", f"X{k + 1}"]
    rig.c.load_lines(1, lines)
    rig.ok("R")
    rig.run_until_idle()
    starts = {f["n"]: k for k, _, f in rig.events("move_start")}
    writes = [(k, f["name"], f["value"]) for k, _, f in rig.events("mvar")]
    seg = 0.010 / rig.period
    k0 = starts[1]
    expected = []
    for n in range(1, 30):
        k_blend = starts[2 * n + 1]  # the move after M{n}== is line 2n + 1
        k_seg = _first_segment_at_or_after(k_blend, k0, seg)
        expected.append((_rti_at_or_after(k_seg, 10), f"M{n}", float(n)))
    assert writes == expected
    # the case that needs the queue: a write waiting for the next segment's RTI while an
    # older one still waits for the RTI after the segment before
    pending_two = [
        n for n in range(1, 29)
        if starts[2 * n + 3] < expected[n - 1][0] < expected[n][0]
    ]  # fmt: skip
    assert pending_two
    assert [f["state"] for _, _, f in rig.events("program")] == ["running", "waiting"]
