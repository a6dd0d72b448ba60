"""Deep nesting is an error naming the limit, never a crash (issue 33 item 1), over every entry.

The PMAC expression parser bounds nesting at ``MAX_NESTING`` (32) levels of brackets, function
calls, variable indexes and unary minus signs; level 33 is ERR003 / 422 naming the limit
(sim/pmac/language/expressions.py). A Trio line nests at most 100 levels (sim/trio/parser.py).
Each entry is tried at the limit (accepted, and the controller goes on) and one past it.
A long run of operators of one level is not nesting: thousands of terms evaluate.
"""

from __future__ import annotations

import asyncio

import pytest
from motionsim.api.pmac_ethernet.server import serve_pmac
from motionsim.api.trio_terminal.server import serve_trio
from motionsim.sim.pmac.language.expressions import MAX_NESTING as PMAC_MAX
from motionsim.sim.trio.language.parser import MAX_NESTING as TRIO_MAX

from tests.api.pmac_ethernet.test_pmac_server import Client
from tests.api.trio_terminal.test_trio_server import read_until_prompt
from tests.api.wire_helpers import connect, run_served

pytestmark = pytest.mark.anyio

P = "/controllers/p"
T = "/controllers/t"
PLAIN = {"content-type": "text/plain"}


def nested(depth: int, inner: str = "1") -> str:
    return "(" * depth + inner + ")" * depth


def test_the_documented_limits() -> None:
    assert (PMAC_MAX, TRIO_MAX) == (32, 100)


async def _terminal(api, base: str, command: str) -> dict:
    r = await api.post(f"{base}/terminal", json={"command": command})
    assert r.status_code == 200
    return r.json()


@pytest.mark.parametrize(("form", "outer"),
                         [("P1={}", 0), ("P1=SIN{}", 0), ("P(1+{})=2", 1), ("P1=-{}", 1)])
async def test_pmac_rest_terminal_limit_and_one_past(pmac_api, form, outer) -> None:
    """``outer``: levels the form adds around the brackets (the index of ``P( )``, a ``-``)."""
    ok = await _terminal(pmac_api, P, form.format(nested(PMAC_MAX - outer)))
    assert ok["error"] is None
    bad = await _terminal(pmac_api, P, form.format(nested(PMAC_MAX + 1 - outer)))
    assert bad["error"] == "ERR003"
    assert f"deeper than {PMAC_MAX} levels" in bad["detail"]
    assert (await _terminal(pmac_api, P, "P1=7 P1"))["reply"] == "7"  # still answering


async def test_pmac_unary_minus_signs_count_as_levels(pmac_api) -> None:
    assert (await _terminal(pmac_api, P, "P1=" + "-" * PMAC_MAX + "P2"))["error"] is None
    bad = await _terminal(pmac_api, P, "P1=" + "-" * (PMAC_MAX + 1) + "P2")
    assert bad["error"] == "ERR003"


@pytest.mark.parametrize("line", ["P1={}", "IF ({}>0)", "IF (P1>0 AND {}>0)"])
async def test_pmac_plc_put_limit_and_one_past(pmac_api, line) -> None:
    at = line.format(nested(PMAC_MAX - 1 if line.startswith("IF") else PMAC_MAX))
    tail = "\nP2=1\nENDIF" if line.startswith("IF") else ""
    assert (await pmac_api.put(f"{P}/plcs/1", json={"text": at + tail})).status_code == 200
    r = await pmac_api.put(f"{P}/plcs/1", json={"text": line.format(nested(10_000)) + tail})
    assert r.status_code == 422
    assert r.json()["pmac_error"] == "ERR003"
    assert f"deeper than {PMAC_MAX} levels" in r.json()["message"]
    # nothing changed: the accepted program is still the one stored
    assert (await pmac_api.get(f"{P}/plcs/1")).json()["program"][0] == at


async def test_pmac_motion_program_and_kinematics_lines(pmac_api) -> None:
    for opened in ("OPEN PROG 1 CLEAR", "&1 OPEN FORWARD CLEAR", "&1 OPEN INVERSE CLEAR"):
        assert (await _terminal(pmac_api, P, opened))["error"] is None
        assert (await _terminal(pmac_api, P, "Q7=" + nested(PMAC_MAX)))["error"] is None
        assert (await _terminal(pmac_api, P, "Q7=" + nested(PMAC_MAX + 1)))["error"] == "ERR003"
        assert (await _terminal(pmac_api, P, "CLOSE"))["error"] is None
    listing = await _terminal(pmac_api, P, "&1 LIST FORWARD")
    assert listing["reply"].split("\r")[0] == "Q7=" + nested(PMAC_MAX)


