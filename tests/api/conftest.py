"""REST fixtures for the PMAC and Trio resource tests: the in-process service with a virtual
``pmac`` controller ``p`` (beside a ``dummy`` ``d``), or a virtual ``trio`` controller ``t``
whose axes move fast (``FAST``)."""

from __future__ import annotations

from collections.abc import AsyncIterator

import httpx
import pytest
from motionsim.api.main import create_app

from tests.conftest import dummy_settings, rest_client

FAST = {"speed": 1000.0, "accel": 100000.0, "decel": 100000.0}


@pytest.fixture
async def pmac_api() -> AsyncIterator[httpx.AsyncClient]:
    settings = dummy_settings(controllers=[
        {"id": "p", "kind": "pmac", "clock": {"mode": "virtual"}},
        {"id": "d", "kind": "dummy", "clock": {"mode": "virtual"}},
    ])
    async with rest_client(create_app(settings)) as client:
        yield client


@pytest.fixture
async def trio_api() -> AsyncIterator[httpx.AsyncClient]:
    settings = dummy_settings(
        controllers=[{"id": "t", "kind": "trio", "clock": {"mode": "virtual"}, "config": FAST}]
    )
    async with rest_client(create_app(settings)) as client:
        yield client


async def clock_t(api: httpx.AsyncClient, base: str) -> float:
    """The simulated time of the controller at ``base`` (``/controllers/{id}``)."""
    return (await api.get(f"{base}/clock")).json()["t"]
