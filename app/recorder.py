"""Wire transcript recorder: every byte of every TCP protocol session, with its times.

``motionsim serve --record FILE`` gives the protocol servers (``api/pmac_ethernet``,
``api/trio_terminal``) one :class:`Recorder`. Each session (one TCP connection) writes JSON
Lines to ``FILE``::

    {"kind": "header", "version": 1, "controllers": {"pmac": {"kind": "pmac", "config": {...}}}}
    {"kind": "open",  "session": 1, "protocol": "pmac", "controller": "pmac", "t": 0.0, "wall": ...}
    {"kind": "in",    "session": 1, "t": 0.0012, "wall": 1764072000.1, "data": "@\\u00bf..."}
    {"kind": "out",   "session": 1, "t": 0.0015, "wall": 1764072000.1, "data": "1.947  \\r\\u0006"}
    {"kind": "close", "session": 1, "t": 0.5, "wall": ...}

``t`` is the controller's simulated time, ``wall`` the Unix time; ``data`` is the bytes as a
latin-1 string (every byte value maps to one character, so it round-trips exactly and stays
readable). ``app/replay.py`` reads the file back and replays it against a fresh controller.

Each line is flushed as it is written, so a crash (``kill -9``) leaves every record written
before it, at most a last line cut short, and no ``close`` for the sessions open then — a
request in flight has its ``in`` record and no ``out``. The replay accepts such a transcript.
"""

from __future__ import annotations

import json
import time
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any


@dataclass(frozen=True, slots=True)
class Record:
    """One line of a transcript."""

    kind: str  # header | open | in | out | close
    session: int = 0
    t: float = 0.0
    wall: float = 0.0
    data: bytes = b""
    fields: Mapping[str, Any] | None = None
    #: The 1-based line of the transcript it was read from (0: not read from a file).
    line: int = 0


class Recorder:
    """Appends session bytes to a JSON Lines transcript (flushed line by line).

    Args:
        path: the transcript file. One that already exists is kept: it is renamed
            ``FILE.1`` (``FILE.1`` to ``FILE.2`` ..., the :data:`KEEP` newest kept), so a
            restart never overwrites the last run's transcript. A path that is a directory,
            or a file that is not a transcript, is refused (:func:`check_path`): nothing is
            renamed.
        controllers: ``{id: {"kind": ..., "config": {...}}}`` of the controllers served, so
            a replay can build fresh ones.
    """

    def __init__(
        self, path: str | Path, controllers: Mapping[str, Mapping[str, Any]] | None = None
    ) -> None:
        self.path = Path(path)
        check_path(self.path)
        rotate(self.path)
        self._file: IO[str] | None = self.path.open("x", encoding="utf-8")
        self._next = 0
        self._write({"kind": "header", "version": 1, "controllers": dict(controllers or {})})

    @classmethod
    def for_handles(cls, path: str | Path, handles: Any) -> Recorder:
        """A recorder whose header describes ``handles`` (``ControllerHandle``s) for replay."""
        return cls(path, {
            h.id: {"kind": h.kind, "config": dict(getattr(h.controller, "config", {}) or {})}
            for h in handles
        })

    def _write(self, obj: dict[str, Any]) -> None:
        if self._file is None:
            return
        self._file.write(json.dumps(obj, separators=(",", ":")) + "\n")
        self._file.flush()

    def open_session(self, protocol: str, controller: str, t: float, peer: str = "") -> int:
        """Start a session; returns its number."""
        self._next += 1
        self._write({"kind": "open", "session": self._next, "protocol": protocol,
                     "controller": controller, "peer": peer, "t": t, "wall": time.time()})
        return self._next

    def record(self, session: int, direction: str, data: bytes, t: float) -> None:
        """Bytes received (``"in"``) or sent (``"out"``) at simulated time ``t``."""
        if data:
            self._write({"kind": direction, "session": session, "t": t, "wall": time.time(),
                         "data": data.decode("latin-1")})

    def close_session(self, session: int, t: float) -> None:
        self._write({"kind": "close", "session": session, "t": t, "wall": time.time()})

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None


#: Earlier transcripts kept beside the current one (``FILE.1`` newest .. ``FILE.5``).
KEEP = 5


