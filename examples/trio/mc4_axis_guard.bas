' MC4xx axis guard: software limits, a following-error trip and its handler, HMI lamps.
' Own test program (issue 32): written for motionsim, after the error handlers of Trio users'
' start-up programs (MOTION_ERROR polled, ERROR_AXIS and FE_LATCH kept, DATUM(0) to clear).
' Run with a following-error model on the axis: config {"fe_lag": 0.002}.
BASE(0)
UNITS=100
SPEED=500 : ACCEL=5000 : DECEL=5000
FS_LIMIT=300 : RS_LIMIT=-10
FE_LIMIT=5 : FE_RANGE=0.5
SERVO=ON
WDOG=ON
OP(8,ON)
' a move beyond the working envelope stops at the forward limit
MOVEABS(1000)
WAIT IDLE
IF AXISSTATUS.9 = ON THEN OP(9,ON)
VR(20)=DPOS
MOVEABS(100)
WAIT IDLE
' now too fast for the servo: the following error trips the axis
FE_LIMIT=0.5
SPEED=2000
MOVEABS(250)
WAIT UNTIL MOTION_ERROR <> 0 OR IDLE
IF MOTION_ERROR <> 0 THEN
  OP(8,OFF)
  OP(10,ON)
  VR(21)=ERROR_AXIS
  VR(22)=FE_LATCH
  VR(23)=WDOG
ENDIF
' the operator presses reset on the HMI (Modbus coil 11)
WAIT UNTIL READ_OP(11) = ON
DATUM(0)
OP(10,OFF)
FE_LIMIT=5 : SPEED=500
SERVO=ON
WDOG=ON
OP(8,ON)
MOVEABS(0)
WAIT IDLE
VR(24)=DPOS
PRINT #5,"guard done, stopped at ";VR(20)[1]
