' README "Check a program without a card": motionsim check examples/trio/check_me.bas
BASE(0)
MOVE(10)
IF IN(3) THEN
  MOVE(5
ENDIF
