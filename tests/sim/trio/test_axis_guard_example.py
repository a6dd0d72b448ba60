"""``examples/trio/mc4_axis_guard.bas`` on ``mc4xx`` with a following-error model: the software
limit stops a move and lights a lamp, a following error beyond FE_LIMIT is handled by the
program (MOTION_ERROR, ERROR_AXIS, FE_LATCH, WDOG), and the HMI's reset coil clears it
(TRM p. 8-177 RS_LIMIT / SERVO; docs/trio.md "Software limits", "Following error")."""

from __future__ import annotations

from pathlib import Path

from tests.sim.trio.conftest import fields, make, run_to

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "trio" / "mc4_axis_guard.bas"


def test_axis_guard_stops_at_the_limit_handles_the_trip_and_resets_from_the_hmi():
    c = make(model="mc4xx", fe_lag=0.002)
    c.store_program("GUARD", EXAMPLE.read_text())
    c.run_program("GUARD", 1)
    run_to(c, 5.0)
    # FS_LIMIT 300 reached at SPEED 500, then 500² / (2 x 5000) = 25 units of ramp
    assert c.get_variable("VR(20)") == 325.0
    assert [f["limit"] for _t, f in fields(c, "soft_limit")] == ["FS_LIMIT"]
    trip = fields(c, "following_error")
    assert len(trip) == 1 and trip[0][1]["fe"] > 0.5
    assert c.get_variable("VR(21)") == 0.0  # ERROR_AXIS
    assert c.get_variable("VR(22)") == trip[0][1]["fe"]  # FE_LATCH
    assert c.get_variable("VR(23)") == 0.0  # WDOG forced off
    lamps = {n: c.get_variable(f"OP({n})") for n in (8, 9, 10)}
    assert lamps == {8: 0.0, 9: 1.0, 10: 1.0}
    assert c.processes()[0]["state"] == "running"  # waiting for the reset button
    c.set_variable("OP(11)", 1)  # the HMI writes its reset coil
    run_to(c, 10.0)
    assert c.processes()[0]["state"] == "stopped"
    assert c.get_variable("VR(24)") == 0.0 and c.axis(0)["dpos"] == 0.0
    assert {n: c.get_variable(f"OP({n})") for n in (8, 10)} == {8: 1.0, 10: 0.0}
    assert [f["on"] for _t, f in fields(c, "wdog")] == [True, False, True]
    assert [f["text"] for _t, f in fields(c, "print")] == ["guard done, stopped at 325.0"]
