"""TN20-16 reproduced row by row: the process buffer shared by two axes holds axis 0 up.

Timing (conftest): one statement = 100 µs; a short move (VR(n) = 10) takes 20 servo periods,
a long one (VR(100+n) = 200) 210. The program lines are 1 ``FOR``, 2 ``MOVE(VR(n)) AXIS(0)``,
3 ``MOVE(VR(100+n)) AXIS(1)``, 4 ``NEXT`` (after the three comment lines of the example file).
"""

from __future__ import annotations

from pathlib import Path

from tests.sim.trio.conftest import cycle, fields, make, run_to

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "trio"
BLOCKING = (EXAMPLES / "tn20_blocking.bas").read_text()
FIX = (EXAMPLES / "tn20_fix.bas").read_text()
L_MOVE, L_AXIS0, L_AXIS1 = 4, 5, 6  # source lines of FOR and the two moves


def tn20(program: str):
    c = make()
    for n in range(1, 51):
        c.set_variable(f"VR({n})", 10)
        c.set_variable(f"VR({100 + n})", 200)
    c.store_program("TN20", program)
    c.run_program("TN20", 1)
    return c


def state(c) -> dict:
    a0, a1 = c.axis(0), c.axis(1)
    proc = c.processes()[0]
    return {
        "axis0": (a0["mtype"], a0["ntype"]),
        "axis1": (a1["mtype"], a1["ntype"]),
        "pmove": proc["pmove"],
        "process": proc["state"],
    }


def test_tn20_table_row_by_row():
    """Each move first enters the process buffer and is transferred at the next servo
    interrupt (M206-320), so the program also waits briefly when it issues two moves within
    one servo period; the TN20 rows then follow one per servo period."""
    c = tn20(BLOCKING)
    # MOVE(VR(1)) AXIS(0) at 0.1 ms: in the process buffer until the interrupt at 1 ms
    run_to(c, 0.00015)
    assert state(c) == {"axis0": (0, 0), "axis1": (0, 0), "pmove": 1, "process": "running"}
    # "MOVE(VR(1)) in MTYPE"; MOVE(VR(101)) AXIS(1) took the freed process buffer
    run_to(c, 0.0011)
    assert state(c) == {"axis0": (1, 0), "axis1": (0, 0), "pmove": 1, "process": "running"}
    # "MOVE(VR(101)) in MTYPE"
    run_to(c, 0.0021)
    assert state(c)["axis1"] == (1, 0)
    # "MOVE(VR(2)) in NTYPE"
    run_to(c, 0.0031)
    assert state(c)["axis0"] == (1, 1)
    # "MOVE(VR(102)) in NTYPE"; "MOVE(VR(3)) in PROCESS BUFFER"
    run_to(c, 0.00405)
    assert state(c) == {"axis0": (1, 1), "axis1": (1, 1), "pmove": 1, "process": "running"}
    # MOVE(VR(103)) AXIS(1): "waits at this line for MOVE(VR(1)) to finish"
    run_to(c, 0.0042)
    assert state(c)["process"] == "blocked"
    assert c.processes()[0]["blocked_on"] == "MOVE(VR(100+n)) AXIS(1)"
    assert c.processes()[0]["line"] == L_AXIS1
    # "MOVE(VR(1)) finishes": VR(2) in MTYPE, VR(3) in NTYPE, VR(103) in the process buffer
    run_to(c, 0.0231)
    assert state(c)["axis0"] == (1, 1)
    assert c.axis(0)["endmove"] == 20.0  # VR(2) executing: 10 + 10
    assert state(c)["pmove"] == 1
    # MOVE(VR(4)) AXIS(0): "waits at this line for MOVE(VR(101)) to finish"
    run_to(c, 0.0235)
    assert state(c)["process"] == "blocked"
    assert c.processes()[0]["line"] == L_AXIS0
    # "MOVE(VR(2)) finishes": VR(3) in MTYPE, IDLE in NTYPE; still waiting
    run_to(c, 0.0435)
    assert state(c)["axis0"] == (1, 0)
    assert c.axis(0)["endmove"] == 30.0
    assert state(c)["process"] == "blocked"
    # "MOVE(VR(3)) finishes": IDLE in MTYPE, IDLE in NTYPE — "AXIS(0) has now stopped!"
    run_to(c, 0.0635)
    assert state(c)["axis0"] == (0, 0)
    assert c.axis(0)["dpos"] == 30.0
    assert state(c)["axis1"] == (1, 1)  # VR(101) still running, VR(102) next
    assert state(c)["process"] == "blocked"
    # "MOVE(VR(101)) finishes" (at 212): VR(102) executing, VR(103) next, VR(4) in the
    # process buffer; one interrupt later VR(4) is in MTYPE of axis 0
    run_to(c, 0.2145)
    assert state(c) == {"axis0": (0, 0), "axis1": (1, 1), "pmove": 1, "process": "blocked"}
    run_to(c, 0.2155)
    assert state(c)["axis0"] == (1, 0)
    assert c.axis(0)["endmove"] == 40.0


