"""The TCP protocol listeners against a ``motionsim serve`` subprocess: no ghost controllers,
a connection cap, an idle timeout, back-pressure on unread pipelined input.

A controller deleted and created again under the same id is served by its new incarnation on
new connections (a ``P8=22`` over TCP is what REST then reads), and connections to the deleted
one are closed.
"""

from __future__ import annotations

import socket
import struct
import time
from pathlib import Path

import httpx
import pytest

from tests.integration.test_clients_pmac import _packet, _read_reply, motionsim_serve

GETRESPONSE = 0xBF


def _config(tmp_path: Path, **settings) -> str:
    path = tmp_path / "settings.json"
    import json

    path.write_text(json.dumps(settings))
    return str(path)


def _pmac_ask(sock: socket.socket, cmd: str) -> bytes:
    sock.sendall(_packet(0x40, GETRESPONSE, cmd.encode()))
    return _read_reply(sock)


def _closed(sock: socket.socket, within_s: float = 10.0) -> bool:
    """True when the server closes the connection within ``within_s``."""
    sock.settimeout(within_s)
    try:
        while True:
            if sock.recv(4096) == b"":
                return True
    except (ConnectionResetError, BrokenPipeError):
        return True
    except TimeoutError:
        return False


def _modbus_write(sock: socket.socket, register: int, value: int) -> bytes:
    sock.sendall(struct.pack(">HHHBBHH", 1, 0, 6, 1, 6, register, value))
    return sock.recv(64)


def _recreate(http: str, cid: str, kind: str) -> None:
    assert httpx.delete(f"{http}/controllers/{cid}", timeout=10).status_code == 204
    r = httpx.post(f"{http}/controllers", timeout=10,
                   json={"id": cid, "kind": kind, "clock": {"mode": "virtual"}})
    assert r.status_code == 201, r.text


def _variable(http: str, cid: str, name: str) -> float:
    return httpx.get(f"{http}/controllers/{cid}/variables/{name}", timeout=10).json()["value"]


def test_no_ghost_controllers_after_delete_and_recreate():
    with motionsim_serve("--pmac-port", "auto", "--trio-port", "auto",
                         "--modbus-port", "auto") as svc:
        http, ports = svc.http, svc.listening
        old_pmac = socket.create_connection(("127.0.0.1", ports["pmac"]), timeout=10)
        assert _pmac_ask(old_pmac, "P8=5").endswith(b"\x06")
        old_modbus = socket.create_connection(("127.0.0.1", ports["modbus"]), timeout=10)
        _modbus_write(old_modbus, 9, 5)
        old_trio = socket.create_connection(("127.0.0.1", ports["telnet"]), timeout=10)
        _recreate(http, "pmac", "pmac")
        _recreate(http, "trio", "trio")
        assert _closed(old_pmac) and _closed(old_modbus) and _closed(old_trio)
        with socket.create_connection(("127.0.0.1", ports["pmac"]), timeout=10) as s:
            assert _pmac_ask(s, "P8=22").endswith(b"\x06")
        assert _variable(http, "pmac", "P8") == 22.0
        with socket.create_connection(("127.0.0.1", ports["modbus"]), timeout=10) as s:
            assert _modbus_write(s, 9, 33)[7] == 6
        assert _variable(http, "trio", "VR%289%29") == 33.0
        with socket.create_connection(("127.0.0.1", ports["telnet"]), timeout=10) as s:
            s.sendall(b"VR(8)=22\r\n")
            deadline = time.monotonic() + 10
            while _variable(http, "trio", "VR%288%29") != 22.0:
                assert time.monotonic() < deadline, "the telnet line never reached the new trio"
                time.sleep(0.05)


def test_a_tcp_listener_caps_its_connections_evicting_the_idlest_and_drops_idle_ones(tmp_path):
    config = _config(tmp_path, tcp_max_connections=2, tcp_idle_timeout_s=1.0)
    with motionsim_serve("--pmac-port", "auto", "--trio-port", "0", "--config", config) as svc:
        port = svc.listening["pmac"]
        first = socket.create_connection(("127.0.0.1", port), timeout=10)
        second = socket.create_connection(("127.0.0.1", port), timeout=10)
        assert _pmac_ask(first, "I16").endswith(b"\x06")
        assert _pmac_ask(second, "I16").endswith(b"\x06")
        third = socket.create_connection(("127.0.0.1", port), timeout=10)
        assert _pmac_ask(third, "I16").endswith(b"\x06"), "the newcomer is served"
        assert _closed(first, 5.0), "the connection idle the longest made room"
        assert _pmac_ask(second, "I16").endswith(b"\x06")
        t0 = time.monotonic()
        assert _closed(second, 10.0) and _closed(third, 10.0)
        assert time.monotonic() - t0 < 8.0
        with socket.create_connection(("127.0.0.1", port), timeout=10) as again:
            assert _pmac_ask(again, "I16").endswith(b"\x06")  # the slots were freed


def test_unread_pipelined_input_is_held_back_by_flow_control():
    """A host sending requests without ever reading the replies: the server stops reading,
    the host's send blocks, and the service keeps answering everyone else."""
    with motionsim_serve("--pmac-port", "auto", "--trio-port", "0") as svc:
        request = _packet(0x40, GETRESPONSE, b"I16")
        flood = socket.create_connection(("127.0.0.1", svc.listening["pmac"]), timeout=10)
        flood.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        flood.settimeout(3.0)
        sent = 0
        with pytest.raises(TimeoutError):
            while sent < 200 * 1024 * 1024:
                flood.sendall(request * 4096)
                sent += len(request) * 4096
        assert sent < 64 * 1024 * 1024, f"the server read {sent} bytes it had not answered"
        assert httpx.get(svc.http + "/health", timeout=10).status_code == 200
        with socket.create_connection(("127.0.0.1", svc.listening["pmac"]), timeout=10) as s:
            assert _pmac_ask(s, "I16").endswith(b"\x06")
        flood.close()
