"""The card's listing format, shared by every ``LIST`` of a program buffer (PLC, PROG, ROT,
FORWARD/INVERSE kinematics).

A Turbo PMAC stores programs compiled and lists them decompiled, so a listing is not the text
that was sent. What a real listing looks like (captured from a DLS Geo Brick, spec pmac.md
§11.8, dls-pmacanalyse ``tests/data/plc1.listing.py``; rules ``[INF]`` from that capture):

* comments dropped, upper case, blanks removed outside ``"..."`` strings;
* short keywords (I9 bit 0 = 0, the factory setting): ``ENDWHILE``→``ENDW``, ``ENDIF``→``ENDI``,
  ``ENABLE PLC``→``ENAPLC``, ``DISABLE PLC``→``DISPLC``, ``ADDRESS``→``ADR``, ``COMMAND``→``CMD``,
  ``RETURN``→``RET``, ``DWELL``→``DWE``, ``DELAY``→``DLY``, ``LINEAR``→``LIN``, ``RAPID``→``RPD``,
  ``CIRCLE``→``CIR``;
* constants as the card holds them: hex ``$60000`` listed ``393216``, ``0.50`` listed ``0.5``;
* every PLC and PROG listing ends with a ``RET`` the card adds;
* with offsets (``LIST PLC n,start,len``) each line is ``{offset}:{text}``, the offset being
  the line's word address in the buffer; the window lists the lines whose offset lies in
  ``[start, start+len)``; a start beyond the last line is answered ERR003 (this is how
  dls-pmacanalyse's chunked read ends).

Word cost of a listed line (``[INF]``, fitted to that capture: ``M4900=1`` 2 words,
``IF(M4900=0)`` 3, ``I5112=1000*8388608/I10`` 4, ``ENDW`` 2, ``CMD"DEFINE LOOKAHEAD 50,10"`` 8,
keywords 1): one word per value (constant or variable), one more for ``IF``; strings one
word per three characters; ``ENDW`` 2; ``ENA``/``DIS`` and anything else 1.
"""

from __future__ import annotations

import math
import re
import threading
from collections.abc import Callable, Iterable, Sequence
from typing import Any, Final

from ..card.variables import format_value

#: Long keyword -> the short form the card lists (I9 bit 0 = 0).
SHORT: Final[dict[str, str]] = {
    "ENDWHILE": "ENDW", "ENDIF": "ENDI", "ENABLE": "ENA", "DISABLE": "DIS",
    "ADDRESS": "ADR", "COMMAND": "CMD", "RETURN": "RET", "DWELL": "DWE", "DELAY": "DLY",
    "LINEAR": "LIN", "RAPID": "RPD", "CIRCLE": "CIR", "ROTARY": "ROT", "GATHER": "GAT",
    "O": "N",
}  # fmt: skip

_TOKEN: Final = re.compile(
    r'(?P<str>"[^"]*"?)|(?P<comment>;.*)|(?P<hex>\$[0-9A-Fa-f]+)|(?P<range>\.\.)'
    r"|(?P<num>\d*\.\d+|\d+(?:\.(?!\.)\d*)?)|(?P<word>[A-Za-z]+)|(?P<blank>\s+)|(?P<other>.)"
)
#: ``END IF`` / ``END WHILE`` written with blanks: one keyword (spec §12.1).
_END_BLANK: Final = re.compile(r"(?i)\bEND\s+(IF|WHILE)\b")
_VALUE: Final = re.compile(r"\d|[IPQM]\d|[IPQM]\(")

#: One listed program line: (word offset, text).
Entry = tuple[int, str]


def canonical(source: str) -> str:
    """A program line as the card lists it (``IF (runFlag = 0) ; c`` → ``IF(RUNFLAG=0)``;
    ``End If`` → ``ENDI``; an ``O`` label as ``N``, TSRM p458). A one-line ``ELSE`` keeps one
    blank before its statement (``ELSE X-10``, spec §12.9 ``[INF]``): ``ELSEX-10`` would not
    read back as an ELSE."""
    out: list[str] = []
    source = _END_BLANK.sub(r"END\1", source)
    for m in _TOKEN.finditer(source):
        kind = m.lastgroup
        text = m.group()
        if kind in ("comment", "blank"):
            continue
        if out and out[-1] == "ELSE":
            out.append(" ")
        if kind == "hex":
            out.append(str(int(text[1:], 16)))
        elif kind == "num":
            out.append(format_value(float(text)))
        elif kind == "word":
            word = text.upper()
            out.append(SHORT.get(word, word))
        else:
            out.append(text)
    return "".join(out)


