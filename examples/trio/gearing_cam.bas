' Electronic gearing and cams on a conveyor. Axis 0 is the conveyor (the master); axis 1 a
' roller geared to it 1:2 (CONNECT); axis 2 a cutter whose profile TABLE(0..4) runs over the
' first 200 units of conveyor travel (CAMBOX); then axis 3 runs the same profile in time
' (CAM over 50 units at its SPEED). Each link is loaded before the conveyor starts.
TABLE(0, 0, 10, 40, 90, 100)
CONNECT(0.5, 0) AXIS(1)
CAMBOX(0, 4, 1, 200, 0) AXIS(2)
MOVE(400) AXIS(0)
WAIT IDLE AXIS(0)
VR(1)=DPOS AXIS(1)
CANCEL AXIS(1)
WAIT IDLE AXIS(1)
CAM(0, 4, 1, 50) AXIS(3)
WAIT IDLE AXIS(3)
PRINT "roller ";VR(1)[1];" cutter ";DPOS AXIS(2)[1];" cam ";DPOS AXIS(3)[1]
