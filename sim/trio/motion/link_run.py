"""One CAMBOX / MOVELINK as it runs: link-axis progress, start at ``link_pos``, repeat
cycles, REP_OPTION's end of cycle, positive-only links, and CAMBOX's pattern mode.

Advanced once per servo period (:meth:`LinkRun.tick`, spec §10.3 ``[INF]``: the slave
demand is computed from the link axis' position each servo tick). The progress ``u`` is the
link-axis distance moved since the start of the current cycle (only positive steps with
link_options bit 5). A cycle is ``link_dist`` long; its displacement ``cycle(x, mult)`` (the
cam shape or MOVELINK's ratio profile at ``x`` along it) is added to the position the cycle
started from. Without the repeat bit the move ends when one cycle is done (MOVELINK: link
movement in either direction counts, MOVELINK-MD; CAMBOX: the cam runs backwards when the link
axis does, TJ2P-56). With the repeat bit (4) cycles follow each other in either direction
until REP_OPTION bit 1 is set on the base axis: the move then ends at the end of the cycle
under way and the bit is cleared again (CAMBOX-MD: "the firmware resets bit 1").

Pattern mode (CAMBOX bit 3, M206-213, CAMBOX-MD): the 7-value control block at ``cb`` in the
TABLE — 0 current pattern position, 1 force position (-1 = none), 2 / 3 first / last pattern
value, 4 repeat position, 5 repeat count (-1 = endless), 6 next control block (-1 = finish) —
picks each cycle's multiplier: ``TABLE(CB(0))``. At the end of every cycle CB(0) moves on (or
to CB(1) when the program wrote one, which then reads -1 again); past CB(3) the pattern
repeats from CB(2) and CB(4) counts up; when \\|CB(4)\\| reaches CB(5) the CAMBOX ends, or
continues with the control block CB(6). The program may write CB(1), CB(4), CB(5), CB(6)
while it runs (CB(5) = 0 ends it at the end of the pattern). Only forward cycles step the
pattern here ``[INF]``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from ..card.basic_errors import BasicError
from .link_options import PATTERN, POSITIVE_ONLY, REPEAT, START_AT_POS

if TYPE_CHECKING:
    from .axis import Axis

Cycle = Callable[[float, float], float]
_EPS = 1e-9


class LinkRun:
    """The running state of one CAMBOX / MOVELINK."""

    __slots__ = ("kind", "options", "length", "link", "link_pos", "base", "table", "cycle",
                 "mult", "cb", "u", "m_last", "waiting", "p_cycle", "finished",
                 "m_end")

    def __init__(self, kind: str, options: int, length: float, link: Axis, link_pos: float,
                 base: Axis, table: dict[int, float], cycle: Cycle, mult: float) -> None:
        self.kind, self.options, self.length = kind, options, length
        self.link, self.link_pos, self.base = link, link_pos, base
        self.table, self.cycle, self.mult = table, cycle, mult
        self.cb = -1
        self.u = 0.0
        self.m_last = 0.0
        self.waiting = bool(options & START_AT_POS)
        self.p_cycle = 0.0
        self.finished = False
        self.m_end = 0.0  # link position where the move's link distance was complete

    def start(self, t: float, p0: float) -> None:
        self.m_last = self.link.position(t)
        self.p_cycle = p0
        if self.options & PATTERN:
            self.cb = int(self.mult)
            self.mult = self._pattern_value()

    # -- the control block -----------------------------------------------------------------

    def _tv(self, i: float) -> float:
        return self.table.get(int(i), 0.0)

    def _pattern_value(self) -> float:
        return self._tv(self._tv(self.cb))

    def _next_pattern(self) -> bool:
        """One cycle done: step the pattern; False when the CAMBOX ends."""
        cb, tv, table = self.cb, self._tv, self.table
        force = tv(cb + 1)
        if force != -1:
            table[cb], table[cb + 1] = force, -1.0
        else:
            cur = tv(cb) + 1
            if cur > tv(cb + 3):
                cur = tv(cb + 2)
                rep = tv(cb + 4) + 1
                table[cb + 4] = rep
                count = tv(cb + 5)
                if count != -1 and abs(rep) >= count:
                    nxt = tv(cb + 6)
                    if nxt == -1:
                        return False
                    self.cb = cb = int(nxt)
                    cur = tv(cb)
            table[cb] = cur
        self.mult = self._pattern_value()
        return True

    # -- per servo period ------------------------------------------------------------------

    def tick(self, t: float) -> bool:
        """One servo period at instant ``t``; True when the move has ended."""
        m = self.link.position(t)
        if self.waiting:
            lp, prev = self.link_pos, self.m_last
            self.m_last = m
            if (prev - lp) * (m - lp) > 0.0 or (m == prev and m != lp):
                return False
            self.waiting = False
            prev = lp
        else:
            prev = self.m_last
        dm = m - prev
        self.m_last = m
        if self.options & POSITIVE_ONLY and dm < 0.0:
            dm = 0.0
        self.u += dm
        length = self.length
        if not self.options & (REPEAT | PATTERN):
            done = (abs(self.u) if self.kind == "MOVELINK" else self.u) >= length - _EPS
            if done:
                self.p_cycle += self.cycle(length, self.mult)
                self.finished = True
                over = abs(self.u) - length
                self.m_end = m - (over if dm >= 0.0 else -over)
            return done
        while self.u >= length - _EPS:
            self.p_cycle += self.cycle(length, self.mult)
            self.u -= length
            if self._cycle_end():
                self.finished = True
                self.m_end = m - self.u
                return True
        while self.u < -_EPS and self.options & REPEAT:
            self.u += length
            self.p_cycle -= self.cycle(length, self.mult)
        return False

    def _cycle_end(self) -> bool:
        """A forward cycle is complete: True when the move ends here."""
        if self.options & REPEAT:
            rep = self.base.stored.values
            opt = int(rep["REP_OPTION"])
            if opt & 2:
                rep["REP_OPTION"] = float(opt & ~2)
                return True
        if self.options & PATTERN:
            return not self._next_pattern()
        return not self.options & REPEAT

    # -- reads -----------------------------------------------------------------------------

    def position(self) -> float:
        if self.waiting or self.finished:
            return self.p_cycle
        x = abs(self.u) if self.kind == "MOVELINK" and not self.options & REPEAT else self.u
        x = min(max(x, 0.0), self.length) if self.kind == "MOVELINK" else x
        return self.p_cycle + self.cycle(x, self.mult)

    def remain(self) -> float:
        """REMAIN: link distance still to go in this cycle."""
        if self.finished:
            return 0.0
        return max(0.0, self.length - abs(self.u))

    def shift_link(self, offset: float) -> None:
        self.m_last += offset
        if self.waiting:
            self.link_pos += offset

    def shift_base(self, offset: float) -> None:
        self.p_cycle += offset


def check_pattern(table: dict[int, float], cb: float, size: int) -> None:
    """A pattern-mode control block must lie in the TABLE (BasicError)."""
    if cb != int(cb) or not 0 <= cb <= size - 7:
        raise BasicError(f"CAMBOX pattern mode: control block TABLE({cb:g}) out of range")


__all__ = ["LinkRun", "check_pattern"]
