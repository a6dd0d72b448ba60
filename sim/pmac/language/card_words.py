"""Builders of the card-memory and kinematics command words (rows and objects of
:mod:`.keywords`): ``DEFINE UBUFFER n``, ``DELETE ALL``, ``DELETE TRACE``,
``OPEN FORWARD`` / ``OPEN INVERSE``,
``UNDEFINE [ALL]``, ``PMATCH``, and the kinematics statements. They run through their rows
of :mod:`motionsim.sim.pmac.host.commands` (handlers in
:mod:`motionsim.sim.pmac.card.user_buffer` and :mod:`motionsim.sim.pmac.kinematics.commands`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..card.user_buffer import DefineUbuffer, DeleteAll

Token = tuple[str, str, int, int]


def define_ubuffer(p: Any) -> DefineUbuffer:
    """``DEFINE UBUFFER {words}`` (after the object word)."""
    tok = p.peek()
    words = p.integer()
    if words < 1:
        raise p.error("DEFINE UBUFFER needs a size of at least 1 word", tok)
    return DefineUbuffer(words)


def delete_all(p: Any) -> DeleteAll:
    return DeleteAll()


@dataclass(frozen=True, slots=True)
class DeleteTrace:
    """``DELETE TRACE``: erase the card's motion-program trace buffer ``[BK]`` (Delta Tau's
    set-up tool writes it after ``DELETE GATHER`` at the top of a Clipper start-up file;
    the Turbo page was not retrieved). No trace buffer is simulated, so there is nothing to
    erase: the command is accepted and changes nothing. An on-line command only."""

    @property
    def in_program(self) -> bool:
        return False



@dataclass(frozen=True, slots=True)
class OpenKinematic:
    """``OPEN FORWARD`` (``inverse`` False) / ``OPEN INVERSE``."""

    inverse: bool
    opens_buffer = True  # the parser stores the lines that follow


@dataclass(frozen=True, slots=True)
class Pmatch:
    """``PMATCH``."""


@dataclass(frozen=True, slots=True)
class Undefine:
    """``UNDEFINE`` / ``UNDEFINE ALL``."""

    every_cs: bool


def delete_trace(p: Any) -> DeleteTrace:
    return DeleteTrace()


def open_kinematic(name: str) -> OpenKinematic:
    return OpenKinematic(inverse=name == "INVERSE")


def undefine(p: Any, tok: Token) -> Undefine:
    """``UNDEFINE`` / ``UNDEFINE ALL``."""
    nxt = p.peek()
    every = nxt is not None and nxt[0] == "word" and nxt[1] == "ALL"
    if every:
        p.take()
    return Undefine(every_cs=every)


def pmatch(p: Any, tok: Token) -> Pmatch:
    return Pmatch()


__all__ = [
    "DeleteTrace", "OpenKinematic", "Pmatch", "Undefine", "define_ubuffer", "delete_all",
    "delete_trace", "open_kinematic", "pmatch", "undefine",
]  # fmt: skip
