' MC6_MACHINE.BAL: a BASIC library of helpers for every program of the machine
' (a program of FUNCTION blocks: store it before the programs that call it)

FUNCTION counts_to_mm(counts AS INTEGER, per_mm AS FLOAT) AS FLOAT
  IF per_mm = 0 THEN RETURN 0
  RETURN counts / per_mm
ENDFUNC

FUNCTION clamp(v, lo, hi AS FLOAT) AS FLOAT
  IF v < lo THEN RETURN lo
  IF v > hi THEN RETURN hi
  RETURN v
ENDFUNC

' the state word an HMI reads: bit 0 running, bits 4-7 the station, bit 8 fault
FUNCTION status_word(running AS BOOLEAN, station AS INTEGER, fault AS BOOLEAN) AS INTEGER
  DIM w AS INTEGER = 0
  IF running THEN w = w OR 1
  w = w OR ((station AND $F) << 4)
  IF fault THEN w = w OR (1 << 8)
  RETURN w
ENDFUNC

FUNCTION state_name(code AS INTEGER) AS STRING
  SELECT_CASE code
    CASE 0
      RETURN "INIT"
    CASE 1, 2
      RETURN "PREOP"
    CASE 3
      RETURN "OP"
    CASE ELSE
      RETURN "?"
  END_CASE
ENDFUNC

' the first free slot of a station table row, -1 when full
FUNCTION first_free(table_vr, slots AS INTEGER) AS INTEGER
  DIM found AS INTEGER = -1
  FOR k = 0 TO slots - 1
    IF VR(table_vr + k) = 0 THEN
      found = k
      EXIT_LOOP
    ENDIF
  NEXT k
  RETURN found
ENDFUNC
