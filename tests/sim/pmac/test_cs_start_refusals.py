"""The card's refusals of ``R`` / ``S`` and every other start of a coordinate system's motion
(the REST run, ``CMD"R"`` from a PLC), in the order of the Turbo error table (TSRM I6, PSRM
p25-26; spec §2.2, §11.10): ERR011 previous move not completed, ERR012 open loop, ERR013 not
activated, ERR014 no motors. A refused start changes nothing; after one the jog that caused it
can still be stopped. Also ``E`` (the EPICS driver's ``&{cs}E``) and the Servo-IC clock
I-variables the driver reads (TSRM I7m00-I7m02, p216)."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import Conflict


def _cs1(rig) -> None:
    rig.ok("&1 #1->1000X #2->1000Y")
    rig.rotary_setup()
    rig.c.load_lines(1, ["LINEAR ABS TA20 TS0 TM100", "X1 Y1"])


def _unchanged(rig, since: int) -> None:
    assert rig.events("program", "line_calculated", "move_start", since=since) == []
    assert not rig.c.coord_system(1).running


@pytest.mark.parametrize("start", ["R", "S", "&1B0R"])
def test_err011_while_a_motor_of_the_cs_jogs_and_the_jog_can_still_be_stopped(rig, start):
    _cs1(rig)
    rig.ok("#2 J+")
    rig.run_for(0.05)
    since = rig.c.log.last_seq
    reply = rig.cmd(start)
    assert reply.error == "ERR011"
    _unchanged(rig, since)
    assert rig.cmd("#2 J/").error is None  # not ERR001: the CS never started
    rig.run_until_idle(5)
    assert rig.events("jog", since=since)[-1][2]["state"] == "end"
    assert rig.cmd(start).error is None  # the jog is over: it starts now
    assert rig.c.coord_system(1).running


def test_err011_during_a_homing_search_and_a_jog_to_position(rig):
    _cs1(rig)
    rig.ok("#1 HM")
    assert rig.cmd("R").error == "ERR011"
    rig.run_until_idle(30)
    rig.ok("#1 J=5000")  # still in its Ixx92 calculation delay: the move is under way
    assert rig.cmd("R").error == "ERR011"


def test_err011_from_the_rest_run_changes_no_program_pointer(rig):
    _cs1(rig)
    rig.ok("OPEN PROG 3 CLEAR X1 CLOSE")
    rig.ok("&1 B3")
    rig.ok("#1 J+")
    with pytest.raises(Conflict) as e:
        rig.c.run(1)  # the REST run is B0 R
    assert e.value.pmac_error == "ERR011"
    assert rig.c.coord_system(1).program == 3


@pytest.mark.parametrize("loop", ["K", "O10"])
def test_err012_with_a_killed_or_open_loop_motor_until_e_closes_it(rig, loop):
    _cs1(rig)
    rig.ok(f"#2 {loop}")
    since = rig.c.log.last_seq
    assert rig.cmd("R").error == "ERR012"
    assert rig.cmd("S").error == "ERR012"
    _unchanged(rig, since)
    rig.ok("&1 E")
    assert rig.c.motor(2).loop == "closed_loop"
    assert rig.cmd("R").error is None


def test_err013_with_a_motor_not_activated(rig):
    """Ixx00 = 0: the motor is not activated. A Geo Brick activates its 8 local axes, motors
    9-32 are not (factory.py)."""
    _cs1(rig)
    rig.ok("I200=0")
    assert rig.cmd("R").error == "ERR013"
    rig.ok("I200=1")
    rig.ok("OPEN PROG 3 CLEAR X1 CLOSE")
    rig.ok("&2 #9->X B3")
    assert rig.cmd("&2 R").error == "ERR013"
    assert rig.cmd("&1 B0 R").error is None  # B again after an OPEN PROG (ERR015)


def test_the_checks_run_in_the_error_tables_order(rig):
    """Motor 2 killed (ERR012) and not activated (ERR013), motor 1 jogging (ERR011): the
    lowest code wins, then the next once it is cleared."""
    _cs1(rig)
    rig.ok("#2 K")
    rig.ok("I200=0")
    rig.ok("#1 J+")
    assert rig.cmd("R").error == "ERR011"
    rig.ok("#1 J/")
    rig.run_until_idle(5)
    assert rig.cmd("R").error == "ERR012"
    rig.ok("&1 E")
    assert rig.cmd("R").error == "ERR013"


def test_err014_in_a_cs_with_no_motors_when_strict(make_rig):
    rig = make_rig(strict_cs_motors=True)
    rig.rotary_setup(cs=3)
    since = rig.c.log.last_seq
    assert rig.cmd("&3 R").error == "ERR014"
    assert rig.cmd("&3 S").error == "ERR014"
    assert rig.events("program", since=since) == []
    rig.ok("&3 #4->X")
    assert rig.cmd("&3 R").error is None
    default = make_rig()  # the simulator's virtual axes: a motorless CS runs
    default.rotary_setup(cs=3)
    assert default.cmd("&3 R").error is None


def test_strict_cs_motors_is_a_boolean(make_rig):
    with pytest.raises(Exception, match="strict_cs_motors"):
        make_rig(strict_cs_motors=1)


def test_a_plc_command_r_is_refused_the_same_way(rig):
    """``CMD"&1R"`` goes through the command line: a jogging motor keeps the CS from starting
    and the PLC goes on."""
    _cs1(rig)
    rig.ok("#1 J+")
    rig.ok("I5=2")
    rig.ok('OPEN PLC 5 CLEAR CMD"&1R" DIS PLC 5 CLOSE')
    rig.ok("ENABLE PLC 5")
    rig.run_for(0.1)
    assert not rig.c.coord_system(1).running
    rig.ok("#1 J/")
    rig.run_until_idle(5)
    rig.ok("ENABLE PLC 5")  # the same command, with the jog over, starts the CS
    rig.run_for(0.1)
    assert rig.events("move_start")


def test_e_closes_the_loops_of_the_cs_motors_only(rig):
    rig.ok("&1 #1->X #2->Y &2 #3->X")
    for n in (1, 2, 3):
        rig.ok(f"#{n} K")
    rig.ok("#4 J+")
    r = rig.cmd("&1 E")
    assert (r.reply, r.error) == ("", None)
    assert [rig.c.motor(n).loop for n in (1, 2, 3)] == ["closed_loop", "closed_loop", "killed"]
    assert rig.c.motor(4).command is not None  # a motor outside the CS jogs on
    assert rig.cmd("&1e").error is None  # lower case, all closed: nothing to do


def test_i7000_chain_gives_the_servo_period(make_rig):
    """TSRM I7m00-I7m02: servo period = (2·I7000+3)(I7001+1)(I7002+1) / 117.9648 MHz; the
    default is the Turbo default clock (I7000 = 6527, I7002 = 3, TSRM p216)."""
    rig = make_rig()
    assert rig.ok("I7000 I7001 I7002 I7003") == "6527\r0\r3\r2258"
    assert rig.ok("I7022 I7023 I7122 I7123") == "1\r0\r1\r0"  # capture on the home flag
    for hz in (1000.0, 5000.0, 200.0):
        r = make_rig(servo_hz=hz)
        i00, i01, i02 = (float(x) for x in r.ok("I7000 I7001 I7002").split("\r"))
        period = (2 * i00 + 3) * (i01 + 1) * (i02 + 1) / 117_964_800
        assert period == pytest.approx(1 / hz, rel=2e-4)
        assert r.ok("I7100 I7101 I7102") == r.ok("I7000 I7001 I7002")
    assert make_rig(i7002=1).ok("I7002") == "1"  # an explicit config value stands
