"""A host downloads motion programs written with every control-flow construct over the PMAC
Ethernet port, as a beamline download does: Diamond's ``.pmc`` preprocessor
(``dls_pmaclib.dls_pmcpreprocessor``) expands the macros, ``dls-pmaclib`` sends the lines one
by one to ``motionsim serve``. No line is refused; the programs run on the virtual clock and
the event log shows what the manuals say (spec pmac.md §12.1: TUM p252 conditions, p341 the
double jump-back; PSRM p313, p357; TSRM p416 CALL, p466 READ, p182 BLOCKSTART; PUM p216
WAIT). The programs are ours, shaped like the trajectory scan: a double-buffered point loop
of nested WHILEs, GOSUBs to a move routine and to a routine chosen by a variable."""

from __future__ import annotations

from pathlib import Path

import httpx

from tests.integration.pmaclib_wire import download, send
from tests.integration.test_clients_pmac import free_port, motionsim_serve

SCAN_PMC = """\
; a point scan in two buffers of three points, then a CALL with arguments
#define Points   P401
#define Index    P402
#define Buffer   P403
#define Status   P404
#define Abort    P405
#define Routine  P406
#define Hits     P407
#define Moves    P408
#define Flag     P409
#define Case     P420

Close
Del Gat

Open Program 13
Clear
O100 READ(X,T)                      ; CALL13.001 enters here
    If (Q100 & 8388608 > 0) TM(Q120) X(Q124)
    Else DWELL 10
    Moves = Moves + 1
Return
Close

Open Program 12
Clear
Abs
Linear
TA10 TS0 TM50
Status = 1
Abort = 0
Hits = 0
Moves = 0
Routine = 1
GoSub200                            ; reset the counters
While (Abort = 0 and Points < 6)
    Index = 0
    While (Abort = 0 and Index < 3)
        GoSub210                    ; one point
        Index = Index + 1
    End While
    If (Buffer = 0)
        Buffer = 1
        Routine = 2
    Else
        Buffer = 0
        Routine = 1
    EndIf
EndW
If (Points !< 6 AND Abort = 0) Status = 2
Else Status = 3
CALL13.001 X(-5) T40                ; the last move, by a subprogram that READs it
Case = 3
GOTO (Case * 10)
N10 Status = 10
N20 Hits = Hits + 100
N30 Hits = Hits + 1000
Dwell 0
Return

N200
    Points = 0
    Buffer = 0
RET

N210
    TM(50) X(Points * 10)
    Points = Points + 1
    GoSub(Routine)
Return

N1 Hits = Hits + 1
Return
O2 Hits = Hits + 10
RET
Close

Open Program 14
Clear
Flag = 0
P430 = 2.5
P431 = 0
IF (P430 ~ 3 AND P430 !~ 5) P431 = P431 + 1
IF (P430 != 2 OR P430 = 2) P431 = P431 + 10
IF (P430 !> 2.5 AND P430 > 2 AND P430 < 3 OR P430 = 7) P431 = P431 + 100
WHILE (Flag = 0) WAIT
BLOCKSTART
TM 20 Y1
Y2
BLOCKSTOP
STOP
Y3
Close
"""

def _preprocessed(tmp_path: Path) -> list[str]:
    from dls_pmaclib.dls_pmcpreprocessor import ClsPmacParser

    src = tmp_path / "scan.pmc"
    src.write_text(SCAN_PMC)
    lines = ClsPmacParser().parse(str(src))
    return [line.strip() for line in lines if line.strip()]


def _until(http: str, event: dict, timeout_s: float = 20) -> dict | None:
    r = httpx.post(http + "/clock/run-until", timeout=60,
                   json={"event": event, "timeout_s": timeout_s})
    return r.json()["matched"]


def _events(http: str, *types: str) -> list[dict]:
    return httpx.get(http + "/events", timeout=5,
                     params={"type": list(types)}).json()["events"]


def test_spec_12_1_every_control_flow_construct_downloads_over_the_wire_and_runs(
    tmp_path: Path,
) -> None:
    lines = _preprocessed(tmp_path)
    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        http = svc.http + "/controllers/pmac"
        download(pmac_port, lines, timeout_s=120)
        assert send(pmac_port, ["&1 B12 R"], timeout_s=120)[0][1]
        assert _until(http, {"type": "program", "state": "stopped"}) is not None
        values = send(pmac_port, ["P404", "P407", "P408", "P401", "Q124", "Q120", "Q100"],
                      timeout_s=120)
        moves = _events(http, "move_start", "move_end")

        send(pmac_port, ["&1 B14 R"], timeout_s=120)
        assert _until(http, {"type": "move_start"}, timeout_s=0.5) is None  # WAIT loop
        status = send(pmac_port, ["&1 ??"], timeout_s=120)[0][0]
        assert status[5] in "13579BDF"  # word 1 bit 0: running
        send(pmac_port, ["P409=1"], timeout_s=120)
        assert _until(http, {"type": "program", "state": "stopped"}) is not None
        p14 = send(pmac_port, ["P431", "&1 PC"], timeout_s=120)
        send(pmac_port, ["&1 R"], timeout_s=120)
        assert _until(http, {"type": "program", "state": "stopped"}) is not None
        y_moves = [e for e in _events(http, "move_start") if e["t"] > moves[-1]["t"]]

    as_float = [float(r[0].strip("\r\x06")) for r in values]
    # Status 2, Hits 1 x 3 + 10 x 3 + 1000 (GOTO 30 skips N10 and N20), one READ move,
    # six points, READ: X -> Q124, T -> Q120, Q100 bits 23 (X) and 19 (T)
    assert as_float == [2, 1033, 1, 6, -5, 40, (1 << 23) | (1 << 19)]
    starts = [e for e in moves if e["type"] == "move_start"]
    ends = [e for e in moves if e["type"] == "move_end"]
    assert len(starts) == 7 + 1  # six points, the READ move, the final DWELL 0
    # TUM p341: inside the inner loop one ENDWHILE between moves — the moves blend; after
    # the 3rd point the inner End While and the outer EndW are two jumps back — it stops.
    assert ends[0]["t"] == starts[1]["t"]
    assert ends[2]["t"] < starts[3]["t"]
    assert p14[0][0].strip("\r\x06") == "111"
    assert p14[1][0].startswith("P14:")
    assert len(y_moves) == 3  # Y1 and Y2 before the STOP, then Y3 after R
