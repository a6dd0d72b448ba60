"""``motionsim replay FILE``: replay a wire transcript against fresh controllers and compare.

The transcript (``app/recorder.py``) holds, per TCP session, the bytes the host sent and the
bytes the service answered, with the simulated time of each. The replay builds the same
controllers (kind and config from the header) on **virtual** clocks, opens one protocol session
per recorded session (the same session code the TCP servers run, without sockets), and for
each recorded input: advances that controller's clock to the input's simulated time (never
backwards), feeds the bytes, and collects the answers. Each session's answers must equal the
recorded ones byte for byte; the first difference is reported with its offset.

A transcript cut by a crash (the service killed while a request was in flight) replays too:
a session with no ``close`` record is *incomplete*; its complete exchanges must match (the
answers recorded are a prefix of the replayed ones), and the replay's extra answer to the
request that was in flight is reported, not counted as a difference. A last line cut short is
skipped and reported.

Transcripts recorded on a realtime clock replay the inputs at the simulated instants they
arrived, so answers that depend on timing (``PR``, a locked Trio prompt) come out the same
as long as the recording did not depend on wall-clock jitter finer than those instants.
"""

from __future__ import annotations

import asyncio
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .recorder import read_transcript

#: Event-loop turns without new output after which a replayed input is considered answered.
_SETTLE_TURNS = 5


@dataclass
class SessionResult:
    """How one recorded session replayed."""

    session: int
    protocol: str
    controller: str
    expected: bytes = b""
    got: bytes = b""
    #: A ``close`` record ended the session (False: the recording stopped while it was open).
    closed: bool = False

    @property
    def incomplete(self) -> bool:
        """The recording ended with the session open (a crash): only its complete exchanges,
        the answers recorded, are compared."""
        return not self.closed

    @property
    def ok(self) -> bool:
        if self.incomplete:
            return self.got[: len(self.expected)] == self.expected
        return self.expected == self.got

    @property
    def first_difference(self) -> int | None:
        """Byte offset of the first difference, or None when equal."""
        if self.ok:
            return None
        if self.incomplete:
            expected, got = self.expected, self.got[: len(self.expected)]
            for i, (a, b) in enumerate(zip(expected, got, strict=False)):
                if a != b:
                    return i
            return len(got)
        for i, (a, b) in enumerate(zip(self.expected, self.got, strict=False)):
            if a != b:
                return i
        return min(len(self.expected), len(self.got))

    def describe(self) -> str:
        head = f"session {self.session} ({self.protocol} on {self.controller})"
        if self.ok and self.incomplete:
            extra = len(self.got) - len(self.expected)
            last = (f"the last request was in flight (the replay answers it with {extra} "
                    "bytes never recorded)" if extra else "no request was in flight")
            return (f"{head}: incomplete (the recording ended with the session open): "
                    f"{len(self.expected)} bytes of complete exchanges match; {last}")
        if self.ok:
            return f"{head}: {len(self.got)} bytes match"
        i = self.first_difference or 0
        lo = max(0, i - 20)
        return (f"{head}: differs at byte {i}: expected {self.expected[lo:i + 20]!r}, "
                f"got {self.got[lo:i + 20]!r}")


@dataclass
class ReplayResult:
    sessions: list[SessionResult] = field(default_factory=list)
    #: Line number of a last line cut short by a crash (skipped), or None.
    truncated_line: int | None = None

    @property
    def ok(self) -> bool:
        return all(s.ok for s in self.sessions)


class _Replayed:
    """A session being replayed: a worker task runs its answers as input arrives."""

    def __init__(self, session: Any, result: SessionResult) -> None:
        self.session = session
        self.result = result
        self.wake = asyncio.Event()
        self.task = asyncio.create_task(self._work())

    async def _work(self) -> None:
        try:
            while True:
                await self.wake.wait()
                self.wake.clear()
                async for out in self.session.replies():
                    self.result.got += out
                if self.session.gone.is_set():
                    return
        except Exception:  # noqa: BLE001 - a disconnect or broken stream ends the session
            return

    def feed(self, data: bytes) -> None:
        self.session.receive(data)
        self.wake.set()


