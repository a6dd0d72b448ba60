"""Our own MC4 programs written the way real Trio users write them (issue 22 "Real programs";
spec trio.md §11): an INCLUDEd initialisation of names, a start-up program that sets the axes
up and starts the machine program, a cam profile computed with PI into the TABLE and run with
CAMBOX, an error handler that stops the motion, and a host-command loop timed with TICKS and
dispatched with ON .. GOSUB. Each loads on ``mc4xx`` and runs as its code says, asserted on the
event log and the axis parameters."""

from __future__ import annotations

import math

import pytest

from tests.sim.trio.conftest import fields, make, run_to

INITIALISE = """\
'==========================================================
' machine names: inputs, outputs, axes, TABLE and VR indices
' INCLUDEd by every program, never RUN on its own
'==========================================================
estop_in = 7
run_op = 8
fault_op = 9
slave_ax = 0
master_ax = 1
spare_ax = 2
host_ax = 3
cam_points = 36
cam_table = 100
err_vr = 200
errline_vr = 201
"""

STARTUP = """\
INCLUDE "INITIALISE"
ON BASICERROR GOTO error_routine
DIM ax AS INTEGER
DIM ready AS BOOLEAN
GLOBAL "machine_state", 202
CONSTANT "edges_per_mm", 1000

machine_state = 0
FOR ax = 0 TO LAST_AXIS
  BASE(ax)
  UNITS = edges_per_mm
  SPEED = 100 : ACCEL = 10000 : DECEL = 10000
  SERVO = ON
NEXT ax
WDOG = ON
ready = IN(estop_in) = OFF
IF ready THEN
  machine_state = 1
  OP(run_op, ON)
  RUN "CAMRUN", 2
ELSE
  machine_state = 99
ENDIF
STOP

error_routine:
VR(err_vr) = RUN_ERROR
VR(errline_vr) = ERROR_LINE
OP(fault_op, ON)
"""

CAMRUN = """\
INCLUDE "INITIALISE"
ON BASICERROR GOTO error_routine
DIM i AS INTEGER
DIM profile AS STRING(16)

' a cycloidal cam: 50 mm of the slave (in encoder edges) over 100 mm of the master
FOR i = 0 TO cam_points
  angle = 2 * PI * i / cam_points
  TABLE(cam_table + i, 50 * edges_per_mm * (angle - SIN(angle)) / (2 * PI))
NEXT i
profile = "CYCLOID" + STR(cam_points, 0)
PRINT("cam ready: "); profile
BASE(slave_ax)
CAMBOX(cam_table, cam_table + cam_points, 1, 100, master_ax)
MOVE(100) AXIS(master_ax)
WAIT IDLE AXIS(master_ax)
WAIT IDLE AXIS(slave_ax)
machine_state = 2
OP(run_op, OFF)
STOP

error_routine:
IF RUN_ERROR <> 31 THEN
  VR(err_vr) = RUN_ERROR
  VR(errline_vr) = ERROR_LINE
  OP(fault_op, ON)
ENDIF
RAPIDSTOP
"""


def machine():
    c = make(model="mc4xx")
    for name, text in (("INITIALISE", INITIALISE), ("STARTUP", STARTUP), ("CAMRUN", CAMRUN)):
        c.store_program(name, text)
    return c


def test_p11_start_up_program_sets_the_axes_up_and_starts_the_cam_program():
    c = machine()
    c.run_program("STARTUP", 1)
    run_to(c, 3.0)
    for n in range(8):
        ax = c.axis(n)
        assert (ax["units"], ax["speed"], ax["accel"], ax["decel"]) == (1000, 100, 10000, 10000)
        assert c.terminal(f"? SERVO AXIS({n})").reply == "1.0000"
    starts = fields(c, "process", state="running")
    assert [(f["process"]) for _t, f in starts][:2] == [1, 2]  # STARTUP, then CAMRUN
    stopped = {f["process"]: f for _t, f in fields(c, "process", state="stopped")}
    assert "error" not in stopped[1] and "error" not in stopped[2]
    assert fields(c, "basic_error") == []
    assert c.vr[202] == 2.0  # machine_state: GLOBAL of STARTUP, written by CAMRUN
    assert c.terminal("? machine_state").reply == "2.0000"
    assert [(f["output"], f["value"]) for _t, f in fields(c, "output")] == [(8, 1), (8, 0)]
    assert c.unread_output("t") == ["cam ready: CYCLOID36"]


def test_trm_p8_19_cam_computed_with_pi_is_followed_by_cambox_over_the_master_distance():
    c = machine()
    c.run_program("STARTUP", 1)
    run_to(c, 3.0)
    table = [c.table[100 + i] for i in range(37)]
    assert table[0] == 0.0 and table[18] == pytest.approx(25000.0)
    assert table[36] == pytest.approx(50000.0)
    assert table[9] == pytest.approx(50000 * (0.25 - math.sin(math.pi / 2) / (2 * math.pi)))
    cam_start = [t for t, f in fields(c, "move_start", axis=0) if f["mtype"] == 20]
    master_start = [t for t, f in fields(c, "move_start", axis=1) if f["mtype"] == 1]
    cam_end = [t for t, f in fields(c, "move_end", axis=0) if f["mtype"] == 20]
    master_end = [t for t, f in fields(c, "move_end", axis=1) if f["mtype"] == 1]
    assert len(cam_start) == len(master_start) == len(cam_end) == len(master_end) == 1
    assert cam_start[0] <= master_start[0] and cam_end[0] == pytest.approx(master_end[0])
    assert c.axis(0)["dpos"] == pytest.approx(50.0)  # 50 000 edges at UNITS 1000
    assert c.axis(1)["dpos"] == pytest.approx(100.0)


