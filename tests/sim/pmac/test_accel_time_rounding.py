"""TA and TS are used as whole milliseconds, halves rounded up (spec §9.1; not Python's
round-half-to-even, which would make ``TA0.5`` 0 ms and ``TA2.5`` 2 ms)."""

from __future__ import annotations

import math

import pytest
from motionsim.sim.pmac.buffers import motion


@pytest.mark.parametrize(
    ("ta", "ts", "ms"),
    [(0.5, 0, 1), (1.5, 0, 2), (2.5, 0, 3), (2.49, 0, 2), (10, 0, 10), (0, 0.5, 2), (0, 2.5, 6),
     (3, 1.5, 4), (0.4, 0, 0)],
)  # fmt: skip
def test_ta_and_ts_round_half_up_to_whole_ms(ta, ts, ms):
    assert motion.accel_time_s(ta, ts) == ms / 1000.0


def _single_move_cycles(rig, header: str) -> int:
    rig.rotary_setup()
    rig.c.load_lines(1, [header + " X1"])
    rig.ok("R")
    rig.run_until_idle()
    (start,) = [k for k, _, _ in rig.events("move_start")]
    (end,) = [k for k, _, _ in rig.events("move_end")]
    return end - start


@pytest.mark.parametrize(("ta", "ms"), [("2.5", 3), ("0.5", 1), ("3.5", 4)])
def test_a_move_from_rest_takes_tm_plus_the_rounded_ta(make_rig, ta, ms):
    """PUM p169: TM + Ta from rest, with Ta = TA rounded half up."""
    rig = make_rig()
    cycles = _single_move_cycles(rig, f"TM100 TA{ta} TS0")
    assert cycles == math.ceil(rig.ms_cycles(100 + ms) - 1e-6)
