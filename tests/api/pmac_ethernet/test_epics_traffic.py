"""The EPICS ``pmac`` driver's whole recorded traffic over the PMAC Ethernet port (issue 37):
every request of one real driver connection (``epics_recording/requests.txt``,
the driver unmodified, DiamondLightSource/pmac @ 3d2e73f) answered without an error, one reply
line per item of a batched line, each in the form the driver parses
(``pmacController.cpp``, ``pmacHardwareTurbo.cpp``, ``pmacAxis.cpp``); and the driver's
trajectory scan walked to its end: the recorded ``WL:`` build into buffers at ``$30000``,
``&1E`` (``getCSEnableCommand``), ``M4034=1``, ``&1B1R``, the recorded polls until the
status word says finished.

The card holds what the recording's Geo Brick held, written here for the test (Diamond's files
are not part of motionsim): a scan program of our own laid out like
``trajectory_scan_brickette.pmc`` (variables at ``$30000``, half A at ``$30050``, 1000 points
per half: the driver requires buffers at or above ``$30000`` when ``CPU`` answers
``DSP56321``), a PROG 10 that moves CS 1's X for the driver's CS-axis move, ``#7->1000X
#8->1000Y`` in CS 1.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from motionsim.api.pmac_ethernet.protocol import VR, VR_DOWNLOAD, pack_request
from motionsim.sim.pmac.card import pmac_float

from tests.api.pmac_ethernet.test_pmac_server import Client, run

#: A copy of the recording (README.md there says how it was made).
RECORDING = Path(__file__).parent / "epics_recording"
SCAN_PROGRAM = Path(__file__).parents[3] / "examples" / "pmac" / "scan_program.pmc"


def _requests() -> list[tuple[str, str]]:
    out = []
    for line in (RECORDING / "requests.txt").read_text().splitlines():
        if line.startswith("#") or not line:
            continue
        kind, _, text = line.partition("\t")
        out.append((kind, text))
    return out


def _scan_program() -> list[str]:
    """Our scan program moved to the brickette's memory: $B8xx -> $300xx, 1000 points."""
    out = []
    for line in SCAN_PROGRAM.read_text().splitlines():
        line = line.split(";")[0].strip()
        if not line or line.startswith("DEFINE UBUFFER"):
            continue
        line = re.sub(r"\$B8([0-9A-F]{2})", r"$300\1", line)
        out.append("M4037=1000" if line == "M4037=50" else line)
    return out


SETUP = [
    "&1 #7->1000X #8->1000Y",
    *_scan_program(),
    "OPEN PROG 10", "CLEAR", "ABS", "LINEAR", "TA10", "TS0", "TM(Q70)", "X(Q77)", "CLOSE",
]

#: What the driver does with each kind of item's reply (sscanf formats of the sources).
_NUMBER = r"-?\d+(\.\d+)?"
_FORMS: list[tuple[re.Pattern[str], re.Pattern[str]]] = [
    (re.compile(r"^&\d+\?\?$"), re.compile(r"^[0-9A-F]{18}$")),  # CS status, 3 words
    (re.compile(r"^#\d+\?$"), re.compile(r"^[0-9A-F]{12}$")),  # motor status, 2 words
    (re.compile(r"^\?\?\?$"), re.compile(r"^[0-9A-F]{12}$")),  # global status
    (re.compile(r"^#\d+[PF]$"), re.compile(rf"^{_NUMBER}$")),
    (re.compile(r"^&\d+%$"), re.compile(rf"^{_NUMBER}$")),
    (re.compile(r"^&\d+#\d+->,$"), re.compile(r"^(0|I|[-+0-9.XYZABCUVW]+)$")),  # axis def
    (re.compile(r"^(&\d+)?[MPQ]\d+$", re.I), re.compile(rf"^{_NUMBER}$")),
    (re.compile(r"^i\d+24$", re.I), re.compile(r"^\$[0-9A-F]+$")),  # "$%x" (flag mode)
    # address-type I-variables answer $hex with I9 = 2 (I90, I95: the driver's "VHS" values)
    (re.compile(r"^I\d+$", re.I), re.compile(rf"^({_NUMBER}|\$[0-9A-F]+)$")),
    (re.compile(r"^cid$", re.I), re.compile(r"^\d+$")),
    (re.compile(r"^cpu$", re.I), re.compile(r"^DSP56321$")),
]


def _check_form(item: str, value: str) -> None:
    for item_re, value_re in _FORMS:
        if item_re.match(item):
            assert value_re.match(value), (item, value)
            return
    raise AssertionError(f"no reply form for item {item!r}")  # pragma: no cover


def _items(text: str) -> list[str] | None:
    """A batched poll line's items (queries only), or None for a line of commands."""
    items = text.split()
    if items and all(re.match(r"^(\?\?\?|&\d+\?\?|#\d+[P?F]|&\d+%|&\d+#\d+->,|"
                              r"(&\d+)?[MPQI]\d+|cid|cpu)$", i, re.I) for i in items):
        return items
    return None


