"""Kinematic coordinate systems at run time: when the forward and inverse programs run and
what motors ``#n->I`` do (TSRM p181–182 Isx50, p270, p379; TUM p258–267; spec §12.6).

**Data conventions.** Forward: before it runs, ``Pn`` = commanded position (counts) of every
motor ``n`` of the CS; after it, ``Q1…Q9`` of the CS = positions of axes A B C U V W X Y Z.
Inverse: ``Q1…Q9`` = axis positions in, ``Q10`` = 0 (not PVT: no velocities wanted, TUM p265),
``Pn`` = position (counts) of each motor ``#n->I`` out.

**When.** With Isx50 = 1 and the program present: the forward program on every ``R`` / ``S``
to the CS and on ``PMATCH`` (the axes start where the motors are; a motor's own jog offset is
folded in so nothing moves); not on position queries ``[INF]``. The inverse program turns the
axis path into motor positions: once per programmed move at its start (its end point; a
failure there stops the program before the move runs), and for every Isx13 segment of the
path — a motor's position between two segment instants is interpolated linearly between the
inverse results at them ``[INF]`` (the card interpolates with a cubic; with Isx13 = 0, the
segmentation the manual requires for LINEAR / CIRCLE is missing and the inverse is evaluated at
the instant itself). Segment results are computed when a motor position inside the segment is
needed (a query, a status word, an event) and cached, so a program's run costs one inverse
per move; a segment that fails when computed stops the program then.

**Failure** (the manual names none, spec §12.6 ``[INF]``): a motor output left unset, not
finite, or saturated by a division by zero (``|Pn| ≥ 2**47``), or a runaway subroutine: the
program aborts with the run-time error (``??`` word 2 bit 22, ``program`` event with
``error="run_time_error"``), a ``kinematics`` event names the reason, the motor outputs keep
their last good values, no other state changes.
"""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING, Any, Final

from ..card.variables import isx
from ..language import axis_definitions
from ..motor.jog import Profile
from ..tasks.scheduler import wake_at
from .commands import buffer_key
from .subroutine import Q_TAG, KinematicFailure, Subroutine

if TYPE_CHECKING:
    from ..controller import PmacController

#: Axis letters in Q-variable order: Q1 = A … Q9 = Z.
AXES_Q: Final = "ABCUVWXYZ"
_Q_OF: Final = {a: i + 1 for i, a in enumerate(AXES_Q)}
SATURATION: Final = float(2**47)
_CACHE_MAX: Final = 256


