"""A catastrophic fault ``match`` installed over REST cannot freeze the service when the
unauthenticated PMAC and Trio TCP ports send it commands (issue 23, item 1).

With a backtracking engine, ``(a+)+$`` against 26 ``A`` and a ``!`` takes seconds of the event
loop per command (doubling with every character); the linear-time matcher answers at once, so
the host's reply and ``/health`` both come within the host's ordinary time-out.
"""

from __future__ import annotations

import pytest
from motionsim.app.settings import Settings

from tests.api.fault_hosts import RetryingHost

SUBJECT = "A" * 26 + "!"


@pytest.fixture
def motionsim_settings():
    return Settings(clock={"mode": "virtual"}, pmac_port="auto", trio_port="auto")


@pytest.mark.parametrize("kind,port,fault", [
    ("pmac", "pmac", {"kind": "error_reply", "error": "ERR003"}),
    ("trio", "telnet", {"kind": "reply_drop"}),
])
def test_a_catastrophic_match_does_not_hold_the_tcp_port_or_health(motionsim, kind, port, fault):
    added = motionsim.http.post(f"/controllers/{kind}/faults",
                                json={**fault, "match": "(a+)+$"})
    assert added.status_code == 201, added.text
    host = RetryingHost(motionsim.ports[port], kind, timeout_s=3.0, tries=1,
                        retry_errors=False)
    try:
        host.command(SUBJECT)
        assert host.outcomes in (["ok"], ["error"])
    finally:
        host.close()
    assert motionsim.http.get("/health", timeout=3.0).status_code == 200
    listed = motionsim.http.get(f"/controllers/{kind}/faults").json()["faults"]
    assert listed[0]["seen"] == 0 and listed[0]["injected"] == 0
