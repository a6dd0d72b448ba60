"""A stuck client cannot lock the real host out of the PMAC or Trio port (issue 23, item 4).

With the connection cap reached by sockets that connected and never sent anything (a leaked
socket, a crashed host), a new host is served at once: the connection idle the longest is
closed to make room. The cap (``tcp_max_connections``) and the idle time-out
(``tcp_idle_timeout_s``) are settings.
"""

from __future__ import annotations

import socket
import time

import pytest
from motionsim.app.settings import Settings

from tests.api.fault_hosts import RetryingHost
from tests.integration.test_tcp_listeners_robust import _closed

CAP = 32


@pytest.fixture
def motionsim_settings():
    return Settings(clock={"mode": "virtual"}, pmac_port="auto", trio_port="auto",
                    tcp_max_connections=CAP, tcp_idle_timeout_s=600.0)


@pytest.mark.parametrize("kind,port", [("pmac", "pmac"), ("trio", "telnet")])
def test_the_cap_full_of_idle_sockets_does_not_lock_a_new_host_out(motionsim, kind, port):
    stuck = []
    try:
        for _ in range(CAP):
            stuck.append(socket.create_connection(("127.0.0.1", motionsim.ports[port]),
                                                  timeout=10))
            time.sleep(0.005)   # their ages differ: the first is the idlest
        host = RetryingHost(motionsim.ports[port], kind, timeout_s=5.0, tries=1)
        try:
            host.command("I16" if kind == "pmac" else "PRINT VR(1)")
            assert host.outcomes == ["ok"]
        finally:
            host.close()
        assert _closed(stuck[0], 5.0), "the connection idle the longest made room"
        assert not _closed(stuck[-1], 0.3), "a younger idle connection stays open"
    finally:
        for sock in stuck:
            sock.close()


def test_the_cap_and_idle_time_out_are_settings():
    fields = Settings.model_fields
    assert fields["tcp_max_connections"].default == 32
    assert fields["tcp_idle_timeout_s"].default == 600.0
    assert Settings(tcp_max_connections=2, tcp_idle_timeout_s=1.5).tcp_idle_timeout_s == 1.5
