"""``PC`` and ``PE``: where the addressed coordinate system's program counter points.

* ``PC`` reports the program and the line being calculated next (the program counter);
* ``PE`` reports the program and the line of the move now executing.

Reply: ``P{program}:{offset}`` (``P1:22``; program 0 is the rotary buffer) ``[BK]`` — the
Turbo SRM on-line command pages for PC / PE (TSRM p260–p420) were not found by ``search``
(pages corpus: "Turbo PMAC on-line command PC report program counter", "PE Report program
number and line of executing move"), so the form is from memory.

Offsets ``[INF]``:

* a fixed PROG: the word offset of the line as ``LIST PROG n,start,len`` numbers it
  (:mod:`motionsim.sim.pmac.host.listing`); at the end of the program the offset of the ``RET``
  the card adds; pointed (``B{n}``) and not yet run: 0, the top;
* the rotary buffer: the line's position in the buffer's numbering from 0 (the REST ``line``
  minus one); its lines are freed as they run, so there is no listing offset to give.

``PE`` with no move executing reports where ``PC`` points ``[INF]``. Both follow into a
``CALL``ed program: ``PE`` names the program whose line the executing move is. A CS that
points at no program (after ``OPEN PROG``, before the next ``B{n}``) answers ERR003
``[INF]``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from ...errors import Conflict
from ..language.statements import ProgramCounter
from . import listing

if TYPE_CHECKING:
    from ..controller import PmacController
    from ..lookahead.coord import CoordSystem


def line_offset(texts: Sequence[str], n: int) -> int:
    """Word offset of 1-based line ``n`` (``n`` >= 1) of a program whose lines are ``texts``
    (``n`` past the last line is the card's closing ``RET``)."""
    offsets = listing.stored_offsets(tuple(texts))  # (polled: worked out once per program)
    return offsets[min(n, len(texts) + 1) - 1]


def report(cmd: ProgramCounter, ctl: PmacController, cs_n: int) -> str:
    """The reply to ``cmd`` for coordinate system ``cs_n``.

    Raises:
        Conflict: ERR003 — the CS points at no program.
    """
    cs = ctl.coord_system(cs_n)
    program = cs.program
    if program is None:
        raise Conflict(f"CS {cs_n} points at no program (B{{n}} first)", pmac_error="ERR003")
    n = _executing_line(cs) if cmd.executing else None
    cur = cs.current
    if n is not None and cur is not None and cur.prog is not None:
        program = cur.prog  # the executing move's program: a CALLed one inside it
    if n is None:
        src = cs.lines()
        where = getattr(src, "where", None)
        if where is not None:  # a fixed program: where its counter is, after any jump
            program, n = where()
        else:
            n = _next_line(cs)
    if program == 0:
        return f"P0:{n - 1}"
    texts = ctl.program_lines(int(program)) or []
    return f"P{int(program)}:{line_offset(texts, n)}"


def _executing_line(cs: CoordSystem) -> int | None:
    """1-based number of the line whose move executes, or None."""
    return None if cs.current is None else int(cs.current.n)


def _next_line(cs: CoordSystem) -> int:
    """1-based number of the line the CS calculates next."""
    src = cs.lines()
    if src is None:
        return 1  # pointed at a PROG, not yet run: the top
    if src.pending:
        return int(src.pending[0][0])
    return int(src.n_loaded) + 1


__all__ = ["ProgramCounter", "line_offset", "report"]