def words(listed: str) -> int:
    """The buffer words a listed line takes (see the module docstring, ``[INF]``)."""
    if listed == "ENDW":
        return 2
    strings = re.findall(r'"([^"]*)"', listed)
    if strings:
        return max(1, sum(math.ceil((len(s) + 2) / 3) for s in strings))
    if listed.startswith(("ENA", "DIS")):
        return 1
    values = len(_VALUE.findall(re.sub(r"\d+", "0", listed)))
    return max(1, values + (1 if listed.startswith("IF") else 0))


def _plc_lines(listed: str) -> list[str]:
    """A PLC line as the card stores it: a one-line ``ELSE`` is not a PLC form, the card
    moves its statements to the next program line (PSRM p313), so it lists as two."""
    if listed.startswith("ELSE "):
        return ["ELSE", listed[5:]]
    return [listed]


def entries(source_lines: Iterable[str], end: str | None = "RET",
            plc: bool = False) -> list[Entry]:
    """Listed lines with their word offsets from the lines as entered; ``end`` is appended
    (the ``RET`` the card adds to PLC and PROG buffers; ``None`` for a rotary buffer);
    ``plc``: the lines of a PLC program (a one-line ELSE lists as two lines)."""
    out: list[Entry] = []
    offset = 0
    listed = [canonical(s) for s in source_lines]
    if plc:
        listed = [part for text in listed for part in _plc_lines(text)]
    if end is not None:
        listed.append(end)
    for text in listed:
        if not text:
            continue
        out.append((offset, text))
        offset += words(text)
    return out


#: Listings of stored programs by their lines (a tuple: a stored program does not change):
#: a host reads a program in windows, each a ``LIST``, and polls ``PC``; working out the
#: listing of 7 000 lines takes 0.1 s. The last few are kept.
_STORED: dict[tuple[tuple[str, ...], str | None], list[Any]] = {}
_STORED_KEPT = 8
_stored_lock = threading.Lock()  # filled beside the event loop too (api/routes/plcs.py)


def _stored(lines: tuple[str, ...], key: str | None, work: Callable[[], list[Any]]) -> list[Any]:
    with _stored_lock:
        found = _STORED.get((lines, key))
    if found is None:
        found = work()
        with _stored_lock:
            while len(_STORED) >= _STORED_KEPT:
                del _STORED[next(iter(_STORED))]
            _STORED[(lines, key)] = found
    return found


def stored_entries(lines: tuple[str, ...], end: str | None = "RET",
                   plc: bool = False) -> list[Entry]:
    """:func:`entries` of a stored program's ``lines``, worked out once."""
    return _stored(lines, f"{end}|plc" if plc else end, lambda: entries(lines, end, plc))


def stored_offsets(lines: tuple[str, ...]) -> list[int]:
    """The word offset of each of a stored program's ``lines`` and, last, of the ``RET``
    after them (a line listed as nothing takes no words), worked out once."""

    def work() -> list[int]:
        out = [0]
        for text in lines:
            listed = canonical(text)
            out.append(out[-1] + (words(listed) if listed else 0))
        return out

    return _stored(lines, "#offsets", work)


def window(listing: Sequence[Entry], start: int | None = None,
           length: int | None = None) -> list[str] | None:
    """The reply lines of ``LIST ... [,start[,len]]``; None when the card answers ERR003
    (an empty buffer, or a start beyond the last line).

    Without ``start`` the lines are listed without offsets; with it, as ``offset:text``.
    """
    if not listing:
        return None
    if start is None:
        return [text for _, text in listing]
    if start > listing[-1][0]:
        return None
    stop = math.inf if length is None else start + length
    return [f"{off}:{text}" for off, text in listing if start <= off < stop]


__all__ = ["SHORT", "Entry", "canonical", "entries", "stored_entries", "stored_offsets", "window",
           "words"]
