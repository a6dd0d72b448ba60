"""Real PLC programs over the PMAC Ethernet port (spec pmac.md §12.2-12.5, §12.8; TSRM p176).

A homing PLC generated at test time by Diamond's ``pmac-motorhome`` and a set of our own PLCs
and set-up lines (shaped like Diamond's ``.pmc`` files: macros, ``ADDRESS&``, ``CMD``, range
assignments, ``MSR``, timers, compiled PLCs, axis definitions) go through Diamond's
preprocessor (``dls_pmaclib.dls_pmcpreprocessor``) and ``dls-pmaclib`` to ``motionsim serve``
one line at a time, as a beamline download does. No line is refused; the programs run on the
virtual clock and the event log shows their timer waits taking their programmed time, to the
servo cycle.
"""

from __future__ import annotations

import math
from pathlib import Path

import httpx

from tests.integration.pmaclib_wire import download, send
from tests.integration.test_clients_pmac import free_port, motionsim_serve


def setup_lines(motors: range) -> list[str]:
    """A Geo Brick set-up as a beamline's base file writes it: the motor status M-variables
    the homing PLCs test (Delta Tau's suggested definitions, TSRM p281-287)."""
    out = ["I5=2"]
    for m in motors:
        y = 0xC0 + 0x80 * (m - 1)
        d = 0x8B + 0x80 * (m - 1)
        out += [f"M{m}30->Y:${y:06X},11,1", f"M{m}40->Y:${y:06X},0,1",
                f"M{m}42->Y:${y:06X},2,1", f"M{m}45->Y:${y:06X},10,1", f"M{m}62->D:${d:06X}"]
    return out


def _values(port: int, names: list[str]) -> list[float]:
    return [float(r[0].strip("\r\x06")) for r in send(port, names)]


def _preprocessed(path: Path) -> list[str]:
    from dls_pmaclib.dls_pmcpreprocessor import ClsPmacParser

    return [line.strip() for line in ClsPmacParser().parse(str(path)) if line.strip()]


def _until(http: str, event: dict, timeout_s: float = 60) -> dict | None:
    r = httpx.post(http + "/clock/run-until", timeout=120,
                   json={"event": event, "timeout_s": timeout_s})
    return r.json()["matched"]


def _events(http: str, *types: str) -> list[dict]:
    return httpx.get(http + "/events", timeout=5,
                     params={"type": list(types)}).json()["events"]


def _homing_plc(tmp_path: Path, sequence: str = "home_home") -> Path:
    from pmac_motorhome import sequences
    from pmac_motorhome.commands import group, motor, plc
    from pmac_motorhome.constants import ControllerType

    home = getattr(sequences, sequence)
    out = tmp_path / "PLC11_HM.pmc"
    with plc(plc_num=11, controller=ControllerType.brick, filepath=out, timeout=20000):
        with group(group_num=2):
            motor(axis=1)
            motor(axis=2)
            home()
        with group(group_num=3):
            motor(axis=3)
            home()
    return out


def test_tsrm_p176_a_motorhome_homing_plc_completes_with_its_timer_waits_timed(
    tmp_path: Path,
) -> None:
    lines = _preprocessed(_homing_plc(tmp_path))
    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        http = svc.http + "/controllers/pmac"
        download(pmac_port, setup_lines(range(1, 4)) + lines)
        (i10,) = _values(pmac_port, ["I10"])
        download(pmac_port, ["P1102=1", "ENABLE PLC11"])  # HomingGroup 1: every group
        assert _until(http, {"type": "plc", "plc": 11, "state": "disabled"}) is not None
        status = _values(pmac_port, ["P1101", "P1100", "M145", "M245", "M345"])
        events = _events(http, "timer", "jog", "home", "plc")

    period = i10 / 8388608 / 1000  # I10 in 1/8388608 ms
    def cyc(e: dict) -> int:
        return round(e["t"] / period)

    assert status == [0, 7, 1, 1, 1]  # StatusDone, StateDone, home complete on every motor
    timers = [e for e in events if e["type"] == "timer"]
    assert {e["var"] for e in timers} == {"I5612"}  # i(5111+(11&30)*50+11%2): PLC 11's own
    small = round(20 * 8388608 / i10)  # "timer = 20 MilliSeconds" in servo cycles
    # per group: the 20 ms wait, then the time-out timer written right when it ran out
    assert [e["value"] for e in timers] == [small, round(20000 * 8388608 / i10)] * 2
    for start, after in ((timers[0], timers[1]), (timers[2], timers[3])):
        assert cyc(after) - cyc(start) == small
    homes = [(e["motor"], e["state"]) for e in events if e["type"] == "home"]
    assert homes == [(1, "triggered"), (2, "triggered"), (3, "triggered")]
    hm_end = [e for e in events if e["type"] == "jog" and e["command"] == "HM"
              and e["state"] == "end"]
    # group 3 starts after group 2's motors are in position; the PLC ends after motor 3
    assert cyc(timers[2]) >= max(cyc(e) for e in hm_end if e["motor"] in (1, 2))
    done = [e for e in events if e["type"] == "plc" and e["state"] == "disabled"]
    assert cyc(done[-1]) - cyc(hm_end[-1]) <= 2