def check_path(path: Path) -> None:
    """Refuse a ``--record`` path that must not be rotated away: a directory, something that
    is not a regular file, or a file whose first line is not a transcript header.

    Raises:
        ValueError: naming the path and what it is.
    """
    if not path.exists() and not path.is_symlink():
        return
    if path.is_dir():
        raise ValueError(f"{path} is a directory, not a transcript file")
    if not path.is_file():
        raise ValueError(f"{path} is not a regular file")
    with path.open("rb") as f:
        first = f.readline(4096)
    if not first.strip():
        return  # an empty file: nothing to lose
    try:
        head = json.loads(first)
    except (json.JSONDecodeError, UnicodeDecodeError):
        head = None
    if not isinstance(head, dict) or head.get("kind") != "header":
        raise ValueError(f"{path} exists and is not a motionsim transcript (its first line is "
                         "not a header record): refusing to rename it")


def rotate(path: Path, keep: int = KEEP) -> None:
    """Move an existing ``path`` to ``path.1``, ``path.1`` to ``path.2``, ...; the oldest beyond
    ``keep`` is removed."""
    if not path.exists():
        return
    older = [path.with_name(f"{path.name}.{n}") for n in range(1, keep + 1)]
    if older[-1].exists():
        older[-1].unlink()
    for n in range(keep - 1, 0, -1):
        if older[n - 1].exists():
            older[n - 1].rename(older[n])
    path.rename(older[0])


def read_transcript(path: str | Path) -> Iterator[Record]:
    """The records of a transcript, in order.

    A process killed while writing (``kill -9``, a power cut) can leave its last line cut
    short, without its newline: that line is skipped and a record of kind ``"truncated"``
    (``fields``: ``line``, the line number) ends the iteration instead. Anything else that is
    not JSON is an error naming the line.
    """
    with Path(path).open(encoding="utf-8", errors="replace") as f:
        for n, line in enumerate(f, 1):
            if not line.strip():
                continue
            try:
                obj = json.loads(line)
            except json.JSONDecodeError as exc:
                if not line.endswith("\n"):  # the last line, cut short by the crash
                    yield Record("truncated", fields={"line": n})
                    return
                raise ValueError(f"{path}:{n}: not JSON: {exc.msg}") from None
            yield _record(obj, path, n)


#: What each field of a record must be (checked before a replay uses it).
_FIELD_TYPES: dict[str, tuple[type, ...]] = {
    "session": (int,), "t": (int, float), "wall": (int, float), "data": (str,),
    "protocol": (str,), "controller": (str,), "controllers": (dict,),
}
_NEEDS: dict[str, tuple[str, ...]] = {
    "header": ("controllers",), "open": ("session", "protocol", "controller"),
    "in": ("session", "data"), "out": ("session", "data"), "close": ("session",),
}


def _record(obj: Any, path: str | Path, n: int) -> Record:
    """One decoded line as a :class:`Record`; ValueError naming the line if it is not one."""
    if not isinstance(obj, dict):
        raise ValueError(f"{path}:{n}: a record must be a JSON object")
    kind = obj.pop("kind", None)
    if kind not in _NEEDS:
        raise ValueError(f"{path}:{n}: unknown record kind {kind!r}")
    for name in _NEEDS[kind]:
        if name not in obj:
            raise ValueError(f"{path}:{n}: the {kind!r} record needs {name!r}")
    for name, types in _FIELD_TYPES.items():
        value = obj.get(name)
        if value is not None and (not isinstance(value, types) or isinstance(value, bool)):
            raise ValueError(f"{path}:{n}: field {name!r} is {type(value).__name__}, not "
                             f"{'/'.join(t.__name__ for t in types)}")
    try:
        data = obj.pop("data", "").encode("latin-1")
    except UnicodeEncodeError:
        raise ValueError(f"{path}:{n}: field 'data' holds characters beyond latin-1") from None
    return Record(kind, obj.pop("session", 0), obj.pop("t", 0.0), obj.pop("wall", 0.0),
                  data, obj, n)


__all__ = ["KEEP", "Record", "Recorder", "check_path", "read_transcript", "rotate"]
