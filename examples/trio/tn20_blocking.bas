' TN20-16 "Process Buffers in Motion Coordinator series 2": the program that makes
' axis 0 wait for axis 1. VR(1..50) hold short moves for axis 0, VR(101..150) long
' moves for axis 1; the process buffer is shared by both axes.
FOR n=1 TO 50
  MOVE(VR(n)) AXIS(0)
  MOVE(VR(100+n)) AXIS(1)
NEXT n