def test_psrm_p241_a_home_switch_homing_plc_runs_its_jogs_until_trigger(tmp_path: Path) -> None:
    """motorhome's ``home_hsw``: each phase jogs ``J^*^0`` by the Mxx72 distance it wrote
    (away from home, towards it, away again) until a trigger, then ``HM``. Every one of those
    jogs must really move and trigger (none may end at its 10^8-count target), and the PLC
    completes with home complete on every motor."""
    lines = _preprocessed(_homing_plc(tmp_path, "home_hsw"))
    mxx72 = [f"M{m}72->L:${0xD7 + 0x80 * (m - 1):06X}" for m in range(1, 4)]  # Delta Tau's
    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        http = svc.http + "/controllers/pmac"
        download(pmac_port, setup_lines(range(1, 4)) + mxx72 + lines)
        (i123,) = _values(pmac_port, ["I123"])
        download(pmac_port, ["P1102=1", "ENABLE PLC11"])
        assert _until(http, {"type": "plc", "plc": 11, "state": "disabled"}, 300) is not None
        status = _values(pmac_port, ["P1101", "P1100", "M145", "M245", "M345"])
        events = _events(http, "jog", "home")

    assert status == [0, 7, 1, 1, 1]
    for m in (1, 2, 3):
        mine = [e for e in events if e["motor"] == m]
        jogs = [e for e in mine if e["type"] == "jog" and e["command"] == "J^"]
        starts = [e for e in jogs if e["state"] == "start"]
        triggers = [e for e in jogs if e["state"] == "triggered"]
        assert len(starts) == len(triggers) == 3  # pre-home move, fast search, away again
        # away from home (against I123's sign), then towards it, then away again
        assert [math.copysign(1, t["position"] - s["position"]) for s, t in
                zip(starts, triggers, strict=True)] == [-math.copysign(1, i123),
                                                         math.copysign(1, i123),
                                                         -math.copysign(1, i123)]
        assert all(abs(e["position"]) < 1e6 for e in jogs)  # stopped at the trigger
        assert [e["state"] for e in mine if e["type"] == "home"] == ["triggered"]


OWN_PMC = """\
; start-up, protection and readback PLCs in the shape of a beamline's .pmc files
#define Timer        I5111
#define Ms           * 8388608/I10
#define Ticks        P1000
#define Done         P1001
#define Station      P1002
#define Coord        3
#define Axis1        P(4700+1)

CLOSE
UNDEFINE ALL
&Coord #6->-29.1X+100000Y
&Coord #7->2000Z-6000
#4->I
i5213,15,100=10
&2 Q70..99=3540
MS0,I910=4
MS $$$1
MSSAVE0
HOMEZ2,3

OPEN PLC 1 CLEAR
DISABLE PLC 2..31
Ticks = 0
ENABLE PLC 6
ADDRESS&Coord
Q77 = 7.5
Timer = 50 Ms
While (Timer > 0)
    Ticks = Ticks + 1
End While
If (Ticks > 10 and Ticks < 200)
or (Ticks = 0)
    Done = 1
Else
    Done = 2
EndIf
SEND"STARTED"
DISPLC1
CLOSE

OPEN PLC 6 CLEAR
MSR0,i910,Station
Axis1 = Station * 2
I(5011+100*Coord) = 1000
Q(70+Station) = Q(70+Station) + 1
M(33) = 1
IF (P1004 = 0)
    P1004 = 1
    CMD"#1J=100"
EndIf
COMMAND"&3 P1010=Q77"
SENDS"PLC6 SCAN"
IF (Done > 0 AND P1003 = 0)
    P1003 = 1
    CMD^D
ENDI
CLOSE

OPEN PLCC 5 CLEAR
P1020 = P1020 + 1
IF (P1020 > 99)
    DISABLE PLCC 5
ENDIF
CLOSE

OPEN PROG 20 CLEAR
ABS(X,Y) INC(Z)
LINEAR FRAX(X) TA20 TS0 F10
X1 Y1
CLOSE
"""