async def test_pmac_a_long_run_of_operators_is_one_loop_not_nesting(pmac_api) -> None:
    """5 000 terms of one level (15 000 characters) compile and evaluate in a PLC: a run is
    not nesting (it recursed once per term before)."""
    await _terminal(pmac_api, P, "P2=3 I5=3")
    text = "P1=" + "+".join(["P2"] * 5000) + "\nP3=" + "*".join(["1"] * 4000 + ["P2"])
    assert (await pmac_api.put(f"{P}/plcs/1", json={"text": text})).status_code == 200
    assert (await pmac_api.post(f"{P}/plcs/1/enable")).status_code == 200
    await pmac_api.post(f"{P}/clock/advance", json={"seconds": 0.05})
    assert (await _terminal(pmac_api, P, "P1 P3"))["reply"] == "15000\r3"


def test_pmac_ethernet_packet_one_past_the_limit_is_err003_and_the_card_lives() -> None:
    """Issue 33's 604-byte packet: ``P1=`` + 300 ``(`` killed the controller."""

    async def scenario(handle, port):
        c = await Client.connect(port)
        out = [await c.ask("I6=1 I3=2"), await c.ask("P1=" + nested(PMAC_MAX)),
               await c.ask("P1=" + nested(PMAC_MAX + 1)), await c.ask("P1=" + nested(300)),
               await c.ask("P1")]
        await c.close()
        return out

    _, ok, bad, worse, p1 = run_served(serve_pmac, "pmac", "pmac", scenario)
    assert ok == b"\x06"
    assert bad == worse == b"\x07ERR003\r"
    assert p1 == b"1\r\x06"


async def test_trio_program_put_limit_and_one_past(trio_api) -> None:
    for text in ("VR(1)=" + nested(TRIO_MAX), "a=1\nVR(1)=" + "-" * TRIO_MAX + "a",
                 "VR(1)=" + "SIN(" * TRIO_MAX + "1" + ")" * TRIO_MAX,
                 "a=1\nVR(1)=" + "+".join(["a"] * (TRIO_MAX + 1)),
                 "IF 1 THEN " * TRIO_MAX + "VR(1)=2"):
        assert (await trio_api.put(f"{T}/programs/OK", content=text, headers=PLAIN)
                ).status_code == 201, text[:40]
    for text in ("VR(1)=" + nested(TRIO_MAX + 1), "VR(1)=" + nested(400),
                 "a=1\nVR(1)=" + "+".join(["a"] * (TRIO_MAX + 2)),
                 "IF 1 THEN " * (TRIO_MAX + 1) + "VR(1)=2"):
        r = await trio_api.put(f"{T}/programs/BAD", content=text, headers=PLAIN)
        assert r.status_code == 422, text[:40]
        assert f"deeper than {TRIO_MAX} levels" in r.json()["message"]
    assert (await trio_api.get(f"{T}/programs/BAD")).status_code == 404


async def test_trio_program_at_the_limit_runs(trio_api) -> None:
    text = ("a=2\nVR(1)=" + "+".join(["a"] * (TRIO_MAX + 1)) + "\nVR(2)=" + nested(TRIO_MAX, "a")
            + "\nVR(3)=" + "ABS(" * TRIO_MAX + "a" + ")" * TRIO_MAX)
    assert (await trio_api.put(f"{T}/programs/DEEP", content=text, headers=PLAIN)
            ).status_code == 201
    assert (await trio_api.post(f"{T}/programs/DEEP/run", json={})).status_code == 200
    await trio_api.post(f"{T}/clock/advance", json={"seconds": 1})
    got = [(await trio_api.get(f"{T}/variables/VR({i})")).json()["value"] for i in (1, 2, 3)]
    assert got == [2.0 * (TRIO_MAX + 1), 2.0, 2.0]
    assert (await trio_api.get(f"{T}/processes")).json()[0]["error"] is None


async def test_trio_rest_terminal_limit_and_one_past(trio_api) -> None:
    assert (await _terminal(trio_api, T, "VR(1)=" + nested(TRIO_MAX)))["error"] is None
    bad = await _terminal(trio_api, T, "VR(1)=" + nested(TRIO_MAX + 1))
    assert f"deeper than {TRIO_MAX} levels" in bad["error"]
    assert (await _terminal(trio_api, T, "? VR(1)"))["reply"] == "1.0000"


def test_trio_telnet_limit_and_one_past_keep_the_session() -> None:
    async def scenario(handle, port):
        reader, writer = await connect(port)
        writer.write(b"\r\n")
        await read_until_prompt(reader)
        got = []
        for line in ("VR(1)=" + nested(TRIO_MAX), "VR(1)=" + nested(TRIO_MAX + 1),
                     "VR(1)=" + nested(450), "? VR(1)"):
            writer.write(line.encode() + b"\r\n")
            got.append(await asyncio.wait_for(read_until_prompt(reader), 5))
        writer.close()
        return got

    ok, bad, worse, value = run_served(serve_trio, "trio", "trio", scenario)
    assert ok.endswith(b")\r\n>>")
    assert f"deeper than {TRIO_MAX} levels".encode() in bad
    assert f"deeper than {TRIO_MAX} levels".encode() in worse
    assert b"\r\n1.0000\r\n>>" in value
