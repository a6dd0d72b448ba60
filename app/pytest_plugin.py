"""pytest plugin: a ``motionsim`` fixture for host authors' own tests.

Installed with motionsim (entry point ``pytest11``), so a test just asks for it::

    def test_my_streamer(motionsim):
        motionsim.terminal("pmac", "&1 DEFINE ROT 600")
        my_streamer = Streamer(motionsim.url)      # your host code, over REST/WebSocket
        my_streamer.send_program(...)
        motionsim.advance("pmac", 2.0)             # virtual time: runs as fast as the CPU
        assert not motionsim.events("pmac", types=["program"]).events[-1]["state"] == "waiting"

``motionsim`` is a :class:`motionsim.app.client.MotionSimClient` connected to a service served on a
free 127.0.0.1 port, on a **virtual** clock, with the default controllers ``pmac`` and ``trio``
(kinds not installed are skipped); it is torn down after the test. Its extra attributes:
``url`` and ``ports`` (protocol -> TCP port of the PMAC Ethernet / Trio telnet listeners).

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
        client.close()
        service.stop()
