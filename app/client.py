"""A small typed client for motionsim's REST API (sync, on httpx), for host authors' tests.

    from .client import MotionSimClient

    with MotionSimClient("http://127.0.0.1:8000") as ms:
        ms.create_controller("pmac", id="p", clock="virtual", config={"i16": 5, "i17": 10})
        ms.terminal("p", "&1 DEFINE ROT 600")
        ms.load_lines("p", 1, ["X10", "X20"])
        ms.advance("p", 0.5)
        for event in ms.events("p", types=["breq"]).events: ...

Every error the service answers is raised as :class:`MotionSimHTTPError` with its ``status``,
``code`` and the full JSON ``body`` (``pmac_error``, ``field``, ``line`` ...).
"""

from __future__ import annotations

import contextlib
import json
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import quote

import httpx


class MotionSimHTTPError(Exception):
    """An error answer: ``status`` (HTTP), ``code`` (stable), ``body`` (the JSON error body)."""

    def __init__(self, status: int, body: Mapping[str, Any]) -> None:
        self.status = status
        self.body = dict(body)
        self.code = str(body.get("code", "error"))
        self.message = str(body.get("message", ""))
        super().__init__(f"{status} {self.code}: {self.message}")


@dataclass(frozen=True, slots=True)
class Clock:
    """A controller's clock; the fields a mode does not have are None (``holders``: empty)."""

    mode: str
    factor: float
    paused: bool
    t: float
    lag_s: float | None = None
    behind: bool | None = None
    slipped_s: float | None = None
    reaction_s: float | None = None
    holders: list[dict[str, Any]] = field(default_factory=list)
    held_by: list[str] = field(default_factory=list)

    @classmethod
    def from_json(cls, body: Mapping[str, Any]) -> Clock:
        """From the API's ``Clock`` (fields this client does not know are ignored)."""
        return cls(**{k: v for k, v in body.items() if k in cls.__dataclass_fields__})


@dataclass(frozen=True, slots=True)
class TerminalReply:
    """``reply``, ``error`` (``ERR003`` ...), ``pending``; with an error, the PMAC's
    ``error_meaning`` and a ``detail`` (what and where); ``not_simulated`` for a valid command
    motionsim does not simulate; Trio ``output`` lines. Fields this client does not know are
    ignored, so a newer server does not break it."""

    reply: str
    error: str | None
    pending: bool
    error_meaning: str | None = None
    not_simulated: bool = False
    detail: str | None = None
    output: list[str] = field(default_factory=list)

    @classmethod
    def from_json(cls, body: Mapping[str, Any]) -> TerminalReply:
        return cls(**{k: v for k, v in body.items() if k in cls.__dataclass_fields__})


@dataclass(frozen=True, slots=True)
class EventsPage:
    events: list[dict[str, Any]]
    next: int
    gap: dict[str, Any] | None = None
    epoch: str | None = None
    reset: dict[str, Any] | None = None


@dataclass(frozen=True, slots=True)
class RunUntilResult:
    """``outcome``: ``matched``, ``timeout`` (simulated), ``wall_timeout``, ``released``."""

    matched: dict[str, Any] | None
    clock: Clock
    outcome: str = "matched"


@dataclass(slots=True)
class LinesAccepted:
    accepted: int
    lines_ahead: int
    free_words: int
    breq: bool
    extra: dict[str, Any] = field(default_factory=dict)


