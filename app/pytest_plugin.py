"""pytest plugin: a ``motionsim`` fixture for host authors' own tests.

Installed with motionsim (entry point ``pytest11``), so a test just asks for it::

    def test_my_streamer(motionsim):
        motionsim.define_rotary("pmac", 1, 600)
        motionsim.host_paced("pmac", "streamer", "main")  # time waits for both: see below
        done = pool.submit(my_host, motionsim.host("pmac", "streamer", register=False))
        motionsim.advance("pmac", 60.0)            # runs while the host waits, holds while it acts
        motionsim.release("pmac", "streamer")
        done.result()
        assert_fed(motionsim, "pmac", cs=1)          # else: each starvation, when and why

``motionsim`` is a :class:`motionsim.app.client.MotionSimClient` connected to a service served on a
free 127.0.0.1 port, on a **virtual** clock, with the default controllers ``pmac`` and ``trio``
(kinds not installed are skipped); it is torn down after the test. Its extra attributes:
``url`` and ``ports`` (protocol -> TCP port of the PMAC Ethernet / Trio telnet listeners).

A host in its own thread (or process) runs deterministically against virtual time on a
**host-paced** clock: ``motionsim.host_paced("pmac", "streamer", "main")`` registers the
holders — the host, and ``main``, the holder the test's own ``advance`` waits as, so time
stands still until the test advances whatever the machine's load — and
``motionsim.host("pmac", "streamer", register=False)`` gives the thread a
:class:`motionsim.app.client.PacedHost` (``wait_for`` an event, ``sleep``). Holders still
registered at teardown are released, so such threads end cleanly.

Override the fixture ``motionsim_settings`` to change what is served, e.g. to get the
controllers' TCP protocols on free ports::

    @pytest.fixture
    def motionsim_settings():
        from .settings import Settings
        return Settings(port=0, clock={"mode": "virtual"}, pmac_port="auto", trio_port="auto")

**Scaling to a suite.** A service start costs a second or more, so a suite shares one:

- ``motionsim_server`` (session scope) serves once per session, with no controllers of its
  own; ``--motionsim-url URL`` (or ``MOTIONSIM_URL``) points it at a server already running
  instead, e.g. ``docker compose up motionsim``, and the same tests run there
  (``--motionsim-token`` / ``MOTIONSIM_TOKEN``: that server's ``--token``). The per-test
  ``motionsim`` fixture above always serves its own service (its settings are the test's).
- ``motionsim_pmac`` / ``motionsim_trio``: a fresh controller of that kind on it for each
  test (virtual clock, deleted after the test), as a :class:`Controller`: the client's methods
  with the controller's id already given (``motionsim_pmac.advance(0.5)``).
- ``motionsim_controllers``: a factory for several controllers, of any kinds and clocks,
  ``motionsim_controllers("trio", config={...})``; ``motionsim_services``: a factory for
  extra services of their own settings, stopped after the test.

**Failures that explain themselves.** :func:`assert_fed` fails with each starvation's
instant, line, lines ahead and diagnosed cause (the scenario runner's diagnosis); when a test
using these fixtures fails, the tail of each of its controllers' event logs is added to the
report (section ``motionsim events``) with the path of the whole log (JSON Lines).
"""

from __future__ import annotations

import functools
import os
import re
import uuid
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from typing import Any

import pytest

from .pytest_failure_log import pytest_runtest_makereport  # noqa: F401 (a hook)
from .pytest_failure_log import watch as _watch
from .scenarios.fed import assert_fed

#: Environment variable naming an external server (the ``--motionsim-url`` option wins).
URL_ENV = "MOTIONSIM_URL"
#: Environment variable with that server's ``--token`` (the ``--motionsim-token`` option wins).
TOKEN_ENV = "MOTIONSIM_TOKEN"


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("motionsim")
    group.addoption(
        "--motionsim-url", metavar="URL", default=None,
        help=f"Run the session-scoped motionsim fixtures against this running server instead "
             f"of serving one (env {URL_ENV}).")
    group.addoption(
        "--motionsim-token", metavar="TOKEN", default=None,
        help=f"The --token of the server named by --motionsim-url, sent by every client of "
             f"the session-scoped fixtures (env {TOKEN_ENV}).")


@dataclass(slots=True)
class Server:
    """A motionsim service the tests share: ``url``, ``ports`` (protocol -> TCP port of the
    listeners it started; empty for an external server), ``external``."""

    url: str
    ports: dict[str, int] = field(default_factory=dict)
    external: bool = False
    token: str | None = None

    def client(self) -> Any:
        """A new :class:`motionsim.app.client.MotionSimClient` for this server."""
        from .client import MotionSimClient

        client = MotionSimClient(self.url, token=self.token)
        client.ports = dict(self.ports)
        return client


class Controller:
    """One controller of a shared service: ``id``, ``kind``, ``client``, ``url``; every
    client method is available with the id already given (``ctl.terminal("#1J+")`` is
    ``client.terminal(ctl.id, "#1J+")``)."""

    def __init__(self, client: Any, id: str, kind: str) -> None:
        self.client = client
        self.id = id
        self.kind = kind
        self.url = client.url

    def __getattr__(self, name: str) -> Any:
        method = getattr(self.client, name)
        return functools.partial(method, self.id) if callable(method) else method

    def __repr__(self) -> str:
        return f"<motionsim {self.kind} controller {self.id!r} at {self.url}>"


@pytest.fixture
def motionsim_settings() -> Any:
    """What the ``motionsim`` fixture serves (override it in your conftest.py)."""
    from .settings import Settings

    return Settings(port=0, clock={"mode": "virtual"}, pmac_port=0, trio_port=0)


