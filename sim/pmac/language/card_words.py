"""Parsing of the card-memory and kinematics commands: one hook the main parser calls.

``DEFINE UBUFFER n`` / ``DEL UBUF n``, ``DELETE ALL``, ``UNDEFINE [ALL]``, ``OPEN FORWARD`` /
``OPEN INVERSE`` (``FWD``, ``INV``), ``PMATCH``. The tokenizer splits words it does not
know into letters (``UBUFFER`` is ``U`` ``B`` …), so each form is recognised on the text
after the word already taken (:meth:`_Parser.match_text`). :func:`parse` returns None for
anything else, leaving it to the main parser.
"""

from __future__ import annotations

import re
from typing import Any, Final

from motionsim.sim.pmac.card.user_buffer import DefineUbuffer, DeleteAll
from motionsim.sim.pmac.kinematics.commands import OpenKinematic, Pmatch, Undefine

_UBUFFER: Final = re.compile(r"\s*UBUF(?:FER)?(?![A-Z])", re.IGNORECASE)
_ALL: Final = re.compile(r"\s*ALL(?![A-Z])", re.IGNORECASE)
_UNDEFINE: Final = re.compile(r"NDEF(?:INE)?(?:\s*(ALL))?(?![A-Z])", re.IGNORECASE)
_KIN_BUFFER: Final = re.compile(r"\s*(FORWARD|FWD|INVERSE|INV)(?![A-Z])", re.IGNORECASE)
_PMATCH: Final = re.compile(r"MATCH(?![A-Z])", re.IGNORECASE)


def parse(p: Any, word: str) -> Any | None:
    """The statement starting at ``word`` (already taken from parser ``p``), or None."""
    if word in ("DEFINE", "DEF"):
        if p.match_text(_UBUFFER) is None:
            return None
        tok = p.peek()
        words = p.integer()
        if words < 1:
            raise p.error("DEFINE UBUFFER needs a size of at least 1 word", tok)
        return DefineUbuffer(words)
    if word in ("DELETE", "DEL"):
        return DeleteAll() if p.match_text(_ALL) is not None else None
    if word == "U":
        m = p.match_text(_UNDEFINE)
        return None if m is None else Undefine(every_cs=m.group(1) is not None)
    if word == "OPEN":
        m = p.match_text(_KIN_BUFFER)
        if m is None:
            return None
        return OpenKinematic(inverse=m.group(1).upper().startswith("INV"))
    if word == "P":
        return Pmatch() if p.match_text(_PMATCH) is not None else None
    return None


__all__ = ["parse"]