ERRORS = """\
INCLUDE "INITIALISE"
ON BASICERROR GOTO error_routine
BASE(spare_ax)
SPEED = 10
FORWARD
WA(50)
VR(64000) = 1
PRINT "not reached"
STOP

error_routine:
IF RUN_ERROR <> 31 THEN
  VR(err_vr) = RUN_ERROR
  VR(errline_vr) = ERROR_LINE
  OP(fault_op, ON)
ENDIF
RAPIDSTOP
WAIT IDLE
PRINT "stopped after error "; RUN_ERROR[0]; " at line "; ERROR_LINE[0]
"""


def test_p11_3_error_handler_stops_the_motion_and_records_the_error():
    c = make(model="mc4xx")
    c.store_program("INITIALISE", INITIALISE)
    c.store_program("ERRORS", ERRORS)
    c.run_program("ERRORS", 4)
    run_to(c, 1.0)
    (t_err, f), = fields(c, "basic_error")
    assert (f["process"], f["line"], f["run_error"]) == (4, 7, 1)
    assert "VR index out of range: 64000" in f["error"]  # VR(0..63999) on MC4xx (TJ2P-16)
    # INCLUDE costs nothing; lines 2-5 take 100 µs each, WA(50) 50 ms, then line 7 fails
    assert t_err == pytest.approx(4 * 100e-6 + 0.050 + 100e-6)
    (t_fault, out), = fields(c, "output")
    assert out["output"] == 9 and t_fault > t_err
    (t_end, end), = fields(c, "move_end", axis=2)
    assert end["mtype"] == 10 and t_end >= t_fault  # FORWARD cancelled by RAPIDSTOP
    assert (c.vr[200], c.vr[201]) == (1.0, 7.0)
    assert c.axis(2)["mtype"] in (0, None)
    assert c.unread_output("t") == ["stopped after error 1 at line 7"]
    (_t, stopped), = fields(c, "process", process=4, state="stopped")
    assert "error" not in stopped


def test_p11_3_machine_program_stopped_from_outside_sees_run_error_31_and_stops_its_axes():
    c = machine()
    c.store_program("CAMRUN", CAMRUN.replace("MOVE(100)", "MOVE(10000)"))  # a long master move
    c.run_program("STARTUP", 1)
    run_to(c, 0.5)
    assert c.terminal('STOP "CAMRUN"').error is None
    run_to(c, 1.5)
    (_t, f), = fields(c, "basic_error")
    assert f["run_error"] == 31 and f["process"] == 2
    assert c.vr[200] == 0.0 and c.vr[201] == 0.0  # 31: a normal stop, not recorded
    assert c.axis(1)["mtype"] in (0, None) and c.axis(1)["dpos"] < 100.0  # RAPIDSTOP


HOSTCMD = """\
INCLUDE "INITIALISE"
DIM cmd AS INTEGER
DIM replies AS INTEGER
TICKS = 0
REPEAT
  cmd = VR(300)
  IF cmd > 0 THEN
    ON cmd GOSUB do_move, do_cancel, do_report
    VR(300) = 0
    replies = replies + 1
  ENDIF
  WA(1)
UNTIL VR(301) = ON
VR(304) = replies
STOP

do_move:
  MOVE(VR(302)) AXIS(host_ax)
  RETURN
do_cancel:
  CANCEL AXIS(host_ax)
  RETURN
do_report:
  VR(303) = -TICKS
  VR(305) = MTYPE AXIS(host_ax).0
  RETURN
"""


def test_tj2p5_138_host_command_loop_dispatches_with_on_gosub_and_times_with_ticks():
    c = make(model="mc4xx")
    c.store_program("INITIALISE", INITIALISE)
    c.store_program("HOSTCMD", HOSTCMD)
    c.run_program("HOSTCMD", 5)
    run_to(c, 0.0105)
    c.set_variable("VR(302)", 500.0)
    c.set_variable("VR(300)", 1.0)  # move 500 units: 0.5 s at SPEED 1000
    run_to(c, 0.1005)
    c.set_variable("VR(300)", 3.0)  # report
    run_to(c, 0.2005)
    c.set_variable("VR(300)", 2.0)  # cancel
    run_to(c, 0.3005)
    c.set_variable("VR(300)", 7.0)  # out of range: no jump, the loop goes on
    run_to(c, 0.4005)
    c.set_variable("VR(301)", 1.0)
    run_to(c, 1.0)
    (t_start, f), = fields(c, "move_start", axis=3)
    assert f["mtype"] == 1 and 0.0105 < t_start < 0.014
    (t_end, _f), = fields(c, "move_end", axis=3)
    assert 0.2005 < t_end < 0.25 and c.axis(3)["dpos"] < 500.0  # cancelled
    assert c.vr[303] == pytest.approx(100.0, abs=1.5)  # TICKS counted down ~100 periods
    assert c.vr[305] == 1.0  # MTYPE 1 (MOVE) running: bit 0 set
    assert c.vr[304] == 4.0 and c.vr[300] == 0.0
    (_t, stopped), = fields(c, "process", process=5, state="stopped")
    assert "error" not in stopped
