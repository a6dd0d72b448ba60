' Pick and place: axis 0 carries the gripper along the line (X), axis 1 lifts it (Z).
' VR(0) = number of parts, VR(1) = pick position, VR(2) / VR(3) = the two drop positions
' (even parts to VR(2), odd ones to VR(3)). Each part: over the pick point, down, grip, up,
' over its drop point, down, release, up. VR(10) counts the parts placed.
' With no inputs (VR(0) = 0, as on a fresh controller) it runs a demonstration of 4 parts.
IF VR(0)=0 THEN
  VR(0)=4
  VR(1)=100
  VR(2)=300
  VR(3)=400
  PRINT "no VR inputs: demonstration with 4 parts"
ENDIF
BASE(0,1)
SPEED AXIS(0)=500
SPEED AXIS(1)=200
placed=0
FOR part=1 TO VR(0)
  GOSUB pick
  IF part MOD 2 = 0 THEN
    drop=VR(2)
  ELSE
    drop=VR(3)
  ENDIF
  GOSUB place
  placed=placed+1
  PRINT "placed part ";part[0];" at ";drop[0]
NEXT part
MOVEABS(0,0)
WAIT IDLE
VR(10)=placed
STOP

pick:
  MOVEABS(VR(1)) AXIS(0)
  WAIT IDLE AXIS(0)
  MOVEABS(-50) AXIS(1)
  WAIT IDLE AXIS(1)
  VR(20)=1 ' gripper closed
  MOVEABS(0) AXIS(1)
  WAIT IDLE AXIS(1)
RETURN

place:
  MOVEABS(drop) AXIS(0)
  WAIT IDLE AXIS(0)
  MOVEABS(-40) AXIS(1)
  WAIT IDLE AXIS(1)
  VR(20)=0 ' gripper open
  MOVEABS(0) AXIS(1)
  WAIT IDLE AXIS(1)
RETURN