class Subscription:
    """An open event stream: iterate for events (dicts; ``{"type": "gap", ...}`` on a gap).

    ``timeout``: seconds to wait for each message (``TimeoutError`` after), None = forever.
    The stream's ``epoch`` message is not yielded: it sets :attr:`epoch` (pass it with the last
    seq seen to resume) and :attr:`reset` (the server's reset notice when the resume position
    belonged to an earlier incarnation of the log, else ``None``).
    """

    def __init__(self, url: str, timeout: float | None = None) -> None:
        from websockets.sync.client import connect

        self.timeout = timeout
        self.epoch: str | None = None
        self.reset: dict[str, Any] | None = None
        self._connection = connect(url, compression=None, open_timeout=10, proxy=None)
        self._ws = self._connection.__enter__()

    def __iter__(self) -> Iterator[dict[str, Any]]:
        return self

    def __next__(self) -> dict[str, Any]:
        while True:
            message = json.loads(self._ws.recv(timeout=self.timeout))
            if message.get("type") != "epoch" or "seq" in message:
                return message
            self.epoch, self.reset = message["epoch"], message.get("reset")

    def close(self) -> None:
        self._connection.__exit__(None, None, None)

    def __enter__(self) -> Subscription:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class PacedHost:
    """A host taking part in a host-paced clock as holder ``holder`` of controller ``id``.

    Between its calls the host is *acting*: simulated time stands still for it, so whatever it
    sends lands at the instant it was woken, however slow its thread. ``wait_for`` and
    ``sleep`` hand time back until the event / simulated delay; ``release`` leaves.
    ``client`` is its own :class:`MotionSimClient` (one connection per thread)::

        host = ms.host("pmac", "streamer")                 # in the test: time waits for it
        # in the host's thread:
        if host.wait_for("breq", 5.0, cs=1, level=True):   # None: timed out or released
            host.client.load_lines("pmac", 1, next_lines)
    """

    def __init__(self, client: MotionSimClient, id: str, holder: str) -> None:
        self.client = client
        self.id = id
        self.holder = holder
        #: How the last ``wait_for`` ended (``matched``, ``timeout``, ``released`` ...).
        self.outcome: str | None = None

    def wait_for(self, type: str, timeout_s: float, **fields: Any) -> dict[str, Any] | None:
        """Hand time back until the next new event of ``type`` with ``fields`` (plus the
        clock's reaction time) or ``timeout_s`` simulated seconds; the event, or None."""
        result = self.client.run_until(self.id, type, timeout_s, holder=self.holder, **fields)
        self.outcome = result.outcome
        return result.matched

    def sleep(self, seconds: float) -> Clock:
        """Hand time back for ``seconds`` of simulated time (a host's own delay)."""
        clock = self.client.advance(self.id, seconds, holder=self.holder)
        if all(h["name"] != self.holder for h in clock.holders):
            self.outcome = "released"
        return clock

    @property
    def released(self) -> bool:
        """The holder was released (the test is over): the host should stop."""
        return self.outcome == "released"

    def release(self) -> None:
        """Leave: time no longer waits for this host."""
        self.client.release(self.id, self.holder)

    def start(self, host_code: Callable[[PacedHost], Any]) -> Future[Any]:
        """Run ``host_code(self)`` in a thread of its own; when it ends — returning or
        raising — the holder is released at once, so the test's ``advance`` returns then
        (time does not stand still 30 s for a host that is gone before the 409) and the
        future's ``result()`` gives the host's value or raises its error."""
        pool = ThreadPoolExecutor(1, thread_name_prefix=f"host-{self.holder}")

        def run() -> Any:
            try:
                return host_code(self)
            finally:
                with contextlib.suppress(Exception):  # the test may have released it first
                    self.release()

        future = pool.submit(run)
        pool.shutdown(wait=False)
        return future

    def close(self) -> None:
        self.client.close()


#: Seconds an idle pooled connection is kept for reuse: shorter than the server's keep-alive
#: (``http_keep_alive_s``, 5 s by default), so the client drops an idle connection before the
#: server closes it, instead of sending a request down a socket the server is closing.
KEEPALIVE_EXPIRY_S = 2.0

#: Methods a request may be sent twice with: RFC 9110 §9.2.2's idempotent methods. POST (an
#: ``advance``, a batch of lines) is never repeated: the first may have been acted on.
IDEMPOTENT_METHODS = frozenset({"GET", "HEAD", "OPTIONS", "PUT", "DELETE"})

#: Transport errors after which an idempotent request is sent once more on a new connection:
#: the connection was closed under it (a keep-alive close racing the request) or could not be
#: used. Timeouts are not among them: the server may still be working on the first.
RETRIED_ERRORS = (httpx.RemoteProtocolError, httpx.ReadError, httpx.WriteError,
                  httpx.ConnectError)