class Kinematics:
    """The kinematic coordinate systems of one controller."""

    def __init__(self, ctl: PmacController) -> None:
        self.ctl = ctl
        self._compiled: dict[int, tuple[int, int, Subroutine]] = {}
        self._matched: set[int] = set()
        #: Inverse results by ``(cs, t)``; a move's start drops the later ones of its CS (its
        #: blend changes the path from there on).
        self._cache: dict[tuple[int, float], dict[int, float]] = {}
        self._good: dict[int, float] = {}  # last valid output of each #n->I motor
        self._failing: set[int] = set()
        #: The last ``(cs, t, current move, {motor: counts})`` asked for (motors share it).
        self._last: tuple[int, float, Any, dict[int, float]] | None = None
        self._ver = -1  # vars.version the cached Isx50 / Isx13 belong to
        self._isx: dict[int, tuple[bool, float]] = {}
        self._motor_src: dict[int, tuple[int, str]] = {}
        self._inverse_motors: dict[int, list[int]] = {}

    # -- set-up -----------------------------------------------------------------------------

    def subroutine(self, cs: int, inverse: bool) -> Subroutine | None:
        """The compiled program (compiled again only after its buffer changed), or None."""
        key = buffer_key(cs, inverse)
        progs = self.ctl.programs
        lines = progs.programs.get(key)
        if not lines or progs.editing() == key:
            return None
        have = self._compiled.get(key)
        if have is None or have[0] != id(lines) or have[1] != len(lines):
            code = progs.code(key)
            if code is None:
                return None
            have = (id(lines), len(lines), Subroutine(code))
            self._compiled[key] = have
            self._cache.clear()
            self._last = None
        return have[2]

    def enabled(self, cs: int) -> bool:
        return int(self.ctl.vars.I(isx(cs, 50))) == 1

    def motors(self, cs: int, inverse_only: bool = True) -> list[int]:
        """The motors of ``cs`` (only the ``#n->I`` ones by default)."""
        defs = self.ctl.motors
        if not inverse_only:
            return sorted(n for n, (c, _d) in defs.items() if c == cs)
        if defs != self._motor_src:
            self._motor_src = dict(defs)
            self._inverse_motors = {}
        got = self._inverse_motors.get(cs)
        if got is None:
            got = self._inverse_motors[cs] = sorted(
                n for n, (c, d) in defs.items() if c == cs and d == "I")
        return got

    # -- forward ----------------------------------------------------------------------------

    def forward(self, cs: int) -> dict[str, float]:
        """Run the forward program on the motors' positions now: the axis positions it gives.

        Raises:
            KinematicFailure: no forward program, or it ran away / set no axis.
        """
        sub = self.subroutine(cs, inverse=False)
        if sub is None:
            raise KinematicFailure(f"CS {cs} has no forward-kinematic program")
        ctl = self.ctl
        v = ctl.vars
        now = ctl.env.now
        for n in self.motors(cs, inverse_only=False):
            v.p[n] = ctl.motor_position(n, now)
        written = sub.run(v, cs)
        axes = {a: v.q.get((cs, i + 1), 0.0) for i, a in enumerate(AXES_Q)
                if Q_TAG + i + 1 in written}
        bad = [a for a, x in axes.items() if not math.isfinite(x) or abs(x) >= SATURATION]
        if bad:
            raise KinematicFailure(f"forward kinematics gave no valid {', '.join(bad)}")
        return axes

    def pmatch(self, cs: int) -> None:
        """``PMATCH``: axis positions from motor positions; the motors stay where they are."""
        ctl = self.ctl
        c = ctl.coord_system(cs)
        now = ctl.env.now
        before = {n: ctl.motor_position(n, now) for n in self.motors(cs, inverse_only=False)}
        if self.enabled(cs) and self.subroutine(cs, inverse=False) is not None:
            try:
                axes = self.forward(cs)
            except KinematicFailure as e:
                ctl.log.emit("kinematics", cs=cs, program="forward", error=str(e))
                return
        else:
            axes = {}
            for n in self.motors(cs, inverse_only=False):
                have = ctl._motor_axis(n)
                if have is not None and have[1] in AXES_Q and have[2] != 0:
                    offset = axis_definitions.lookup(ctl.motors[n][1]).offset
                    axes[have[1]] = (before[n] - offset) / have[2]
        c.rest_pos = {**c.rest_pos, **axes}
        c.calc_pos = {**c.calc_pos, **axes}
        self._matched.add(cs)
        self._cache.clear()
        self._last = None
        for n, pos in before.items():
            motor = ctl.motor_table[n]
            if motor.command is None:  # at rest: its jog offset becomes what the new axes
                motor.profile = Profile.rest(now, 0.0)  # leave, so the motor stays put
                motor.profile = Profile.rest(now, pos - ctl.motor_position(n, now))
        ctl.log.emit("pmatch", cs=cs, axes=axes)

    def program_start(self, cs: int) -> None:
        """``R`` / ``S``: with Isx50 = 1 the forward program sets the starting axes, and moves
        go through the inverse program."""
        c = self.ctl.coord_system(cs)
        if not self.enabled(cs) or c.running:
            return
        if self.subroutine(cs, inverse=False) is not None:
            self.pmatch(cs)
        self._failing.discard(cs)
        has_inverse = bool(self.motors(cs)) and self.subroutine(cs, inverse=True) is not None
        c.on_move_start = partial(self._move_started, cs) if has_inverse else None

    # -- inverse ----------------------------------------------------------------------------

    def inverse(self, cs: int, axes: dict[str, float]) -> dict[int, float]:
        """Motor positions (counts) of the ``#n->I`` motors for ``axes``.

        Raises:
            KinematicFailure: no inverse program, an output unset / not finite / saturated,
                or a runaway subroutine; the outputs are restored.
        """
        sub = self.subroutine(cs, inverse=True)
        if sub is None:
            raise KinematicFailure(f"CS {cs} has no inverse-kinematic program")
        v = self.ctl.vars
        q, p = v.q, v.p
        for a, x in axes.items():
            i = _Q_OF.get(a)
            if i is not None:
                q[(cs, i)] = x
        q[(cs, 10)] = 0.0
        motors = self.motors(cs)
        saved = [(n, p.get(n, 0.0)) for n in motors]
        written = sub.run(v, cs)
        out: dict[int, float] = {}
        for n in motors:
            x = p.get(n, 0.0)
            if n not in written or not -SATURATION < x < SATURATION:  # NaN fails too
                p.update(saved)
                why = "was not set" if n not in written else f"= {x}"
                raise KinematicFailure(f"inverse kinematics: P{n} {why}")
            out[n] = x
        return out

    def _point(self, cs: int, t: float) -> dict[int, float]:
        ctl = self.ctl
        c = ctl.coord_systems[cs]
        key = (cs, t)
        got = self._cache.get(key)
        if got is None:
            try:
                got = self.inverse(cs, c.positions(t))
            except KinematicFailure as e:
                self._fail(cs, str(e))
                got = {n: self._good.get(n, 0.0) for n in self.motors(cs)}
            else:
                self._good.update(got)
            if len(self._cache) >= _CACHE_MAX:
                self._cache.clear()
            self._cache[key] = got
        return got

    def motor_base(self, cs: int, motor: int, t: float) -> float:
        """Position (counts) motor ``#motor->I`` of ``cs`` takes from the axes at ``t``."""
        c = self.ctl.coord_systems[cs]
        last = self._last
        if last is not None and last[0] == cs and last[1] == t and last[2] is c.current:
            return last[3].get(motor, 0.0)
        at = self._motors_at(cs, c, t)
        self._last = (cs, t, c.current, at)
        return at.get(motor, 0.0)

    def _settings(self, cs: int) -> tuple[bool, float]:
        """``(Isx50 = 1, Isx13 in seconds)`` of ``cs``, cached until a variable changes."""
        v = self.ctl.vars
        if v.version != self._ver:
            self._ver = v.version
            self._isx = {}
        isx_ = self._isx.get(cs)
        if isx_ is None:
            isx_ = self._isx[cs] = (int(v.I(isx(cs, 50))) == 1, v.I(isx(cs, 13)) / 1000.0)
        return isx_

    @staticmethod
    def _segment_start(t0: float, ts: float, t: float) -> float:
        """The Isx13 segment instant at or before ``t`` of segments starting at ``t0``."""
        return t0 + math.floor((t - t0) / ts + 1e-9) * ts

    def _motors_at(self, cs: int, c: Any, t: float) -> dict[int, float]:
        isx_ = self._settings(cs)
        if cs not in self._matched or not isx_[0]:
            return {}
        ts = isx_[1]
        if ts <= 0 or c.current is None:
            return self._point(cs, t)
        ta = self._segment_start(c._seg_t0, ts, t)
        a = self._point(cs, ta)
        frac = (t - ta) / ts
        if frac < 1e-9:
            return a
        b = self._point(cs, ta + ts)
        return {n: x + (b.get(n, x) - x) * frac for n, x in a.items()}

    def _move_started(self, cs: int, m: Any, t: float) -> None:
        """A move of ``cs`` starts executing at ``t``; called just before it becomes the CS's
        current move. The segment instant at or before ``t`` lies on the path executed so far:
        its inverse result is computed now, from that path, so a motor position asked later in
        this segment interpolates from where the motors were, not from the new move's profile
        read before its start (a position no longer depends on whether it was asked before).
        Segment results after ``t`` computed from the old path are dropped. The move's end
        point must have an inverse solution."""
        c = self.ctl.coord_systems[cs]
        if c.current is not None and cs in self._matched:
            on, ts = self._settings(cs)
            if on and ts > 0:
                ta = self._segment_start(c._seg_t0, ts, t)
                if ta < t - 1e-12:
                    self._point(cs, ta)
        cache = self._cache
        stale = [k for k in cache if k[0] == cs and k[1] >= t - 1e-12]
        for k in stale:
            del cache[k]
        self._last = None
        end = getattr(m, "end", None)
        if not end:
            return
        axes = {**self.ctl.coord_systems[cs].rest_pos, **end}
        try:
            self._good.update(self.inverse(cs, axes))
        except KinematicFailure as e:
            self._fail(cs, str(e))

    def _fail(self, cs: int, reason: str) -> None:
        """Stop the program of ``cs`` with the run-time error (once per run)."""
        ctl = self.ctl
        c = ctl.coord_systems[cs]
        if cs in self._failing or not c.running:
            return
        self._failing.add(cs)
        ctl.log.emit("kinematics", cs=cs, program="inverse", error=reason)
        wake_at(ctl.env, ctl.env.now, lambda _e: c.abort("run_time_error"))


__all__ = ["AXES_Q", "Kinematics"]