def test_every_recorded_request_is_answered_without_error_in_the_form_the_driver_parses():
    """1 444 requests: FLUSH answers its ``@``; every GETRESPONSE ends ``\\r\\x06`` (I3=2) or is
    a bare ``\\x06``, never ``\\x07``; a batched line answers one line per item, each parsed
    as the driver parses it; ``&1 list forward,0,1`` / ``inverse`` (a CS with no kinematic
    program) answer nothing, which ends the driver's listing."""

    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("i6=1 i3=2")
        for line in SETUP:
            assert b"\x07" not in await c.ask(line), line
        seen = []
        for kind, text in _requests():
            if kind == "FLUSH":
                seen.append((kind, text, await c.send(pack_request(VR_DOWNLOAD, VR.PMAC_FLUSH),
                                                      1)))
            else:
                seen.append((kind, text, await c.ask(text)))
            handle.clock.advance(0.005)
        await c.close()
        return seen

    seen = run(scenario, kind="pmac")
    assert len(seen) == 1444
    checked, special = 0, set()
    for kind, text, reply in seen:
        assert b"\x07" not in reply, (text, reply)
        if kind == "FLUSH":
            assert reply == b"@"
            continue
        assert reply.endswith(b"\x06") and reply.count(b"\x06") == 1, (text, reply)
        lines = reply[:-1].decode().split("\r")[:-1]
        if text.startswith("I7022"):  # sscanf "%d %d $%x %lf %d" (pmacAxis::home)
            assert re.match(r"^1\r0\r\$[0-9A-F]+\r-?[\d.]+\r-?\d+\r\x06$",
                            reply.decode()), reply
            special.add(text)
        items = _items(text)
        if items is None:
            if text.lower().startswith("&1 list"):
                assert lines == [], (text, reply)
                special.add(text)
            elif text == "&1e":
                assert reply == b"\x06"
                special.add(text)
            continue
        assert len(lines) == len(items), (text, reply)
        for item, value in zip(items, lines, strict=True):
            _check_form(item, value)
            checked += 1
            if item.endswith("->,"):
                assert value == {"&1#7->,": "1000X", "&1#8->,": "1000Y"}[item]
                special.add(item)
    assert checked > 11_000
    assert special == {"&1 list forward,0,1", "&1 list inverse,0,1", "&1e",
                       "I7022 I7023 i224 i223 i226", "&1#7->,", "&1#8->,"}


def _scan_lines() -> tuple[list[str], list[str]]:
    """The recorded trajectory build (the ``WL:`` lines and fills, in order) and the poll lines
    the driver sends every fast cycle while a scan runs."""
    texts = [t for k, t in _requests() if k == "GETRESPONSE"]
    build = [t for t in texts if t.startswith("WL:") or t.startswith("M4044=")
             or t.startswith("M4036=") or t.startswith("M4045=")]
    polls = ["M4034 &1??",
             next(t for t in texts if t.startswith("#1P &1Q89")),
             next(t for t in texts if t.startswith("#6F #8F"))]
    return build, polls


def test_the_drivers_trajectory_scan_runs_to_its_end_over_the_ethernet_port():
    """TUM p246 / spec §12.7: the recorded 100-point X scan (20 ms points) built with the
    driver's own ``WL:`` lines at ``$30050`` / ``$31BA8`` / ``$33ED0``, then ``&1E``,
    ``M4034=1``, ``&1B1R``; the driver's polls see status 1 (running) while the points
    advance and then 2 (finished) with 100 points done, motor 7 at the last X point."""
    build, polls = _scan_lines()
    last_x = pmac_float.decode(int(next(t for t in build if t.startswith("WL:$31BFD"))
                                   .split(",")[-1][1:], 16))

    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("i6=1 i3=2")
        for line in SETUP:
            assert b"\x07" not in await c.ask(line), line
        adr = [await c.ask(v) for v in ("M4037", "M4041", "M4042", "M4049")]
        replies = [await c.ask(line) for line in build]
        replies += [await c.ask(line) for line in ("&1e", "M4034=1", "&1B1R")]
        statuses = []
        for _ in range(100):
            handle.clock.advance(0.1)
            got = [(await c.ask(line))[:-1].decode().split("\r")[:-1] for line in polls]
            values = dict(zip(" ".join(polls).split(), sum(got, []), strict=True))
            statuses.append((int(values["M4034"]), int(values["M4038"])))
            if statuses[-1][0] != 1:
                break
        position = await c.ask("#7P")
        await c.close()
        return adr, replies, statuses, position

    adr, replies, statuses, position = run(scenario, kind="pmac")
    assert adr == [b"1000\r\x06", b"196688\r\x06", b"215688\r\x06", b"1\r\x06"]  # $30050
    assert all(r == b"\x06" for r in replies), replies
    assert statuses[-1] == (2, 100)
    assert all(s == 1 for s, _ in statuses[:-1]) and len(statuses) > 10
    done = [n for _, n in statuses]
    assert done == sorted(done) and 0 < done[len(done) // 2] < 100
    assert float(position[:-2]) == pytest.approx(last_x * 1000, abs=0.5)
