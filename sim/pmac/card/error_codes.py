"""What the Turbo PMAC's ``ERRnnn`` answers mean, for people reading a REST body.

The wire keeps the card's exact ``<BELL>ERRnnn<CR>`` (I6 = 1); the REST terminal and the
error bodies add the meaning from the Turbo SRM's I6 error table (TSRM I6; PSRM p25–26 gives
the same meanings; spec pmac.md §2.2, §11.10). The texts below are our own wording of that
table. ERR020 is in no source found and is never produced ``[INF]``.
"""

from __future__ import annotations

from typing import Final

MEANINGS: Final[dict[str, str]] = {
    "ERR001": "command not allowed while a program is running",
    "ERR002": "password error (protected buffer)",
    "ERR003": "unrecognized command or invalid data (syntax error)",
    "ERR004": "illegal character: a byte above 127, or a serial parity/framing error",
    "ERR005": "command allowed only with a buffer open",
    "ERR006": "no room in the buffer for the command",
    "ERR007": "a buffer is already open (CLOSE it first)",
    "ERR008": "MACRO auxiliary communications error",
    "ERR009": "program structure error (e.g. ENDIF without IF)",
    "ERR010": "both overtravel limits are set for a motor in the coordinate system",
    "ERR011": "the previous move has not completed",
    "ERR012": "a motor in the coordinate system is open-loop",
    "ERR013": "a motor in the coordinate system is not activated",
    "ERR014": "no motors in the coordinate system",
    "ERR015": "not pointing to a valid program buffer (no B command, or a PROG buffer is open)",
    "ERR016": "running an improperly structured program",
    "ERR017": "cannot resume after H or Q: motors are away from the stopped position",
    "ERR018": "phase reference during a move, move during phase reference, or phase clock error",
    "ERR019": "illegal position-change command while moves are stored in CCBUFFER",
}


def meaning(code: str | None) -> str | None:
    """The SRM meaning of ``code`` (``"ERR003"``), or None for no error / an unknown code."""
    return MEANINGS.get(code) if code else None


__all__ = ["MEANINGS", "meaning"]
