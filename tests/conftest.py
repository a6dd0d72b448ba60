"""Shared test fixtures: the ``dummy`` controller kinds and an in-process service.

``api`` is an ``httpx.AsyncClient`` on the ASGI app (no sockets), with the lifespan running,
serving one controller ``d`` of kind ``dummy`` on a virtual clock (ticks every 10 ms).
"""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager

import httpx
import pytest
from fastapi import FastAPI
from motionsim.api.main import create_app
from motionsim.app.settings import Settings

import tests.dummy_kind  # noqa: F401  (registers the dummy kinds)

pytest_plugins = ["pytester"]


@pytest.fixture
def anyio_backend() -> str:
    return "asyncio"


def dummy_settings(**overrides) -> Settings:
    """Settings with one virtual ``dummy`` controller ``d`` unless ``controllers`` is given."""
    data = {"controllers": [{"id": "d", "kind": "dummy", "clock": {"mode": "virtual"}}]}
    data.update(overrides)
    return Settings(**data)


@pytest.fixture
def make_app() -> Callable[..., FastAPI]:
    return lambda **overrides: create_app(dummy_settings(**overrides))


@asynccontextmanager
async def rest_client(app: FastAPI) -> AsyncIterator[httpx.AsyncClient]:
    """An ``httpx.AsyncClient`` on ``app`` (in process, no sockets) with its lifespan running;
    ``client.app`` is the app."""
    async with app.router.lifespan_context(app):
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://127.0.0.1") as client:
            client.app = app  # type: ignore[attr-defined]
            yield client


@pytest.fixture
async def api(make_app) -> AsyncIterator[httpx.AsyncClient]:
    async with rest_client(make_app()) as client:
        yield client


# -- the fuzz targets' case counts (tests/fuzz/conftest.py), across pytest-xdist workers ------


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error) -> None:  # noqa: ANN001 - pytest-xdist hook
    """A worker finished: add the fuzz cases it ran to this (controlling) process' counts."""
    from tests.fuzz.conftest import COUNTS

    COUNTS.update(getattr(node, "workeroutput", {}).get("fuzz_counts", {}))


def pytest_terminal_summary(terminalreporter) -> None:  # noqa: ANN001 - pytest hook
    from tests.fuzz.conftest import summary

    summary(terminalreporter)
