' MERGE and SRAMP: a stream of MOVE(100) on axis 0 runs as one smooth move.
' With MERGE ON, each move that is already in NTYPE when the one in MTYPE reaches its
' ramp down is joined on at speed: only the first move ramps up, only the last ramps down.
' SRAMP (ms) makes those two ramps S-shaped; each adds SRAMP to the total time.
BASE(0)
MERGE=ON
SRAMP=5
FOR i=1 TO 5
  MOVE(100)
NEXT i
WAIT IDLE
PRINT "DPOS="; DPOS