def test_tn20_axis0_stops_and_resumes_on_the_servo_periods():
    c = tn20(BLOCKING)
    run_to(c, 0.3)
    starts = [cycle(c, t) for t, _ in fields(c, "move_start", axis=0)]
    ends = [cycle(c, t) for t, _ in fields(c, "move_end", axis=0)]
    # VR(1) starts at the first servo period after it was issued; each later move starts in
    # the servo period after its predecessor ended.
    assert starts[:4] == [1, 22, 43, 215]
    assert ends[:3] == [21, 42, 63]
    idle = [cycle(c, t) for t, f in fields(c, "axis", axis=0, mtype=0, ntype=0)]
    assert idle[0] == 63  # AXIS(0) has now stopped!
    # VR(101) ends at 212; VR(102) loads at 213; VR(103) leaves the process buffer at 214,
    # where the waiting MOVE(VR(4)) AXIS(0) is buffered; it reaches axis 0 at 215.
    assert [cycle(c, t) for t, _ in fields(c, "move_end", axis=1)][:1] == [212]
    pb = [(cycle(c, t), f["axis"], f["mtype"]) for t, f in fields(c, "process_buffer")
          if 0.005 < t < 0.216]
    assert pb == [(23, 0, 0), (23, 1, 1), (214, 1, 0), (214, 0, 1), (215, 0, 0), (215, 1, 1)]


def test_tn20_process_waits_at_the_two_lines_of_the_note():
    """Beside the one-period waits for the transfer, the program waits at the two lines of
    the note: at MOVE(VR(103)) until VR(1) ends, at MOVE(VR(4)) until VR(101) ends."""
    c = tn20(BLOCKING)
    run_to(c, 0.22)
    procs = [(round(t, 7), f["state"], f.get("blocked_on"), f["line"])
             for t, f in fields(c, "process", process=1)]
    long_waits = [
        (a[0], a[2], a[3], b[0]) for a, b in zip(procs, procs[1:], strict=False)
        if a[1] == "blocked" and b[0] - a[0] > c.clock.period_s
    ]
    assert long_waits == [
        (0.0041, "MOVE(VR(100+n)) AXIS(1)", L_AXIS1, 0.023),
        (0.0232, "MOVE(VR(n)) AXIS(0)", L_AXIS0, 0.214),
    ]
    assert procs[:3] == [
        (0.0, "running", None, L_MOVE),
        (0.0002, "blocked", "MOVE(VR(100+n)) AXIS(1)", L_AXIS1),  # VR(1) not yet transferred
        (0.001, "running", None, L_AXIS1),
    ]