def test_spec_12_own_plcs_with_every_construct_load_without_a_refused_line_and_run(
    tmp_path: Path,
) -> None:
    src = tmp_path / "own.pmc"
    src.write_text(OWN_PMC)
    lines = _preprocessed(src)
    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        http = svc.http + "/controllers/pmac"
        download(pmac_port, lines)
        listing = send(pmac_port, ["&3 #6->", "&3 #7->", "&3 #4->", "I6613", "&2 Q99",
                                    "MS0,I910"])
        download(pmac_port, ["I5=2", "#1$", "ENABLE PLCC 5", "ENABLE PLC 1"])
        assert _until(http, {"type": "plc", "plc": 6, "state": "disabled"}) is not None
        values = _values(pmac_port, ["P1001", "P4701", "I5311", "&3 Q77", "&1 Q74",
                                     "P1010", "P1020", "M33"])
        events = _events(http, "plc", "plc_send", "timer", "jog")

    assert [r[0].strip("\r\x06") for r in listing] == [
        "-29.1X+100000Y", "2000Z-6000", "I", "10", "3540", "4"]
    done, axis1, i5311, q77, q74, p1010, p1020, m33 = values
    assert (done, axis1, q77, p1010, p1020, m33) == (1, 8, 7.5, 7.5, 100, 1)
    assert q74 >= 1 and q74 == int(q74)  # Q(70+4) of CS 1 (PLC 6 has no ADDRESS), per scan
    assert i5311 < 1000  # I(5011+100*3) = CS 3's timer 1, counting down
    sends = [(e["plc"], e["port"], e["text"]) for e in events if e["type"] == "plc_send"]
    assert (1, "host", "STARTED") in sends and (6, "S", "PLC6 SCAN") in sends
    states = [(e["plc"], e["state"], e.get("compiled", False)) for e in events
              if e["type"] == "plc"]
    # PLC 1 enables PLC 6 and ends itself; PLC 6's CMD^D disables every PLC (and PLCC 5
    # stops itself after 100 scans)
    assert states[:3] == [(5, "enabled", True), (1, "enabled", False), (6, "enabled", False)]
    assert (1, "disabled", False) in states and (6, "disabled", False) in states
    assert (5, "disabled", True) in states
    jogs = [(e["state"], e["command"]) for e in events if e["type"] == "jog" and e["motor"] == 1]
    assert jogs[:1] == [("start", "J=")]  # the one-shot CMD"#1J=100"


def test_tsrm_p470_a_plc_send_line_reaches_the_dls_pmaclib_client_that_enabled_it() -> None:
    """PSRM p347: the line goes to the active response port — here the dls-pmaclib
    connection whose ``ENA PLC`` ran last. With I64=0 (no ``<STX>``) the Ethernet
    GETRESPONSE returns it ahead of the next command's reply, up to that reply's ACK; the
    REST terminal's ``output`` and the event log carry it too."""
    pmac_port = free_port()
    plc = ["I5=2", "I64=0", "OPEN PLC 9 CLEAR", "P9=P9+1", "IF (P9=2)", 'SEND"AXIS 3 HOMED"',
           "DIS PLC 9", "ENDIF", "CLOSE"]
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        http = svc.http + "/controllers/pmac"
        replies = [r[0] for r in send(pmac_port, [*plc, "ENA PLC 9", "P9", "P9", "P9"])]
        after = replies[-3:]
        carrying = [r for r in after if r.startswith("AXIS 3 HOMED\r")]
        assert len(carrying) == 1 and "".join(after).count("HOMED") == 1
        assert all(r.removeprefix("AXIS 3 HOMED\r") in ("1\r\x06", "2\r\x06") for r in after)
        (event,) = _events(http, "plc_send")
        assert (event["plc"], event["port"], event["text"]) == (9, "host", "AXIS 3 HOMED")
        r = httpx.post(http + "/terminal", json={"command": "P9"}, timeout=5).json()
        assert r["output"] == ["AXIS 3 HOMED"]
