' TN20-16 solution: test NTYPE for zero before loading a new move, so the program
' never waits at a move line.
FOR n=1 TO 50
  IF NTYPE AXIS(0)=0 THEN
    MOVE(VR(n)) AXIS(0)
  ENDIF

  IF NTYPE AXIS(1)=0 THEN
    MOVE(VR(100+n)) AXIS(1)
  ENDIF
NEXT n
