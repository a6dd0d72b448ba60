"""pytest plugin: a ``motionsim`` fixture for host authors' own tests.

Installed with motionsim (entry point ``pytest11``), so a test just asks for it::

    def test_my_streamer(motionsim):
        motionsim.define_rotary("pmac", 1, 600)
        motionsim.host_paced("pmac", "streamer")   # time waits for the host's first call
        done = pool.submit(my_host, motionsim.host("pmac", "streamer", register=False))
        motionsim.advance("pmac", 60.0)            # runs while the host waits, holds while it acts
        motionsim.release("pmac", "streamer")
        done.result()
        assert "waiting" not in [e["state"] for e in motionsim.all_events("pmac", ["program"])]

``motionsim`` is a :class:`motionsim.app.client.MotionSimClient` connected to a service served on a
free 127.0.0.1 port, on a **virtual** clock, with the default controllers ``pmac`` and ``trio``
(kinds not installed are skipped); it is torn down after the test. Its extra attributes:
``url`` and ``ports`` (protocol -> TCP port of the PMAC Ethernet / Trio telnet listeners).

A host in its own thread (or process) runs deterministically against virtual time on a
**host-paced** clock: ``motionsim.host_paced("pmac", "streamer")`` registers the holder, and
``motionsim.host("pmac", "streamer", register=False)`` gives the thread a
:class:`motionsim.app.client.PacedHost` (``wait_for`` an event, ``sleep``). Holders still
registered at teardown are released, so such threads end cleanly.

Override the fixture ``motionsim_settings`` to change what is served, e.g. to get the
controllers' TCP protocols on free ports::

    @pytest.fixture
    def motionsim_settings():
        from motionsim.app.settings import Settings
        return Settings(port=0, clock={"mode": "virtual"}, pmac_port="auto", trio_port="auto")
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest


@pytest.fixture
def motionsim_settings() -> Any:
    """What the ``motionsim`` fixture serves (override it in your conftest.py)."""
    from motionsim.app.settings import Settings

    return Settings(port=0, clock={"mode": "virtual"}, pmac_port=0, trio_port=0)


@pytest.fixture
def motionsim(motionsim_settings: Any) -> Iterator[Any]:
    """A served motionsim (virtual clock, free port) and a client for it."""
    from motionsim.app.client import MotionSimClient
    from motionsim.app.embedded import EmbeddedService

    settings = motionsim_settings.model_copy(update={"host": "127.0.0.1", "port": 0})
    service = EmbeddedService(settings).start()
    client = MotionSimClient(service.url)
    client.ports = dict(service.ports)
    try:
        yield client
    finally:
        _release_hosts(client)
        client.close()
        service.stop()


def _release_hosts(client: Any) -> None:
    """Release every host-paced holder, so host threads still waiting get ``released``
    and stop instead of dying on a closed connection."""
    try:
        for controller in client.controllers():
            clock = controller["clock"]
            if clock.get("mode") == "host-paced":
                for holder in clock.get("holders") or ():
                    client.release(controller["id"], holder["name"])
    except Exception:  # the service may already be gone (a test that stopped it)
        pass