class MotionSimClient:
    """REST client for one motionsim service.

    Args:
        base_url: e.g. ``http://127.0.0.1:8000``.
        timeout: seconds per request (a realtime terminal command may wait up to ~5 s).
        token: the service's ``--token``: sent as ``Authorization: Bearer`` on every request
            and as ``?token=`` on event streams (None: a service without a token).
    """

    def __init__(self, base_url: str, *, timeout: float = 30.0,
                 transport: httpx.BaseTransport | None = None,
                 token: str | None = None) -> None:
        self.base_url = base_url.rstrip("/")
        self.token = token
        #: protocol -> TCP port of the service's protocol listeners, when known (fixture).
        self.ports: dict[str, int] = {}
        headers = {"Authorization": f"Bearer {token}"} if token is not None else None
        self.http = httpx.Client(base_url=self.base_url, timeout=timeout, transport=transport,
                                 trust_env=False, headers=headers,
                                 limits=httpx.Limits(keepalive_expiry=KEEPALIVE_EXPIRY_S))

    @property
    def url(self) -> str:
        """The service's base URL."""
        return self.base_url

    # -- plumbing ----------------------------------------------------------------------------

    def request(self, method: str, path: str, **kwargs: Any) -> Any:
        """One request; the decoded JSON (None for 204); raises :class:`MotionSimHTTPError`.

        An idempotent request (:data:`IDEMPOTENT_METHODS`) that fails with one of
        :data:`RETRIED_ERRORS` is sent once more (httpx then opens a new connection); a
        second failure is raised."""
        try:
            r = self.http.request(method, path, **kwargs)
        except RETRIED_ERRORS:
            if method.upper() not in IDEMPOTENT_METHODS:
                raise
            r = self.http.request(method, path, **kwargs)
        if r.status_code >= 400:
            try:
                body = r.json()
            except ValueError:
                body = {"code": "http_error", "message": r.text}
            raise MotionSimHTTPError(r.status_code, body)
        if r.status_code == 204 or not r.content:
            return None
        return r.json()

    def close(self) -> None:
        self.http.close()

    def __enter__(self) -> MotionSimClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- service and controllers -------------------------------------------------------------

    def health(self) -> bool:
        try:
            return self.http.get("/health").status_code == 200
        except httpx.TransportError:
            return False

    def controllers(self) -> list[dict[str, Any]]:
        return self.request("GET", "/controllers")

    def controller(self, id: str) -> dict[str, Any]:
        return self.request("GET", f"/controllers/{id}")

    def create_controller(self, kind: str, *, id: str | None = None, clock: str = "virtual",
                          factor: float = 1.0, config: Mapping[str, Any] | None = None
                          ) -> dict[str, Any]:
        body: dict[str, Any] = {"kind": kind, "clock": {"mode": clock, "factor": factor},
                                "config": dict(config or {})}
        if id is not None:
            body["id"] = id
        return self.request("POST", "/controllers", json=body)

    def delete_controller(self, id: str) -> None:
        self.request("DELETE", f"/controllers/{id}")

    def reset(self, id: str) -> dict[str, Any]:
        """The power cycle."""
        return self.request("POST", f"/controllers/{id}/reset")

    # -- clock -------------------------------------------------------------------------------

    def clock(self, id: str) -> Clock:
        return Clock.from_json(self.request("GET", f"/controllers/{id}/clock"))

    def set_clock(self, id: str, *, factor: float | None = None, paused: bool | None = None,
                  mode: str | None = None, reaction_s: float | None = None,
                  holders: Sequence[str] | None = None) -> Clock:
        body = {k: v for k, v in {"factor": factor, "paused": paused, "mode": mode,
                                  "reaction_s": reaction_s}.items() if v is not None}
        if holders is not None:
            body["holders"] = list(holders)
        return Clock.from_json(self.request("PATCH", f"/controllers/{id}/clock", json=body))

    def host_paced(self, id: str, *holders: str, reaction_s: float = 0.0) -> Clock:
        """Switch ``id`` to the host-paced clock with ``holders`` registered (acting: time waits
        for each one's first call), the hosts reacting ``reaction_s`` simulated seconds after
        the event they waited for."""
        return self.set_clock(id, mode="host-paced", reaction_s=reaction_s, holders=holders)

    def hold(self, id: str, holder: str) -> Clock:
        """Register ``holder`` on a host-paced clock (acting now: time waits for it)."""
        return Clock.from_json(self.request("PUT", f"/controllers/{id}/clock/holders/{holder}"))

    def release(self, id: str, holder: str) -> Clock:
        """Release ``holder``: time no longer waits for it (a call it waits in returns)."""
        return Clock.from_json(self.request("DELETE",
                                            f"/controllers/{id}/clock/holders/{holder}"))

    def host(self, id: str, holder: str, *, register: bool = True) -> PacedHost:
        """A :class:`PacedHost` named ``holder`` on controller ``id`` with its own connection
        (give it to the host's thread); registered at once unless ``register`` is False."""
        host = PacedHost(MotionSimClient(self.base_url, timeout=self.http.timeout.read or 60.0,
                                         token=self.token), id, holder)
        if register:
            host.client.hold(id, holder)
        return host

    def advance(self, id: str, seconds: float, *, holder: str | None = None) -> Clock:
        """Virtual: run ``seconds`` forward. Host-paced: ``holder`` (default ``main``) waits
        that long while the other holders act."""
        body: dict[str, Any] = {"seconds": seconds}
        if holder is not None:
            body["holder"] = holder
        return Clock.from_json(self.request("POST", f"/controllers/{id}/clock/advance",
                                            json=body))

    def run_until(self, id: str, type: str, timeout_s: float, *, holder: str | None = None,
                  **fields: Any) -> RunUntilResult:
        """Run (virtual), wait as ``holder`` (host-paced) or wait (realtime) for the first new
        event of ``type`` with ``fields``."""
        body: dict[str, Any] = {"event": {"type": type, **fields}, "timeout_s": timeout_s}
        if holder is not None:
            body["holder"] = holder
        out = self.request("POST", f"/controllers/{id}/clock/run-until", json=body)
        return RunUntilResult(out["matched"], Clock.from_json(out["clock"]),
                              out.get("outcome", "matched"))

    # -- events ------------------------------------------------------------------------------

    def events(self, id: str, since: int = 0, types: Sequence[str] | None = None,
               limit: int = 1000, epoch: str | None = None) -> EventsPage:
        params: list[tuple[str, str | int]] = [("since", since), ("limit", limit)]
        params += [("type", t) for t in types or ()]
        if epoch is not None:
            params.append(("epoch", epoch))
        out = self.request("GET", f"/controllers/{id}/events", params=params)
        return EventsPage(out["events"], out["next"], out.get("gap"), out.get("epoch"),
                          out.get("reset"))

    def all_events(self, id: str, types: Sequence[str] | None = None) -> list[dict[str, Any]]:
        """Every held event, paging through."""
        out: list[dict[str, Any]] = []
        since = 0
        while True:
            page = self.events(id, since, types, limit=10_000)
            out.extend(page.events)
            if page.next == since:
                return out
            since = page.next

    # -- recordings (PMAC data gathering, Trio SCOPE) ------------------------------------------

    def recording(self, id: str, resource: str = "gather") -> dict[str, Any]:
        """The whole recording, paging through ``GET /controllers/{id}/{resource}``
        (``"gather"`` for a PMAC, ``"scope"`` for a Trio): the first page's fields with every
        column complete (docs/API.md "Recordings")."""
        path = f"/controllers/{id}/{resource}"
        page: dict[str, Any] = self.request("GET", path, params={"limit": 100_000})
        while page["next"] < page["total"]:
            more = self.request("GET", path, params={"since": page["next"], "limit": 100_000})
            if more["next"] == page["next"]:
                break
            for name, column in more["columns"].items():
                page["columns"][name].extend(column)
            page["next"] = more["next"]
        return page

    def subscribe(self, id: str, since: int = 0, types: Sequence[str] | None = None,
                  timeout: float | None = None, epoch: str | None = None) -> Subscription:
        """Events over the WebSocket: the backlog after ``since``, then live ones (and gaps).

        Use it as a context manager (it holds a connection)::

            with ms.subscribe("pmac", since=last_seq, types=["breq"]) as events:
                for event in events: ...
        """
        query = "&".join([f"since={since}"] + [f"type={quote(t)}" for t in types or ()]
                         + ([f"epoch={quote(epoch)}"] if epoch is not None else [])
                         + ([f"token={quote(self.token)}"] if self.token is not None else []))
        url = self.base_url.replace("http", "ws", 1) + f"/controllers/{id}/events?{query}"
        return Subscription(url, timeout)

    # -- terminal and variables --------------------------------------------------------------

    def terminal(self, id: str, command: str) -> TerminalReply:
        return TerminalReply.from_json(self.request("POST", f"/controllers/{id}/terminal",
                                                    json={"command": command}))

    def terminal_state(self, id: str) -> dict[str, Any]:
        return self.request("GET", f"/controllers/{id}/terminal")

    def get_variable(self, id: str, name: str) -> float:
        return self.request("GET", f"/controllers/{id}/variables/{quote(name)}")["value"]

    def set_variable(self, id: str, name: str, value: float) -> float:
        return self.request("PUT", f"/controllers/{id}/variables/{quote(name)}",
                            json={"value": value})["value"]

    # -- PMAC --------------------------------------------------------------------------------

    def coord(self, id: str, cs: int) -> dict[str, Any]:
        return self.request("GET", f"/controllers/{id}/coord/{cs}")

    def define_rotary(self, id: str, cs: int, size_words: int) -> Any:
        return self.request("PUT", f"/controllers/{id}/coord/{cs}/rotary",
                            json={"size_words": size_words})

    def delete_rotary(self, id: str, cs: int) -> Any:
        return self.request("DELETE", f"/controllers/{id}/coord/{cs}/rotary")

    def load_lines(self, id: str, cs: int, lines: Sequence[str],
                   first_seq: int | None = None) -> LinesAccepted:
        body: dict[str, Any] = {"lines": list(lines)}
        if first_seq is not None:
            body["first_seq"] = first_seq
        out = dict(self.request("POST", f"/controllers/{id}/coord/{cs}/rotary/lines", json=body))
        known = {k: out.pop(k) for k in ("accepted", "lines_ahead", "free_words", "breq")}
        return LinesAccepted(**known, extra=out)

    def run(self, id: str, cs: int) -> Any:
        return self.request("POST", f"/controllers/{id}/coord/{cs}/run")

    def quit(self, id: str, cs: int) -> Any:
        return self.request("POST", f"/controllers/{id}/coord/{cs}/quit")

    def abort(self, id: str, cs: int) -> Any:
        return self.request("POST", f"/controllers/{id}/coord/{cs}/abort")

    # -- Trio --------------------------------------------------------------------------------

    def axis(self, id: str, axis: int) -> dict[str, Any]:
        return self.request("GET", f"/controllers/{id}/axes/{axis}")

    def set_axis(self, id: str, axis: int, **params: float) -> dict[str, Any]:
        return self.request("PATCH", f"/controllers/{id}/axes/{axis}", json=params)

    def move(self, id: str, axis: int, type: str, args: Sequence[float],
             process: int | None = None, wait: bool = False) -> dict[str, Any]:
        body: dict[str, Any] = {"type": type, "args": list(args)}
        if process is not None:
            body["process"] = process
        return self.request("POST", f"/controllers/{id}/axes/{axis}/moves", json=body,
                            params={"wait": "true"} if wait else None)

    def store_program(self, id: str, name: str, text: str) -> Any:
        return self.request("PUT", f"/controllers/{id}/programs/{name}", content=text.encode(),
                            headers={"content-type": "text/plain"})

    def run_program(self, id: str, name: str, process: int | None = None) -> int:
        body = {} if process is None else {"process": process}
        return self.request("POST", f"/controllers/{id}/programs/{name}/run", json=body)["process"]

    def processes(self, id: str) -> list[dict[str, Any]]:
        return self.request("GET", f"/controllers/{id}/processes")


__all__ = ["Clock", "EventsPage", "LinesAccepted", "MotionSimClient", "MotionSimHTTPError",
           "PacedHost", "RunUntilResult", "Subscription", "TerminalReply"]
