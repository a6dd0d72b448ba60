' Homing routine: axis 0 to its datum switch (input 5, DATUM(4)), axis 1 to the encoder
' Z mark (DATUM(1)), then both given their machine coordinates with DEFPOS.
' Own test program (issue 22), after real datuming programs of Trio users.
BASE(0)
UNITS=100 : SPEED=50 : ACCEL=500 : DECEL=500 : CREEP=2
DATUM_IN=5
BASE(1)
UNITS=100 : CREEP=4 : ACCEL=500 : DECEL=500
VR(10)=0
BASE(0)
DATUM(4)
DATUM(1) AXIS(1)
WAIT IDLE AXIS(0)
WAIT IDLE AXIS(1)
IF AXISSTATUS AXIS(0) <> 0 OR MOTION_ERROR <> 0 THEN
  VR(10)=-1
  STOP
ENDIF
BASE(0,1)
DEFPOS(-10,25)
WAIT UNTIL OFFPOS AXIS(0)=0 AND OFFPOS AXIS(1)=0
MOVEABS(0,0)
WAIT IDLE
VR(11)=DPOS AXIS(0)
VR(12)=DPOS AXIS(1)
VR(10)=1
PRINT "homed ";VR(11);" ";VR(12)
