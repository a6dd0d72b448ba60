' MC4xx start-up: bring the bus up, set comms, tune the drives, then enable them.
' Own test program (issue 22): written for motionsim, after the start-up programs of
' Trio users (bus state loop, per-axis gains in a FOR loop, repeat axis, watchdog last).
ETHERCAT($22,0,50)
IF VR(50) <> 3 AND CONTROL <> 400 THEN
  ETHERCAT(0,0)
  WA(100)
  ETHERCAT($22,0,50)
ENDIF
SETCOM(19200,8,1,0,1,0)
ETHERNET(1,-1,10,502)
LIMIT_BUFFERED=16
FOR ax=0 TO 2
  BASE(ax)
  UNITS=1000
  P_GAIN=0.8 : I_GAIN=0.002 : D_GAIN=3 : OV_GAIN=-1 : VFF_GAIN=12
  FE_LIMIT=2 : FE_RANGE=1
  SPEED=200 : ACCEL=2000 : DECEL=2000 : CREEP=5
  DATUM_IN=-1
  SERVO=ON
NEXT ax
BASE(2)
REP_DIST=360 : REP_OPTION=1
CLUTCH_RATE AXIS(1)=50
STEP_RATIO(-1,1) AXIS(3)
ENCODER_RATIO(4,1) AXIS(0)
IF SYSTEM_ERROR <> 0 THEN UNIT_CLEAR
WDOG=ON
VR(51)=DRIVE_STATUS AXIS(0) + FE AXIS(1) + FE_LATCH AXIS(2)
BASE(0)
PRINT #5,"start-up done, bus ";VR(50)[0];" buffered ";LIMIT_BUFFERED[0]
