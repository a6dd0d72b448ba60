"""The special lookahead buffer of a coordinate system: ``DEFINE LOOKAHEAD`` / ``DELETE
LOOKAHEAD`` and when the lookahead is active.

From the manuals (TSRM p308-309 DEFINE LOOKAHEAD, p315 DELETE LOOKAHEAD, p181 Isx20, p98
Ixx16; TUM p310; spec §1.3, §9.2, §11.3):

* ``DEFINE LOOKAHEAD {segments},{outputs}`` reserves, for the addressed CS, room for
  ``segments`` motion segments (Isx20 plus any back-up segments) and ``outputs`` synchronous
  M-variable assignments. It is not kept through a reset or power cycle, even after ``SAVE``,
  so hosts send it after every reset (the DLS Geo Brick PLC1 defines ``50,10`` from CS 16
  down to CS 3).
* Refused with ERR003 while any ROTARY or GATHER buffer exists, and when a lower-numbered CS
  already has a lookahead buffer: lookahead buffers are defined from the highest CS down and
  deleted from the lowest up (``DELETE LOOKAHEAD`` is refused while a lower-numbered CS still
  has one, or a rotary / gather buffer exists).
* The special lookahead is **active** when the CS is in segmentation mode (Isx13 > 0), has a
  lookahead buffer and Isx20 > 0; only then do Ixx16 / Ixx17 apply to segmented LINEAR and
  CIRCLE moves (TSRM p98: "not used ... when the special lookahead buffer is not active").

``[INF]``: defining a second buffer for the same CS is refused (ERR003); both constants must
be positive whole numbers ("a positive integer", TSRM p308); the buffer's memory is not taken
from the 65 536 words the rotary buffers share (its size per segment was not found); deleting
while the CS runs a program is ERR001, as ``DELETE ROT``; a CS with no buffer deletes nothing.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Protocol

from ...errors import Conflict, InvalidValue


@dataclass(frozen=True, slots=True)
class LookaheadBuffer:
    """What ``DEFINE LOOKAHEAD`` reserved: motion segments and synchronous outputs."""

    segments: int
    outputs: int


class _Coord(Protocol):
    @property
    def lookahead(self) -> LookaheadBuffer | None: ...
    @lookahead.setter
    def lookahead(self, buf: LookaheadBuffer | None) -> None: ...
    @property
    def rotary(self) -> object | None: ...

    @property
    def running(self) -> bool: ...


def _refuse_with_buffers(coords: Mapping[int, _Coord], gather: bool, what: str) -> None:
    if gather:
        raise Conflict(f"a gather buffer exists: DELETE GATHER before {what}", pmac_error="ERR003")
    rot = [n for n, c in coords.items() if c.rotary is not None]
    if rot:
        raise Conflict(
            f"CS {rot[0]} has a rotary buffer: DELETE ROT before {what}", pmac_error="ERR003"
        )


def _refuse_if_lower(coords: Mapping[int, _Coord], cs: int, why: str) -> None:
    """ERR003 if a CS numbered below ``cs`` has a lookahead buffer (``why``: the rule)."""
    lower = [n for n, c in coords.items() if n < cs and c.lookahead is not None]
    if lower:
        raise Conflict(
            f"CS {lower[0]} (lower-numbered) has a lookahead buffer: {why}", pmac_error="ERR003"
        )


def define(
    coords: Mapping[int, _Coord], cs: int, segments: int, outputs: int, gather: bool
) -> None:
    """``&cs DEFINE LOOKAHEAD segments,outputs`` (``gather``: a gather buffer exists)."""
    for name, value in (("segments", segments), ("outputs", outputs)):
        if isinstance(value, bool) or not isinstance(value, int) or value < 1:
            raise InvalidValue(f"{name} must be a positive whole number", field=name)
    _refuse_with_buffers(coords, gather, "DEFINE LOOKAHEAD")
    _refuse_if_lower(coords, cs, "define lookahead buffers from the highest-numbered CS down")
    if coords[cs].lookahead is not None:
        raise Conflict(f"CS {cs} already has a lookahead buffer", pmac_error="ERR003")
    coords[cs].lookahead = LookaheadBuffer(segments, outputs)


def delete(coords: Mapping[int, _Coord], cs: int, gather: bool) -> None:
    """``&cs DELETE LOOKAHEAD``."""
    c = coords[cs]
    if c.lookahead is None:
        return
    _refuse_with_buffers(coords, gather, "DELETE LOOKAHEAD")
    _refuse_if_lower(coords, cs, "delete lookahead buffers from the lowest-numbered CS up")
    if c.running:
        raise Conflict(f"CS {cs} is running its program", pmac_error="ERR001")
    c.lookahead = None


__all__ = ["LookaheadBuffer", "define", "delete"]
