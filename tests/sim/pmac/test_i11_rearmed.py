"""I11 ("the delay from when the run signal is taken ... and when the first programmed move
starts", PSRM I11) for a line arriving while the program waits: the sequence from rest starts
at that line, under the I11 then in force. A delay armed by an earlier ``R`` under another
I11 no longer applies."""

from __future__ import annotations


def test_i11_set_to_0_while_waiting_drops_the_delay_an_earlier_r_armed(make_rig):
    """``R`` with I11 = 50 on an empty buffer arms a 50-ms delay; ``I11=0`` then, and a line
    arriving just before that delay ends is calculated at its RTI and runs: no run-time error
    at the old deadline."""
    rig = make_rig()
    rig.ok("I11=50")
    rig.rotary_setup()
    rig.ok("R")
    t_r = rig.c.now
    rig.ok("I11=0")
    deadline = rig.c.scheduler.servo_at_or_after(t_r + 0.05)
    rig.c.env.run(until=deadline - 0.5 * rig.period)
    rig.c.load_lines(1, ["TM10 X1"])
    rig.run_until_idle(2.0)
    states = [f["state"] for _, _, f in rig.events("program")]
    assert states == ["running", "waiting", "running", "waiting"]
    (k_start,) = [k for k, _, f in rig.events("move_start") if f["n"] == 1]
    assert k_start * rig.period < deadline + 3 * rig.period  # the RTI after the line


def _x3_start(rig, before_x3: str | None = None) -> int:
    """I8 = 255, I11 = 170; X1 runs, X2 arrives during it (cycle 600) and runs after it; the
    program waits at cycle 940 (``before_x3`` typed then); X3 arrives at cycle 950, with
    calculation already due. X3's ``move_start`` cycle."""
    for command in ("I8=255", "I11=170"):
        rig.ok(command)
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM200 TA10 TS0 X1"])
    rig.ok("R")
    rig.c.env.run(until=600 * rig.period)
    rig.c.load_lines(1, ["TM20 X2"])
    rig.c.env.run(until=940 * rig.period)
    assert rig.c.coord(1)["program"] == {"state": "waiting"}
    if before_x3 is not None:
        rig.ok(before_x3)
    rig.c.env.run(until=950 * rig.period)
    rig.c.load_lines(1, ["X3"])
    rig.run_until_idle(3.0)
    assert "error" not in rig.c.coord(1)["program"]
    return rig.by_n("move_start")[3]


def test_a_line_arriving_while_waiting_starts_its_delay_with_planning_already_due(rig):
    """I8 = 255 (RTIs 256 cycles apart), I11 = 170 ms (384 cycles): X2 arrives during X1 and
    runs after it, its start asking for calculation at the RTI of cycle 1024; X3 arrives while
    the program waits (cycle 950). The sequence from rest starts at X3: it moves 384 cycles
    after it arrived (cycle 1334), not 384 after that RTI (1408)."""
    assert _x3_start(rig) == 950 + 384


def test_an_i11_changed_while_waiting_is_the_delay_of_the_line_that_arrives_next(rig):
    """As above, but ``I11=100`` is typed at cycle 940 while the program waits: X3, arriving
    at cycle 950 with calculation already due, starts under the I11 now in force, 100 ms
    (226 cycles) after it arrived — cycle 1176, not 1334."""
    assert _x3_start(rig, "I11=100") == 950 + 226
