' Flying shear: the knife (axis 0) waits out the cut length, accelerates to the web speed
' (axis 2, the measuring encoder), cuts while in step with it, slows down and returns.
' Own test program (issue 22), built from the MOVELINK rules of the MC4 help: an
' acceleration phase needs twice its distance of web, a phase in step the same distance.
BASE(0)
VR(20)=0
WHILE VR(20) < VR(21)
  MOVELINK(0,VR(22),0,0,2)
  MOVELINK(20,40,40,0,2)
  MOVELINK(40,50,0,20,2)
  WAIT LOADED
  OP(8,ON)
  MOVELINK(-60,90,30,30,2)
  WAIT LOADED
  OP(8,OFF)
  VR(20)=VR(20)+1
WEND
WAIT IDLE
PRINT "cuts ";VR(20)[0]