def test_tn20_fix_never_waits_for_a_move_to_end():
    """The guarded program only ever waits for the servo interrupt that empties its process
    buffer (at most one servo period), never for a move to finish."""
    c = tn20(FIX)
    run_to(c, 0.5)
    procs = [(t, f["state"]) for t, f in fields(c, "process", process=1)]
    waits = [b[0] - a[0] for a, b in zip(procs, procs[1:], strict=False) if a[1] == "blocked"]
    assert waits and max(waits) <= c.clock.period_s + 1e-12
    assert c.processes()[0]["state"] == "stopped"
    assert "error" not in c.processes()[0]
    # NTYPE does not show a move still in the process buffer, so the guard let a third
    # axis-1 move through at 3.4 ms: it waits in the process buffer until NTYPE frees
    pb = [(round(t * 1e3, 1), f["axis"], f["mtype"]) for t, f in fields(c, "process_buffer")]
    assert pb[-2:] == [(4.0, 1, 1), (214.0, 1, 0)]


def test_tn20_fix_skips_the_moves_it_finds_ntype_busy_for():
    """The note's solution as printed: ``n`` counts on when NTYPE is busy, so the FOR loop is
    over in 18.3 ms and only the moves issued while NTYPE was free run — two on axis 0 and
    three on axis 1 (the third slipped through while the second still sat in the process
    buffer, which NTYPE does not show), not 50 each."""
    c = tn20(FIX)
    run_to(c, 1.0)
    states = [(round(t, 4), f["state"]) for t, f in fields(c, "process", process=1)]
    assert states[-1] == (0.0183, "stopped")
    assert "error" not in c.processes()[0]
    assert _runs(c, 0) == [(1, 21), (22, 42)]
    assert _runs(c, 1) == [(2, 212), (213, 423), (424, 634)]
    assert (c.axis(0)["dpos"], c.axis(1)["dpos"]) == (20.0, 600.0)


#: The note's test of NTYPE, with each axis's own move counter and PMOVE: a move is issued only
#: when its axis can buffer it and the process buffer is empty (a move still waiting there for
#: the servo interrupt is not yet in NTYPE, TRM p. 8-130), and no move is skipped.
FIX_WAITING = """n0=1
n1=1
WHILE n0<=6 OR n1<=6
  IF NTYPE AXIS(0)=0 AND PMOVE=0 AND n0<=6 THEN
    MOVE(VR(n0)) AXIS(0)
    n0=n0+1
  ENDIF
  IF NTYPE AXIS(1)=0 AND PMOVE=0 AND n1<=6 THEN
    MOVE(VR(100+n1)) AXIS(1)
    n1=n1+1
  ENDIF
WEND
"""


def test_testing_ntype_and_pmove_keeps_axis0_moving_while_axis1_runs_its_long_moves():
    """What the note's fix is for: axis 0 is no longer held up by axis 1. Its six short moves
    run back to back — each starts in the servo period after the previous one ended — while
    axis 1 is still in its first long move, and the process never blocks."""
    c = tn20(FIX_WAITING)
    run_to(c, 1.5)
    assert _runs(c, 0) == [(1 + 21 * i, 21 + 21 * i) for i in range(6)]
    assert _runs(c, 1) == [(2 + 211 * i, 212 + 211 * i) for i in range(6)]
    assert _runs(c, 0)[-1][1] < _runs(c, 1)[0][1]
    assert [f["state"] for _, f in fields(c, "process", process=1)] == ["running", "stopped"]


def _runs(c, axis: int) -> list[tuple[int, int]]:
    starts = [cycle(c, t) for t, _ in fields(c, "move_start", axis=axis)]
    ends = [cycle(c, t) for t, _ in fields(c, "move_end", axis=axis)]
    return list(zip(starts, ends, strict=True))


def test_tn20_fix_skips_moves_while_ntype_is_full():
    c = tn20(FIX)
    run_to(c, 0.0035)
    # axis 0: first pass MTYPE, second NTYPE, later passes skip (NTYPE busy)
    assert c.axis(0)["mtype"] == 1 and c.axis(0)["ntype"] == 1
    run_to(c, 0.0205)
    assert c.processes()[0]["state"] == "stopped"
    assert len(fields(c, "process_buffer", process=1, axis=0, mtype=1)) == 2


def test_same_program_same_log_byte_for_byte():
    a, b = tn20(BLOCKING), tn20(BLOCKING)
    run_to(a, 0.5)
    run_to(b, 0.5)
    assert a.log.to_jsonl() == b.log.to_jsonl()
