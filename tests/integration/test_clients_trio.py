"""The Trio command line over TCP against a real ``motionsim serve`` subprocess: a plain socket
client and a telnet client (telnetlib3). Each session is a command line of process 0 shared
with the REST terminal; TN20's lock-up shows as the ``>>`` prompt not returning until the move
is buffered (spec trio.md §0.6, §0.10, §9.9; seed TN20-16)."""

from __future__ import annotations

import asyncio
import socket

import httpx

from tests.integration.test_clients_pmac import free_port, motionsim_serve

TIMEOUT_S = 5.0


def read_until(sock: socket.socket, marker: bytes = b">>") -> bytes:
    data = b""
    while not data.endswith(marker):
        chunk = sock.recv(4096)
        if not chunk:
            break
        data += chunk
    return data


def test_plain_socket_session_prints_and_locks_on_a_fourth_move() -> None:
    trio_port = free_port()
    with motionsim_serve("--trio-port", str(trio_port), "--pmac-port", "0") as svc:
        assert svc.listening.get("telnet") == trio_port, svc.lines
        http = svc.http + "/controllers/trio"
        with socket.create_connection(("127.0.0.1", trio_port), timeout=TIMEOUT_S) as s:
            s.sendall(b"\r\n")
            assert read_until(s) == b"\r\n>>"
            s.sendall(b"VR(5)=2\r\n")
            assert read_until(s) == b"VR(5)=2\r\n>>"
            s.sendall(b"? VR(5)\r\n")
            assert read_until(s) == b"? VR(5)\r\n2.0000\r\n>>"
            assert httpx.get(http + "/variables/VR(5)", timeout=5).json()["value"] == 2
            # MTYPE, NTYPE, process buffer: three moves one servo period apart are buffered
            # (each waits in the process buffer for the next servo interrupt, TRM PMOVE) ...
            for _ in range(3):
                s.sendall(b"MOVE(100) AXIS(0)\r\n")
                assert read_until(s).endswith(b"\r\n>>")
                httpx.post(http + "/clock/advance", timeout=5, json={"seconds": 0.001})
            # ... the fourth locks the command line: echo, but no prompt
            s.sendall(b"MOVE(100) AXIS(0)\r\n")
            assert read_until(s, b"\r\n") == b"MOVE(100) AXIS(0)\r\n"
            state = httpx.get(http + "/terminal", timeout=5).json()
            assert state["locked"] is True and state["pending"] == ["MOVE(100) AXIS(0)"]
            s.settimeout(0.3)
            try:
                early = s.recv(100)
            except TimeoutError:
                early = b""
            assert early == b""
            s.settimeout(TIMEOUT_S)
            run = httpx.post(http + "/clock/run-until", timeout=30, json={
                "event": {"type": "terminal", "locked": False}, "timeout_s": 3600})
            assert run.json()["matched"] is not None
            assert read_until(s) == b">>"
        assert httpx.get(http + "/terminal", timeout=5).json()["locked"] is False


def test_telnetlib3_client_gets_prompt_and_print_reply() -> None:
    import telnetlib3

    trio_port = free_port()

    async def session() -> list[str]:
        reader, writer = await telnetlib3.open_connection(
            "127.0.0.1", trio_port, connect_minwait=0.05, connect_maxwait=0.5)
        got = []
        for line in ("", "? 1+2", "PRINT MTYPE AXIS(0)"):
            writer.write(line + "\r\n")
            got.append(await asyncio.wait_for(reader.readuntil(b">>"), TIMEOUT_S))
        writer.close()
        return [g if isinstance(g, str) else g.decode("latin-1") for g in got]

    with motionsim_serve("--trio-port", str(trio_port), "--pmac-port", "0") as svc:
        assert svc.listening.get("telnet") == trio_port, svc.lines
        got = asyncio.run(session())
    assert got[0].endswith(">>")
    assert got[1].replace("\r", "").endswith("? 1+2\n3.0000\n>>")
    assert got[2].replace("\r", "").endswith("PRINT MTYPE AXIS(0)\n0.0000\n>>")