@pytest.fixture
def motionsim(request: pytest.FixtureRequest, motionsim_settings: Any) -> Iterator[Any]:
    """A served motionsim (virtual clock, free port) and a client for it."""
    from .client import MotionSimClient
    from .embedded import EmbeddedService

    settings = motionsim_settings.model_copy(update={"host": "127.0.0.1", "port": 0})
    service = EmbeddedService(settings).start()
    client = MotionSimClient(service.url, token=settings.token)
    client.ports = dict(service.ports)
    _watch(request, client, None)
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


# -- a service per session, a controller per test ---------------------------------------------


@pytest.fixture(scope="session")
def motionsim_session_settings() -> Any:
    """What ``motionsim_server`` serves (override it in your conftest.py, session scope):
    by default no controllers (each test makes its own) and no TCP protocol listeners."""
    from .settings import Settings

    return Settings(port=0, clock={"mode": "virtual"}, controllers=[], pmac_port=0,
                    trio_port=0)


@pytest.fixture(scope="session")
def motionsim_server(request: pytest.FixtureRequest,
                     motionsim_session_settings: Any) -> Iterator[Server]:
    """One service for the whole session; or the ``--motionsim-url`` / ``MOTIONSIM_URL`` one."""
    url = request.config.getoption("motionsim_url") or os.environ.get(URL_ENV)
    if url:
        token = request.config.getoption("motionsim_token") or os.environ.get(TOKEN_ENV)
        server = Server(url.rstrip("/"), external=True, token=token)
        with server.client() as client:
            try:
                status = client.http.get("/health").status_code
            except Exception as exc:  # refused, unresolvable, timed out: all the same here
                pytest.exit(f"--motionsim-url {url}: cannot reach it ({exc})", returncode=3)
            if status != 200:
                pytest.exit(f"--motionsim-url {url}: GET /health answered {status}, not 200",
                            returncode=3)
            try:
                client.controllers()  # /health needs no token: check it on a guarded route
            except Exception as exc:
                pytest.exit(f"--motionsim-url {url}: GET /controllers refused ({exc}); "
                            f"give its token with --motionsim-token or {TOKEN_ENV}", returncode=3)
        yield server
        return
    from .embedded import EmbeddedService

    settings = motionsim_session_settings.model_copy(update={"host": "127.0.0.1", "port": 0})
    service = EmbeddedService(settings).start()
    try:
        yield Server(service.url, dict(service.ports), token=settings.token)
    finally:
        service.stop()


def _test_id(request: pytest.FixtureRequest) -> str:
    """A controller id naming the test (as the dashboard shows it), unique on a shared server."""
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "-", request.node.name).strip("-.")[:48] or "t"
    return f"{stem}-{uuid.uuid4().hex[:6]}"


@pytest.fixture
def motionsim_controllers(request: pytest.FixtureRequest,
                          motionsim_server: Server) -> Iterator[Callable[..., Controller]]:
    """A factory: ``make(kind="pmac", *, id=None, clock="virtual", factor=1.0, config=None,
    server=None)`` creates a controller (on ``server``, default the session's) and returns
    it as a :class:`Controller`; every one is deleted after the test."""
    made: list[Controller] = []
    clients: dict[str, Any] = {}

    def make(kind: str = "pmac", *, id: str | None = None, clock: str = "virtual",
             factor: float = 1.0, config: dict[str, Any] | None = None,
             server: Server | None = None) -> Controller:
        srv = server or motionsim_server
        if srv.url not in clients:
            clients[srv.url] = srv.client()
        client = clients[srv.url]
        body = client.create_controller(kind, id=id or _test_id(request), clock=clock,
                                        factor=factor, config=config)
        ctl = Controller(client, body["id"], kind)
        made.append(ctl)
        _watch(request, client, ctl.id)
        return ctl

    try:
        yield make
    finally:
        for ctl in made:
            _delete(ctl)
        for client in clients.values():
            client.close()


def _delete(ctl: Controller) -> None:
    from .client import MotionSimHTTPError

    try:
        for holder in ctl.clock().holders or ():
            ctl.release(holder["name"])
        ctl.delete_controller()
    except (MotionSimHTTPError, OSError):  # already deleted by the test, or server gone
        pass


@pytest.fixture
def motionsim_pmac(motionsim_controllers: Callable[..., Controller]) -> Controller:
    """A fresh PMAC (virtual clock, factory defaults) on the session's service."""
    return motionsim_controllers("pmac")


@pytest.fixture
def motionsim_trio(motionsim_controllers: Callable[..., Controller]) -> Controller:
    """A fresh Trio Motion Coordinator (virtual clock) on the session's service."""
    return motionsim_controllers("trio")


@pytest.fixture
def motionsim_services() -> Iterator[Callable[..., Server]]:
    """A factory: ``start(settings=None)`` serves another motionsim (default: the
    ``motionsim_session_settings`` defaults) on a free port; each is stopped after the test."""
    from .embedded import EmbeddedService
    from .settings import Settings

    started: list[Any] = []

    def start(settings: Any = None) -> Server:
        base = settings if settings is not None else Settings(
            clock={"mode": "virtual"}, controllers=[], pmac_port=0, trio_port=0)
        service = EmbeddedService(base.model_copy(update={"host": "127.0.0.1", "port": 0}))
        started.append(service.start())
        return Server(service.url, dict(service.ports))

    try:
        yield start
    finally:
        for service in started:
            service.stop()


__all__ = ["Controller", "Server", "assert_fed"]
