"""The Turbo PMAC's motors: servo-loop state, jog and home moves, kill, and their positions.

A motor's commanded position (``#nP``, counts) is the position its coordinate-system axis
gives it through its axis definition (``#1->1000X``: 1000 counts per X unit; the program's
moves) plus its own jog displacement, a :class:`motionsim.sim.pmac.motor.jog.Profile` that on-line
jog and home commands drive. Following error is 0: the servo loop tracks perfectly
``[INF]`` (no plant is simulated), so commanded = actual.

On-line motor commands (TSRM p270-283, TUM p217, PSRM p241, p270; spec §11.9), addressed
with ``#n``:

* ``J+`` / ``J-`` jog on at Ixx22; ``J/`` ramps to rest; ``J=`` jogs to the pre-jog position
  (where the motor was when its last jog started from rest); ``J={pos}`` to a position;
  ``J^{d}`` / ``J:{d}`` by ``d`` counts from the actual / commanded position (the same here);
  acceleration from Ixx19-Ixx21 (:mod:`motionsim.sim.pmac.motor.jog`);
* every jog or home command is calculated for Ixx92 ms before it acts: a motor at rest waits
  that long, a moving one keeps its old trajectory that long (TSRM p152); motion starts on a
  servo cycle;
* ``HM`` searches at Ixx23 (sign = direction): "home search in progress" until the trigger,
  "home complete" cleared at the start and set at the trigger; the new zero is the captured
  position + Ixx26 (1/16 count units, TSRM p108), and the motor moves on to it and stops there
  (PUM-V p128-130, TSRM p283). ``[INF]`` no home switch is simulated: the trigger comes the
  first servo cycle the search is at full speed (at once with Ixx23 = 0), so a search always
  ends;
* ``HMZ`` makes the present position zero, without motion ``[BK]``;
* ``K`` kills (loop open, amplifier off, the position stays where it is); ``O{p}`` opens
  the loop at p % output (no plant: the position stays ``[INF]``); ``$`` closes it again
  (motors here are not phased: "just close the loop", TSRM p271), as does ``J/`` and any jog
  or home command ``[INF]``; ``$*`` reads the absolute position — with no absolute sensor
  (Ixx10 = 0) the position becomes 0, home complete is cleared and the motor is left killed
  (TSRM p275);
* software position limits (TSRM p96 Ixx13, PSRM p72 Ix13/Ix14: 0 = that limit off, counted
  from the power-up or home zero): a jog or the post-trigger home move that passes Ixx13 (up)
  or Ixx14 (down) decelerates at Ixx15 from the servo cycle it passes it, like an abort, and
  "stopped on position limit" stays set until the next move command; the limits are off
  during the home search until the trigger, on for the post-trigger move (same pages).
  ``[INF]`` not modelled: the manual's "no further increments in that direction" while past
  the limit — a new jog outward from beyond it runs. No hardware limit switch is
  simulated, so none ever trips ``[INF]`` (Ixx24 bit 17 has nothing to disable);
* a motor whose coordinate system runs a program refuses ``J``, ``HM``, ``K``, ``O`` and
  ``$`` with ERR001 (TSRM p377 for ``O``; ``[INF]`` the others alike).

Events: ``jog`` (``motor``, ``state`` "start"/"end", ``command``, ``position`` in counts) at
the servo cycles motion starts and comes to rest; ``home`` (``motor``, ``state``
"triggered", ``position`` = the captured position before re-zeroing); ``motor`` (``motor``,
``state`` "closed_loop" / "open_loop" / "killed") when the loop state changes.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...errors import Conflict
from ...simpy_adapter import cancel
from ..card.variables import N_MOTORS, Variables, ixx
from ..tasks.scheduler import Scheduler, Wake, wake_at
from . import jog
from .jog import Profile

CLOSED, OPEN, KILLED = "closed_loop", "open_loop", "killed"

#: ``(CS number, axis letter, counts per axis unit)`` of an assigned motor, or None.
AxisOf = Callable[[int], "tuple[int, str, float] | None"]


class Motor:
    """Motor ``n``: loop state, jog displacement profile, homing flags."""

    def __init__(self, n: int, table: MotorTable, t: float) -> None:
        self.n = n
        self._table = table
        self.loop = CLOSED  # [INF] motors come up enabled (Ixx80 not modelled)
        self.output_pct = 0.0
        self.profile = Profile.rest(t, 0.0)
        self.command: str | None = None  # the jog / home move in progress
        self.definite = False  # the move in progress ends at a target (move timer)
        self.homing = False
        self.home_complete = False
        #: A jog-until-trigger is searching for its trigger (``?`` word 1 bit 10 too).
        self.trigger_search = False
        #: ``?`` word 2 bit 7: set at the start of a move-until-trigger, cleared when the
        #: trigger is found; stays set when the move ends without one (TSRM p282).
        self.trigger_move = False
        self.aborting = False
        self.limit_stop = False  # stopped on a position limit (stays set until the next move)
        self.pre_jog = 0.0
        self._wake: Wake | None = None
        #: Called once when the jog / home move in progress ends (a program ``HOME`` waits).
        self.when_stopped: list[Callable[[], None]] = []

    # -- positions ------------------------------------------------------------------------

    def position(self, t: float) -> float:
        """Commanded (= actual) position in counts at ``t``."""
        return self._table.base(self.n, t) + self.profile.position(t)

    def jog_velocity(self, t: float) -> float:
        """Velocity of the jog / home part of the motion, counts/s."""
        return self.profile.velocity(t)

    # -- scheduling -----------------------------------------------------------------------

    def _at(self, t: float, fn: Callable[[Any], None]) -> None:
        """Call ``fn`` at ``t`` (at once when that is now), superseding the pending wake-up."""
        self._cancel()
        env = self._table.sched.env
        if t <= env.now:
            fn(None)
        else:
            self._wake = wake_at(env, t, fn)

    def _cancel(self) -> None:
        cancel(self._wake)
        self._wake = None

    def _emit(self, type_: str, **fields: Any) -> None:
        self._table.emit(type_, motor=self.n, **fields)

    def _set_loop(self, loop: str) -> None:
        if loop != self.loop:
            self.loop = loop
            self._emit("motor", state=loop)

    # -- commands -------------------------------------------------------------------------

    def _rate(self, speed: float) -> float:
        v = self._table.vars
        n = self.n
        return jog.ramp_rate(speed, v.I(ixx(n, 19)), v.I(ixx(n, 20)), v.I(ixx(n, 21)))

    def _start_time(self) -> float:
        """Ixx92 ms after now, on a servo cycle (TSRM p152)."""
        sched = self._table.sched
        i92 = max(0.0, self._table.vars.I(ixx(self.n, 92)))
        return sched.servo_at_or_after(sched.env.now + i92 / 1000.0)

    def jog(self, command: str, value: float | None = None,
            trigger: float | None = None) -> None:
        """``J+`` ``J-`` ``J/`` ``J=`` ``J=pos`` ``J^d`` ``J:d`` (``command`` is the text up to
        the value); with ``trigger`` a definite jog is a jog-until-trigger that ends
        ``trigger`` counts past the captured trigger position."""
        v = self._table.vars
        now = self._table.sched.env.now
        speed = abs(v.I(ixx(self.n, 22)))  # cts/ms
        rate = self._rate(speed)
        t0 = self._start_time()
        p0 = self.profile.position(t0)
        v0 = self.profile.velocity(t0)
        pre_jog = self.pre_jog
        if self.command is None and v0 == 0:
            self.pre_jog = self.position(now)
        base = self._table.base(self.n, t0)
        if command in ("J+", "J-", "J/"):
            v1 = 0.0 if command == "J/" else (speed if command == "J+" else -speed) * 1000.0
            new = jog.to_velocity(t0, p0, v0, v1, rate)
            self.definite = False
        else:
            if command == "J=" and value is None:
                target = pre_jog
            elif command == "J=":
                target = float(value)  # type: ignore[arg-type]
            else:  # J^ / J: relative to the actual / commanded position (the same here)
                target = self.position(now) + float(value or 0.0)
            new = jog.to_position(t0, p0, v0, target - base, speed * 1000.0, rate)
            self.definite = True
        until = trigger is not None and self.definite
        self.trigger_move = self.trigger_search = until
        self._begin(command, new, self._until_trigger(new, trigger) if until else None)

    def _until_trigger(self, move: Profile, after: float | None) -> Callable[[], None] | None:
        """What a jog-until-trigger arms when it starts (``[INF]`` as for ``HM``: no flag
        input is simulated, so the trigger comes the first servo cycle the jog runs at full
        speed; a move too short to reach full speed ends at its target with no trigger)."""
        cruise = next((s.t0 for s in move.segments if s.a == 0 and s.v0 != 0), None)
        if cruise is None or after is None:
            return None
        t_trig = self._table.sched.servo_at_or_after(cruise)

        def armed() -> None:
            hit = self._limit_crossing()
            if hit is not None and hit < t_trig:
                self._schedule_end()  # a software limit comes first
            else:
                self._at(t_trig, lambda _e: self._jog_trigger(after))

        return armed

    def _jog_trigger(self, after: float) -> None:
        """The trigger of a jog-until-trigger: capture the position, move on to capture +
        ``after`` at Ixx22 (no change of the motor's zero, PSRM p241)."""
        self._wake = None
        now = self._table.sched.env.now
        capture = self.position(now)
        self.trigger_move = self.trigger_search = False
        self._emit("jog", state="triggered", command=self.command, position=self._pos_now())
        speed = abs(self._table.vars.I(ixx(self.n, 22)))
        base = self._table.base(self.n, now)
        on = jog.to_position(now, self.profile.position(now), self.profile.velocity(now),
                             capture + after - base, speed * 1000.0, self._rate(speed))
        self.profile = self.profile.then(on)
        self._schedule_end()

    def home(self) -> None:
        """``HM``: the home search (module docstring)."""
        v = self._table.vars
        i23 = v.I(ixx(self.n, 23))
        rate = self._rate(i23)
        t0 = self._start_time()
        p0 = self.profile.position(t0)
        v0 = self.profile.velocity(t0)
        search = jog.to_velocity(t0, p0, v0, i23 * 1000.0, rate)
        self.homing = True
        self.home_complete = False
        self.definite = self.trigger_move = self.trigger_search = False
        ramp_end = search.segments[-1].t0
        t_trig = self._table.sched.servo_at_or_after(ramp_end)
        if t_trig > t0:
            self._begin("HM", search, lambda: self._at(t_trig, self._trigger))
        else:
            self._begin("HM", search, lambda: self._trigger(None))

    def _begin(self, command: str, new: Profile,
               then: Callable[[], None] | None = None) -> None:
        """Take ``new`` as the motion from its first instant; when it starts, emit ``jog``
        "start" and call ``then`` (default: wake at its end or a software limit)."""
        self._close_loop()
        self.aborting = self.limit_stop = False
        self.profile = self.profile.then(new)
        self.command = command
        t0 = new.segments[0].t0
        self._at(t0, lambda _e: self._started(then or self._schedule_end))

    def _started(self, then: Callable[[], None]) -> None:
        self._emit("jog", state="start", command=self.command, position=self._pos_now())
        then()

    def _schedule_end(self) -> None:
        """Wake at the end of the move, or where it first passes a software limit."""
        sched = self._table.sched
        hit = None if self.command == "HM" else self._limit_crossing()
        if hit is not None:
            self._at(sched.servo_at_or_after(hit), self._limit_hit)
            return
        t_end = self.profile.t_end
        if t_end is not None:
            self._at(sched.servo_at_or_after(t_end), self._ended)

    def soft_limits(self) -> tuple[float | None, float | None]:
        """Ixx13 / Ixx14 in counts (0 = that limit off; TSRM p96, PSRM p72)."""
        v = self._table.vars
        hi, lo = v.I(ixx(self.n, 13)), v.I(ixx(self.n, 14))
        return (hi if hi != 0 else None), (lo if lo != 0 else None)

    def _limit_crossing(self) -> float | None:
        now = self._table.sched.env.now
        base = self._table.base(self.n, now)
        hi, lo = self.soft_limits()
        hits = []
        if hi is not None:
            hits.append(self.profile.crossing(now, hi - base, rising=True))
        if lo is not None:
            hits.append(self.profile.crossing(now, lo - base, rising=False))
        found = [t for t in hits if t is not None]
        return min(found) if found else None

    def _limit_hit(self, _ev: Any) -> None:
        """Past a software limit: decelerate at Ixx15 like an abort (PSRM Ix15), flag it."""
        self._wake = None
        now = self._table.sched.env.now
        rate = abs(self._table.vars.I(ixx(self.n, 15)))
        stop = jog.to_velocity(now, self.profile.position(now), self.profile.velocity(now), 0.0,
                               rate)
        self.profile = self.profile.then(stop)
        self.definite = False
        self.limit_stop = self.aborting = True
        t_end = self.profile.t_end
        assert t_end is not None
        self._at(self._table.sched.servo_at_or_after(t_end), self._ended)

    def _ended(self, _ev: Any) -> None:
        self._wake = None
        command, self.command = self.command, None
        self.definite = self.aborting = self.trigger_search = False
        now = self._table.sched.env.now
        self.profile = Profile.rest(now, self.profile.position(now))
        self._emit("jog", state="end", command=command, position=self._pos_now())
        if self.when_stopped:
            calls, self.when_stopped = self.when_stopped, []
            for call in calls:
                call()

    def _trigger(self, _ev: Any) -> None:
        """The home flag is found: capture, re-zero at capture + Ixx26, move to the zero."""
        self._wake = None
        sched = self._table.sched
        now = sched.env.now
        capture = self.position(now)
        zero = capture + self._table.vars.I(ixx(self.n, 26)) / 16.0
        self.profile = self.profile.shifted(-zero)
        self.homing = False
        self.home_complete = True
        self._emit("home", state="triggered", position=round(capture, 4) + 0.0)
        i23 = self._table.vars.I(ixx(self.n, 23))
        base = self._table.base(self.n, now)
        back = jog.to_position(
            now, self.profile.position(now), self.profile.velocity(now), -base,
            abs(i23) * 1000.0, self._rate(i23),
        )  # fmt: skip
        self.profile = self.profile.then(back)
        self.definite = True
        self._schedule_end()

    def offset_moved(self, delta: float) -> None:
        """Its axis definition's constant offset moved by ``delta`` counts: a definition
        commands no motion, so a motor at rest stays where it is (its jog part takes the
        change) ``[INF]``; a motor in a jog or home move is left to it."""
        if delta and self.command is None:
            now = self._table.sched.env.now
            self.profile = Profile.rest(now, self.profile.position(now) - delta)

    def home_zero(self) -> None:
        """``HMZ``: the present position is zero; home complete, no motion ``[BK]``."""
        self._stop_now()
        now = self._table.sched.env.now
        self.profile = self.profile.shifted(-self.position(now))
        self.homing = False
        self.home_complete = True

    def _stop_now(self) -> None:
        """Freeze the jog part where it is now (a kill); ends a move in progress."""
        now = self._table.sched.env.now
        self._cancel()
        self.profile = Profile.rest(now, self.profile.position(now))
        if self.command is not None:
            command, self.command = self.command, None
            self._emit("jog", state="end", command=command, position=self._pos_now())
        self.homing = self.definite = self.aborting = self.trigger_search = False

    def kill(self) -> None:
        """``K`` / CTRL-K: open loop, zero output, amplifier off; the motor stays put."""
        self._stop_now()
        self.output_pct = 0.0
        self._set_loop(KILLED)

    def open_loop(self, percent: float) -> None:
        """``O{p}``: open loop at ``p`` % of Ixx69 (saturating at ±100)."""
        self._stop_now()
        self.output_pct = max(-100.0, min(100.0, percent))
        self._set_loop(OPEN)

    def _close_loop(self) -> None:
        self.output_pct = 0.0
        self._set_loop(CLOSED)

    def enable(self) -> None:
        """``$``: close the loop (no phasing search: motors here are not PMAC-commutated)."""
        if self.loop != CLOSED:
            self._stop_now()
        self._close_loop()

    def absolute_read(self) -> None:
        """``$*`` with no absolute sensor (Ixx10 = 0): position 0, not homed, killed."""
        self.kill()
        now = self._table.sched.env.now
        self.profile = self.profile.shifted(-self.position(now))
        self.home_complete = False

    def abort(self) -> None:
        """CTRL-A: a jog or home in progress decelerates at Ixx15; open loops close."""
        now = self._table.sched.env.now
        if self.loop != CLOSED:
            self._stop_now()
            self._close_loop()
            return
        v0 = self.profile.velocity(now)
        if self.command is None or v0 == 0:
            if self.command is not None:
                self._stop_now()
            return
        rate = abs(self._table.vars.I(ixx(self.n, 15)))
        stop = jog.to_velocity(now, self.profile.position(now), v0, 0.0, rate)
        self.profile = self.profile.then(stop)
        self.homing = self.definite = False
        self.aborting = True
        self._schedule_end()

    # -- state ----------------------------------------------------------------------------

    def _pos_now(self) -> float:
        return round(self.position(self._table.sched.env.now), 4) + 0.0  # never -0.0

    def moving(self, t: float) -> bool:
        """The jog / home part of the motion is under way at ``t`` (desired velocity not 0)."""
        return self.command is not None and self.profile.velocity(t) != 0.0


class MotorTable:
    """Motors 1..32 of one controller.

    Args:
        sched: servo / RTI instants (and the environment).
        vars_: the variable store (Ixx19-Ixx23, Ixx26, Ixx92, Ixx15).
        emit: the event log's ``emit``.
        axis_of: the axis definition of a motor (CS, axis, counts per unit) or None.
        axis_position: commanded position of an axis of a CS at ``t`` (axis units).
        cs_running: whether a CS runs a motion program.
    """

    def __init__(
        self,
        sched: Scheduler,
        vars_: Variables,
        emit: Callable[..., Any],
        axis_of: AxisOf,
        axis_position: Callable[[int, str, float], float],
        cs_running: Callable[[int], bool],
    ) -> None:
        self.sched = sched
        self.vars = vars_
        self.emit = emit
        self.axis_of = axis_of
        #: The whole axis-definition sum of a motor, when the owner computes it.
        self.base_of: Callable[[int, float], float] | None = None
        self._axis_position = axis_position
        self._cs_running = cs_running
        t = sched.env.now
        self.motors = {n: Motor(n, self, t) for n in range(1, N_MOTORS + 1)}

    def __getitem__(self, n: int) -> Motor:
        return self.motors[n]

    def base(self, n: int, t: float) -> float:
        """The part of motor ``n``'s position its CS axis gives it (counts)."""
        if self.base_of is not None:  # several axes in one definition (axis_definitions)
            return self.base_of(n, t)
        m = self.axis_of(n)
        if m is None:
            return 0.0
        cs, axis, scale = m
        return self._axis_position(cs, axis, t) * scale

    def check_free(self, n: int) -> None:
        """ERR001 when motor ``n``'s coordinate system runs a program."""
        m = self.axis_of(n)
        if m is not None and self._cs_running(m[0]):
            raise Conflict(
                f"motor {n} is in coordinate system {m[0]}, which runs a program",
                pmac_error="ERR001",
            )

    def detach(self) -> None:
        """Forget every scheduled wake-up (the controller is being reset)."""
        for m in self.motors.values():
            m._cancel()

    def kill_all(self) -> None:
        for m in self.motors.values():
            m.kill()

    def abort_all(self) -> None:
        for m in self.motors.values():
            m.abort()


__all__ = ["CLOSED", "KILLED", "OPEN", "Motor", "MotorTable"]
