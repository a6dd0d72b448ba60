' Continuous-path feeder: streams the XY points VR(100), VR(101), VR(102) ... (VR(0) of
' them) as interpolated MOVEABS on BASE(0,1) with MERGE on. A move is issued only while NTYPE
' is free and the process buffer empty (PMOVE=0: a move waiting there for the servo interrupt
' is not in NTYPE yet), so NTYPE is refilled as soon as it is pulled into MTYPE, the path never
' stops, and the program never waits at a move line. VR(1) counts the passes it did other work.
' With no inputs (VR(0) = 0, as on a fresh controller) it streams a demonstration path: the
' corners and mid-points of a 200 x 200 square, back to the start.
IF VR(0)=0 THEN
  VR(0)=8
  VR(100)=100
  VR(101)=0
  VR(102)=200
  VR(103)=0
  VR(104)=200
  VR(105)=100
  VR(106)=200
  VR(107)=200
  VR(108)=100
  VR(109)=200
  VR(110)=0
  VR(111)=200
  VR(112)=0
  VR(113)=100
  VR(114)=0
  VR(115)=0
  PRINT "no VR inputs: demonstration path of 8 points"
ENDIF
BASE(0,1)
MERGE=ON
n=0
spins=0
WHILE n < VR(0)
  IF NTYPE=0 AND PMOVE=0 THEN
    MOVEABS(VR(100+2*n), VR(101+2*n))
    n=n+1
  ELSE
    spins=spins+1
  ENDIF
WEND
WAIT IDLE
VR(1)=spins
