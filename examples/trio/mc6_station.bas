' MC6_STATION: start-up check and an indexing station on an MC6xx (model mc6xx)
' calls the functions of the library MC6_MACHINE (store mc6_machine.bal first)
CONSTANT "ecat_vr", 59
CONSTANT "status_vr", 60
CONSTANT stations, 4
DIM tries, state AS INTEGER = 0
DIM parts AS INTEGER(4, 2)
DIM name AS STRING(8)

' wait for the EtherCAT network, at most 50 polls
ETHERCAT(0, 0)
REPEAT
  ETHERCAT($22, 0, ecat_vr)
  tries = tries + 1
  IF VR(ecat_vr) <> 3 THEN WA(10)
UNTIL VR(ecat_vr) = 3 OR tries >= 50
name = state_name(VR(ecat_vr))
PRINT "EtherCAT "; name; " with "; ETHERCAT(3, 0); " slaves"

BASE(0)
UNITS = 100 : SPEED = 500 : ACCEL = 10000 : DECEL = 10000
WHILE TRUE
  SELECT_CASE state
    CASE 0
      DEFPOS(0)
      state = 1
    CASE 1 TO stations
      MOVE(clamp(VR(10 + state), 0, 90))
      WAIT IDLE
      parts(state - 1, 0) = parts(state - 1, 0) + 1
      parts(state - 1, 1) = MPOS * UNITS
      VR(status_vr) = status_word(TRUE, state, FALSE)
      state = state + 1
    CASE ELSE
      EXIT_LOOP
  END_CASE
WEND
VR(status_vr) = status_word(FALSE, 0, FALSE)
VR(61) = counts_to_mm(parts(3, 1), 100)
VR(62) = first_free(20, 8)
PRINT "done at "; MPOS[1]
