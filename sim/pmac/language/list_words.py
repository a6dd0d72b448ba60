"""``LIST {buffer} [n][,start[,len]]`` as a statement: what the parser reads after ``LIST``.

How a listing is answered is :mod:`motionsim.sim.pmac.host.list_commands` (the forms and
their sources are in its docstring).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

#: Buffer words after LIST -> the buffer listed.
_BUFFERS = {
    "PLC": "PLC", "PROGRAM": "PROG", "PROG": "PROG", "ROTARY": "ROT", "ROT": "ROT",
    "FORWARD": "FORWARD", "INVERSE": "INVERSE", "GATHER": "GATHER", "GAT": "GATHER",
}  # fmt: skip
_NUMBERED = ("PLC", "PROG")


@dataclass(frozen=True, slots=True)
class ListBuffer:
    """``LIST {buffer} [n][,start[,len]]``."""

    buffer: str
    number: int | None = None
    start: int | None = None
    length: int | None = None


def parse(p: Any) -> ListBuffer:
    """Read a LIST command after the ``LIST`` word from parser ``p`` (``motionsim.sim.pmac
    .parser._Parser``)."""
    tok = p.take()
    if tok[0] == "word" and tok[1] == "PLCC":
        # [INF] the card holds a compiled PLC as machine code from the PC-side compiler, not
        # its text; the SRM lists no LIST PLCC, so the card does not recognise it (ERR003).
        raise p.error("LIST PLCC: the card keeps no source text for a compiled PLC "
                      "(list the source on the PC; LIST PLC lists interpreted PLCs)", tok)
    buffer = _BUFFERS.get(tok[1]) if tok[0] == "word" else None
    if buffer is None:
        raise p.error("LIST what? (PLC, PROG, ROT, FORWARD, INVERSE, GATHER)", tok)
    number = p.integer() if buffer in _NUMBERED else None
    start = length = None
    if p.at("op", ","):
        p.take()
        start = p.integer()
        if p.at("op", ","):
            p.take()
            length = p.integer()
    return ListBuffer(buffer, number, start, length)


__all__ = ["ListBuffer", "parse"]