async def _settle(replayed: list[_Replayed]) -> None:
    still = 0
    last = -1
    while still < _SETTLE_TURNS:
        await asyncio.sleep(0)
        total = sum(len(r.result.got) for r in replayed)
        still = still + 1 if total == last else 0
        last = total


async def replay(path: str | Path) -> ReplayResult:
    """Replay the transcript at ``path``; see the module docstring."""
    from ..api.pmac_ethernet.server import PmacSession
    from ..api.trio_terminal.server import TrioSession
    from .clock import VirtualClock
    from .registry import Registry

    registry = Registry()
    result = ReplayResult()
    live: dict[int, _Replayed] = {}
    by_session: dict[int, SessionResult] = {}
    try:
        for rec in read_transcript(path):
            fields = dict(rec.fields or {})
            if rec.kind == "truncated":
                result.truncated_line = fields.get("line")
                break
            if rec.kind == "header":
                for cid, spec in fields.get("controllers", {}).items():
                    registry.add(spec.get("kind", cid), cid, clock="virtual",
                                 config=spec.get("config") or {})
                continue
            if rec.kind == "open":
                try:
                    handle = registry.get(fields["controller"])
                except Exception:
                    raise ValueError(f"{path}:{rec.line}: session {rec.session} opens on "
                                     f"controller {fields['controller']!r}, which the header "
                                     "does not describe") from None
                _advance(handle, rec.t, VirtualClock)
                cls = PmacSession if fields["protocol"] == "pmac" else TrioSession
                res = SessionResult(rec.session, fields["protocol"], fields["controller"])
                by_session[rec.session] = res
                result.sessions.append(res)
                live[rec.session] = _Replayed(cls(handle, f"replay:{rec.session}"), res)
                continue
            rep = live.get(rec.session)
            res = by_session.get(rec.session)
            if rep is None or res is None:
                raise ValueError(f"{path}:{rec.line}: record for unknown session {rec.session}")
            if rec.kind == "out":
                res.expected += rec.data
                continue
            _advance(rep.session.handle, rec.t, VirtualClock)
            await _settle(list(live.values()))
            if rec.kind == "in":
                rep.feed(rec.data)
            else:  # close
                res.closed = True
                rep.feed(b"")
            await _settle(list(live.values()))
        await _settle(list(live.values()))
    finally:
        for rep in live.values():
            rep.task.cancel()
            rep.session.close()
        await asyncio.gather(*(r.task for r in live.values()), return_exceptions=True)
        await registry.close()
    return result


def _advance(handle: Any, t: float, virtual: type) -> None:
    clock = handle.clock
    if isinstance(clock, virtual) and t > handle.controller.now:
        clock.advance(t - handle.controller.now)


def main(path: str | Path) -> int:
    """Replay ``path``, print one line per session; exit status 0 when every session matches,
    1 when one differs, 2 (one line naming the transcript line, no traceback) when the file is
    not a transcript that can be replayed."""
    try:
        result = asyncio.run(replay(path))
    except (ValueError, OSError) as exc:
        print(f"motionsim replay: {exc}", file=sys.stderr)
        return 2
    if result.truncated_line is not None:
        print(f"note line {result.truncated_line} was cut short (the recording process was "
              "killed while writing it) and is skipped")
    for s in result.sessions:
        mark = "FAIL " if not s.ok else ("cut  " if s.incomplete else "ok   ")
        print(mark + s.describe())
    print(f"{sum(s.ok for s in result.sessions)}/{len(result.sessions)} sessions match")
    return 0 if result.ok else 1


__all__ = ["ReplayResult", "SessionResult", "main", "replay"]
