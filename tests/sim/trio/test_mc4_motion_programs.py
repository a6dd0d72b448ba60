"""Issue 22 "real programs": our own start-up, homing and flying-shear programs
(``examples/trio/mc4_*.bas``, ``flying_shear.bas``), written with the constructs real Trio
programs use, loaded on the ``mc4xx`` model and run as their code says."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.sim.trio.conftest import fields, make, run_to

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "trio"


def _run(c, name: str, process: int = 1) -> None:
    c.store_program(name.upper(), (EXAMPLES / f"{name}.bas").read_text())
    c.run_program(name.upper(), process)


def _stopped_cleanly(c, process: int) -> None:
    stopped = fields(c, "process", process=process, state="stopped")
    assert len(stopped) == 1 and "error" not in stopped[0][1], stopped


def test_mc4_startup_program_sets_drives_comms_and_enables_them():
    c = make(model="mc4xx")
    _run(c, "mc4_startup")
    run_to(c, 1.0)
    _stopped_cleanly(c, 1)
    assert [f["command"] for _t, f in fields(c, "setup")] == [
        "ETHERCAT", "SETCOM", "ETHERNET", "STEP_RATIO", "ENCODER_RATIO"]  # the bus was up
    assert c.get_variable("VR(50)") == 3.0 and c.get_variable("VR(51)") == 0.0
    for ax in range(3):
        for name, reply in [("P_GAIN", "0.8000"), ("I_GAIN", "0.0020"), ("D_GAIN", "3.0000"),
                            ("OV_GAIN", "-1.0000"), ("VFF_GAIN", "12.0000"),
                            ("FE_LIMIT", "2.0000"), ("SERVO", "1.0000"), ("UNITS", "1000.0000"),
                            ("DATUM_IN", "-1.0000")]:
            assert c.terminal(f"? {name} AXIS({ax})").reply == reply, (name, ax)
    assert c.terminal("? P_GAIN AXIS(3)").reply == "1.0000"  # untouched: power-up value
    assert c.terminal("? REP_DIST AXIS(2)").reply == "360.0000"
    assert c.terminal("? CLUTCH_RATE AXIS(1)").reply == "50.0000"
    assert c.terminal("? LIMIT_BUFFERED").reply == "16.0000"
    assert [f["on"] for _t, f in fields(c, "wdog")] == [True]
    assert [f["text"] for _t, f in fields(c, "print", channel=5)] == [
        "start-up done, bus 3 buffered 16"]
    assert c.system.comms.setcom[1] == (19200.0, 8.0, 1.0, 0.0, 1.0, 0.0)


def test_mc4_startup_repeat_axis_wraps_after_start_up():
    c = make(model="mc4xx")
    _run(c, "mc4_startup")
    run_to(c, 1.0)
    c.terminal("SPEED AXIS(2)=10000")
    c.terminal("MOVE(450) AXIS(2)")
    run_to(c, 3.0)
    assert c.terminal("? DPOS AXIS(2)").reply == "90.0000"  # REP_OPTION 1: 0..360


def _homing(c) -> None:
    c.set_variable("IN(5)", 1)  # the datum switch is clear (active low)
    _run(c, "mc4_homing")
    run_to(c, 0.5005)
    assert c.axis(0)["mtype"] == 12 and c.axis(0)["dpos"] < -15  # reverse at SPEED 50
    c.set_variable("IN(5)", 0)  # the switch is reached
    run_to(c, 1.0005)
    c.set_variable("IN(5)", 1)  # and left again, creeping forward


def test_mc4_homing_routine_datums_both_axes_then_defines_machine_coordinates():
    c = make(model="mc4xx")
    _homing(c)
    run_to(c, 5.0)
    _stopped_cleanly(c, 1)
    datums = {f["axis"]: (t, f["mode"]) for t, f in fields(c, "datum")}
    assert set(datums) == {0, 1}
    assert datums[0][1] == 4 and datums[1][1] == 1
    assert datums[0][0] == pytest.approx(1.001)  # the period after the input changed
    # DEFPOS(-10, 25) then MOVEABS(0, 0): both end at their machine zero
    assert (c.get_variable("VR(10)"), c.get_variable("VR(11)"), c.get_variable("VR(12)")) == (
        1.0, 0.0, 0.0)
    offsets = [f["offset"] for _t, f in fields(c, "offpos")]
    assert len(offsets) == 2
    assert [f["text"] for _t, f in fields(c, "print")] == ["homed 0.0000 0.0000"]


def test_mc4_homing_routine_without_the_switch_waits_at_its_datum_line():
    c = make(model="mc4xx")
    c.set_variable("IN(5)", 1)
    _run(c, "mc4_homing")
    run_to(c, 3.0)
    assert c.axis(0)["mtype"] == 12 and c.terminal("? AXISSTATUS AXIS(0)").reply == "64.0000"
    assert c.get_variable("VR(10)") == 0.0


def test_flying_shear_cuts_in_step_with_the_web_every_cut_length():
    """Web (axis 2) at 100 units/s; cut length 300. Each cut: the knife waits out 300 of web,
    accelerates over 40 of web to 20, runs in step (ratio 1) and stops at 60, then returns
    over 90: 480 of web per cut, none lost at the joints of the MOVELINKs."""
    c = make(model="mc4xx")
    c.set_variable("VR(21)", 3)
    c.set_variable("VR(22)", 300)
    c.set_axis(2, speed=100.0)
    c.terminal("FORWARD AXIS(2)")
    run_to(c, 0.0105)  # the web at speed (ramp 1 ms) before the shear starts
    _run(c, "flying_shear")
    samples = []
    for k in range(1, 1600):
        run_to(c, 0.0105 + k * 0.01)
        samples.append((c.now, c.axis(0)["dpos"], c.axis(2)["dpos"]))
    _stopped_cleanly(c, 1)
    ons = [t for t, f in fields(c, "output", output=8) if f["value"] == 1]
    offs = [t for t, f in fields(c, "output", output=8) if f["value"] == 0]
    assert len(ons) == len(offs) == 3
    # the knife is in step with the web between the cut (accel over) and the slow-down
    for t_on in ons:
        after = [(t, k, w) for t, k, w in samples if t_on + 0.01 < t < t_on + 0.25]
        (t0, k0, w0), (_t1, k1, w1) = after[0], after[-1]
        assert (k1 - k0) == pytest.approx(w1 - w0, abs=0.2)
        assert 20.0 <= k0 <= 20.0 + (t0 - t_on) * 100.0 + 0.2  # the cut at the end of accel
    gaps = [b - a for a, b in zip(ons, ons[1:], strict=False)]
    assert gaps == pytest.approx([4.8, 4.8], abs=0.002)  # 480 of web at 100 units/s
    assert samples[-1][1] == 0.0  # the knife back at its start
    assert [f["text"] for _t, f in fields(c, "print")] == ["cuts 3"]
