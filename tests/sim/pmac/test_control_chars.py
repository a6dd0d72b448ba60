"""Control characters act at once and report card-wide (PUM-V p28, p34; TSRM p260-270, p424;
TUM p217, p319; spec pmac.md §11.9)."""

from __future__ import annotations

import pytest

JOG = "I122=10 I120=100 I121=0 I119=1 I192=0 I115=0.1"


def test_ctrl_b_reports_the_eight_motor_status_words_of_the_motor_group(rig):
    rig.ok("#10K")
    words = rig.ok("\x02").split(" ")
    assert len(words) == 8 and all(len(w) == 12 for w in words)
    assert words == [rig.ok(f"#{n}?") for n in range(1, 9)]
    rig.ok("##1")
    assert rig.ok("##") == "1"
    assert rig.ok("\x02").split(" ") == [rig.ok(f"#{n}?") for n in range(9, 17)]
    assert not int(rig.ok("\x02").split(" ")[1][:6], 16) & (1 << 19)  # motor 10 killed


def test_ctrl_c_reports_every_coordinate_system_status(rig):
    words = rig.ok("\x03").split(" ")
    assert len(words) == 16 and all(len(w) == 18 for w in words)
    assert words[2] == rig.ok("&3??")


def test_ctrl_p_positions_to_a_32nd_count_ctrl_f_following_errors_ctrl_v_velocities(rig):
    rig.ok(JOG + " #2J+")
    rig.run_for(0.05)
    t = rig.c.env.now
    reply = rig.cmd("\x10\x06\x16")
    positions, errors, velocities = reply.reply.split("\r")
    p2 = float(positions.split(" ")[1])
    assert p2 * 32 == int(p2 * 32)
    assert p2 == pytest.approx(rig.c.motor_position(2, reply.t_done), abs=1 / 32)
    assert positions.split(" ")[0] == "0" and p2 > rig.c.motor_position(2, t) - 1
    assert errors == "0 0 0 0 0 0 0 0"
    assert float(velocities.split(" ")[1]) > 0 and velocities.split(" ")[0] == "0"


def test_ctrl_k_kills_all_motors_and_aborts_a_running_program(rig):
    rig.ok("&1 #1->1000X")
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.ok("TM1000 X1 X2")
    rig.ok("CLOSE &1R")
    rig.run_for(0.3)
    rig.ok("\x0b")
    k = rig.cyc(rig.c.log.events("program")[-1].t)
    assert rig.events("program")[-1] == (k, "program",
                                         {"cs": 1, "state": "aborted", "error": "killed"})
    p = rig.ok("#1P")
    rig.run_for(0.5)
    assert rig.ok("#1P") == p
    killed = [e["motor"] for _, _, e in rig.events("motor") if e["state"] == "killed"]
    assert killed == list(range(1, 33))
    assert all(not int(w[:6], 16) & (1 << 19) for w in rig.ok("\x02").split(" "))


def test_ctrl_a_stops_jogs_at_ixx15_and_closes_open_loops(rig):
    rig.ok(JOG + " #1J+ #3K")
    rig.run_for(0.3)
    t_a = rig.cmd("\x01").t_done
    w1 = int(rig.ok("#1?")[:6], 16)
    assert w1 & (1 << 12)  # abort deceleration
    rig.run_until_idle()
    assert rig.events("jog")[-1][2]["state"] == "end"
    assert int(rig.ok("#3?")[:6], 16) & (1 << 19)  # motor 3's loop closed again
    # 10 cts/ms at Ixx15 = 0.1 cts/ms² stops in 100 ms, at the next servo cycle
    k_end = rig.events("jog")[-1][0]
    assert k_end == rig.cyc(rig.c.scheduler.servo_at_or_after(t_a + 0.1))
    assert rig.events("motor")[-1][2] == {"motor": 3, "state": "closed_loop"}


def test_ctrl_q_quits_programs_and_ctrl_d_disables_plcs(rig):
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.ok("TM100 X1 X2 X3 X4 X5")
    rig.ok("CLOSE &1R")
    rig.ok("OPEN PLC 3 CLEAR P1=P1+1 CLOSE ENABLE PLC 3")
    rig.run_for(0.05)
    rig.ok("\x11\x04")
    rig.run_until_idle()
    assert rig.events("program")[-1][2]["state"] == "stopped"
    assert rig.events("plc")[-1][2] == {"plc": 3, "state": "disabled"}


def test_a_control_character_in_the_middle_of_a_line_acts_first(rig):
    reply = rig.cmd("#5\x02K")
    assert reply.error is None
    first = reply.reply.split(" ")
    assert not int(first[4][:6], 16) & (1 << 18)  # reported before the K ran
    assert int(rig.ok("#5?")[:6], 16) & (1 << 18)


def test_an_unknown_control_character_answers_err003_changes_nothing_and_the_port_goes_on(rig):
    n = len(rig.c.log.events())
    assert rig.cmd("\x1a#1K").error == "ERR003"
    assert rig.c.log.events()[n:] == []
    assert rig.ok("#1?") == rig.ok("#2?")
    assert rig.ok("I10") == "3713707"


@pytest.mark.parametrize("start", ["R", "S"])
def test_after_ctrl_k_the_cs_is_at_rest_and_r_runs_the_next_lines(rig, start):
    """After CTRL-K (TUM p319) nothing of the killed run is left: ``??`` word 1 shows no
    running / single-step / continuous-motion bits (only the TM-mode bit 3), and, with the
    motors re-enabled (``J/``), an ``R`` calculates and runs new lines, including one in the
    I11 delay before the first move (I11 = 50)."""
    rig.ok("I11=50")
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM1000 TA10 TS0 X1", "X2", "X3"])
    rig.ok(start)
    rig.run_for(0.3)
    rig.ok("\x0b")
    assert int(rig.ok("??")[:6], 16) == 1 << 3
    rig.ok("#1J/")
    rig.c.load_lines(1, ["TM100 X5"])
    rig.ok("R")
    rig.run_until_idle()
    assert rig.c.positions(1)["X"] == pytest.approx(5.0)
