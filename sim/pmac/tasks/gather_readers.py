"""Batch reads of gather sources: what they show at the servo cycles between two events.

Data gathering (:mod:`.gather`) takes its samples in batches: just before the simulation
processes an event, it records every sample due before it. Nothing changes between two
events but time, so the sources of a ``GATHER`` are resolved once into a :class:`Plan`, and
at each batch :meth:`Plan.key` copies out of the card's state everything their values
depend on — numbers and immutable objects only, so the values can be computed later (when
the buffer is read) and two batches with equal keys show the same values at the same
instants (they are merged). Per source:

* plain memory (a word the host or a program wrote, an M-variable definition word, the user
  buffer): its raw value, which only a write changes;
* a motor's commanded / actual position, following error and velocity register
  (:func:`.registers.motor_register`): the motor's position as a function of time
  (:meth:`PmacController.motor_position_spec` over :meth:`Execution.axis_position_spec`)
  and the Ixx08 / Ixx09 it is scaled by, turned into the register's raw value by the same
  :func:`.registers.report_at` and ``*_raw`` functions the register table uses;
* the servo counter: a function of the cycle alone;
* anything else (status words, the timing registers, a motor under kinematics or in a move
  mode other than blended LINEAR, a CS stopping on ``A``): no batch form — the batch reads it
  through card memory at each sample's instant, exactly as a per-cycle sampler does.

``tests/sim/pmac/test_gather_batches.py`` pins every kind to the per-cycle reads through card
memory (:mod:`.registers`, the one home of what an address shows).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ..card import registers

if TYPE_CHECKING:
    from ..controller import PmacController

_WORD = 0xFFFFFF
_LONG = (1 << 48) - 1

#: What a batch's samples depend on (:meth:`Plan.key`).
Key = tuple[Any, ...]
#: One sample's raw values; None where the source has no batch form in this key.
Row = tuple[int | None, ...]


class Plan:
    """How the sources ``(space, address, bits)`` of one ``GATHER`` are read in batches
    (``space`` ``D`` / ``L`` for a 48-bit source)."""

    def __init__(self, ctl: PmacController, sources: list[tuple[str, int, int]],
                 period: int, position_at: Callable[[Any, float], float]) -> None:
        """``position_at(spec, t)``: a motor's position at ``t`` from its
        :meth:`PmacController.motor_position_spec` (the controller's ``motor_position_at``,
        handed down: the motion core sits above this tier)."""
        self._ctl = ctl
        self._position_at = position_at
        self._period = period
        memory = ctl.vars.mvars
        regs = memory.registers
        motors: list[int] = []
        ivars: list[int] = []
        consts: list[Callable[[], int]] = []
        #: per source: ("motor", motor index, what, ivar index, mask) | ("const", index) |
        #: ("servo", mask) | None
        self.kinds: list[tuple[Any, ...] | None] = []
        for space, address, bits in sources:
            key = "D" if bits == 48 else space
            mask = _LONG if bits == 48 else _WORD
            if (key, address) in regs:
                named = registers.motor_register(key, address)
                if named is not None:
                    motor, what = named
                    n = 100 * motor + (9 if what == "V" else 8)
                    if motor not in motors:
                        motors.append(motor)
                    if n not in ivars:
                        ivars.append(n)
                    self.kinds.append(("motor", motors.index(motor), what, ivars.index(n),
                                       mask))
                elif (key, address) == ("X", registers.SERVO_COUNTER):
                    self.kinds.append(("servo", mask))
                else:
                    self.kinds.append(None)
                continue
            if bits == 48:
                if ("X", address) in regs or ("Y", address) in regs:
                    self.kinds.append(None)
                    continue
                consts.append(functools.partial(memory.long, address))
            else:
                consts.append(functools.partial(memory.word, space, address))
            self.kinds.append(("const", len(consts) - 1))
        self._motors = tuple(motors)
        self._ivars = tuple(ivars)
        self._consts = tuple(consts)
        #: Some source is read through card memory at every sample.
        self.always_per_sample = None in self.kinds
        self._marks: tuple[Any, ...] | None = None
        self._definitions: dict[int, Any] | None = None
        self._key: Key = ((), (), ())
        self._cs_list: list[Any] = []
        self._motor_objects = [ctl.motor(m) for m in self._motors]
        #: The controller's axis definitions and I-variable reads (a reset, which makes
        #: new ones, ends the gathering this plan serves).
        self._axis_definitions = ctl.motors
        self._ivar = ctl.vars.I
        self._specs: tuple[Any, ...] = ()

    def key(self) -> Key:
        """Everything the batch form of the sources depends on, now. The motor specs are
        kept from the last call while what they are made of is unchanged (the axis
        definitions, each motor's jog profile, its CS's :meth:`Execution.axis_spec_key`)."""
        definitions = self._axis_definitions
        if definitions != self._definitions:
            self._definitions = dict(definitions)
            self._marks = None
            css = self._ctl.coord_systems
            haves = [definitions.get(m) for m in self._motors]
            self._cs_list = [css[c] for c in dict.fromkeys(h[0] for h in haves if h)]
        cs_list = self._cs_list
        marks = ([m.profile for m in self._motor_objects],
                 cs_list[0].axis_spec_key() if len(cs_list) == 1
                 else [c.axis_spec_key() for c in cs_list])
        ivars = self._ivars
        ivals = (self._ivar(ivars[0]),) if len(ivars) == 1 else tuple(
            [self._ivar(n) for n in ivars])
        consts = tuple([read() for read in self._consts]) if self._consts else ()
        if marks != self._marks:
            spec = self._ctl.motor_position_spec
            self._specs = tuple([spec(m) for m in self._motors])
            self._marks = marks
        elif ivals == self._key[1] and consts == self._key[2]:
            return self._key  # the same object: callers may compare keys with ``is``
        self._key = (self._specs, ivals, consts)
        return self._key

    def per_sample(self, key: Key) -> bool:
        """Does some source need reading through card memory at each sample of a batch
        with this key?"""
        if self.always_per_sample:
            return True
        return None in key[0]

    def rows(self, key: Key) -> Callable[[int, float], Row]:
        """``row(k, t)``: the raw values at servo cycle ``k`` (instant ``t``) of a batch with
        this key; None for a source without a batch form in it."""
        motor_position_at = self._position_at
        ctl = self._ctl
        period_s = ctl.scheduler.period_s
        clock = ctl.scheduler.clock
        specs, ivals, consts = key
        positions = [None if s is None else functools.partial(_position, motor_position_at, s)
                     for s in specs]
        parts: list[Callable[[float], int | None]] = []
        for kind in self.kinds:
            if kind is None:
                parts.append(_nothing)
            elif kind[0] == "const":
                parts.append(functools.partial(_constant, consts[kind[1]]))
            elif kind[0] == "servo":
                parts.append(functools.partial(_servo_count, clock, kind[1]))
            else:
                _, i, what, j, mask = kind
                position = positions[i]
                if position is None:
                    parts.append(_nothing)
                    continue
                raw = registers.velocity_raw if what == "V" else registers.position_raw
                parts.append(functools.partial(_motor_register, position, what, raw, ivals[j],
                                               mask, period_s))
        shared = _shared(parts, self.kinds)

        def row(_k: int, t: float) -> Row:
            return shared(t)

        return row


    def evaluate(self, items: list[tuple[Key, int, int, int]]) -> list[list[Row]]:
        """The rows of batches ``(key, first cycle, first sample kept, count)`` (cycles
        ``first + j·period`` for ``j`` from the sample kept on), computed together: batches
        whose sources are plain memory and motor position registers of motors on a blended
        LINEAR trajectory (or at rest), with their jog profiles at rest, are computed as
        arrays (:func:`_linear_positions`: the scalar functions' operations, element by
        element); the others sample by sample through :meth:`rows`."""
        out: list[list[Row] | None] = [None] * len(items)
        vector: list[int] = []
        for b, item in enumerate(items):
            if self._vectorizable(item):
                vector.append(b)
            else:
                key, k, j0, n = item
                row = self.rows(key)
                t_of = self._ctl.scheduler.clock.t
                p = self._period
                out[b] = [row(k + j * p, t_of(k + j * p)) for j in range(j0, n)]
        if vector:
            rows = self._vector([items[b] for b in vector])
            for b, r in zip(vector, rows, strict=True):
                out[b] = r
        return [r if r is not None else [] for r in out]

    def _vectorizable(self, item: tuple[Key, int, int, int]) -> bool:
        key, k, _, _ = item
        t0 = self._ctl.scheduler.clock.t(k)
        specs = key[0]
        for kind in self.kinds:
            if kind is None or kind[0] == "servo":
                return False
            if kind[0] == "motor":
                spec = specs[kind[1]]
                if kind[2] != "P" or spec is None:
                    return False
                terms, _, profile = spec
                if terms is not None and len(terms) != 1:
                    return False
                if profile.t_end is None or t0 < profile.t_end:
                    return False
        return True

    def _vector(self, items: list[tuple[Key, int, int, int]]) -> list[list[Row]]:
        """:meth:`evaluate` of batches :meth:`_vectorizable` says are."""
        import numpy as np

        period, period_s = self._period, self._ctl.scheduler.period_s
        counts = [n - j0 for _, _, j0, n in items]
        ks = np.concatenate([np.arange(k + j0 * period, k + n * period, period, dtype=np.int64)
                             if period else np.full(n - j0, k, dtype=np.int64)
                             for _, k, j0, n in items])
        t = ks * period_s
        # the distinct motor registers (a commanded and an actual position are one), all
        # computed in one pass: their rows of parameters one after the other
        motor_kinds = list(dict.fromkeys((k[1], k[3], k[4]) for k in self.kinds
                                         if k is not None and k[0] == "motor"))
        per_item = []
        for i, j, _ in motor_kinds:
            for key, _, _, _ in items:
                terms, offset, profile = key[0][i]
                c_prof = profile.position(profile.t_end)
                if terms is None:
                    per_item.append((0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                                     0.0, 0.0, c_prof, key[1][j]))
                    continue
                (a, scale), = terms
                if isinstance(a, float):
                    per_item.append((0.0, a, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                                     scale, offset, c_prof, key[1][j]))
                else:
                    p0, v, b0, ta_in, v_prev, b_end, ta_out = a
                    per_item.append((1.0, p0, v, b0, ta_in, v_prev,
                                     0.0 if b_end is None else 1.0,
                                     0.0 if b_end is None else b_end, ta_out, 0.0,
                                     scale, offset, c_prof, key[1][j]))
        values: dict[tuple[int, int, int], list[int]] = {}
        if motor_kinds:
            m = len(motor_kinds)
            cols = np.repeat(np.array(per_item, dtype=np.float64), counts * m, axis=0)
            moving, p0, v, b0, ta_in, v_prev, has_end, b_end, ta_out, _, scale, offset, \
                c_prof, ixx08 = cols.T
            tt = np.tile(t, m)
            a = np.where(moving > 0, _linear_positions(tt, p0, v, b0, ta_in, v_prev,
                                                       has_end > 0, b_end, ta_out), p0)
            # no axis definition: scale = offset = 0 and a = 0.0, so this is 0.0 + c_prof
            position = (a * scale + offset) + c_prof
            report = _round1(position)
            raw = np.rint((report * ixx08) * 32).astype(np.int64)
            size = len(t)
            for r, register in enumerate(motor_kinds):
                values[register] = (raw[r * size:(r + 1) * size] & register[2]).tolist()
        columns: list[list[int]] = []
        for source in self.kinds:
            assert source is not None
            if source[0] == "const":
                col: list[int] = []
                for (key, _, _, _), c in zip(items, counts, strict=True):
                    col += [key[2][source[1]]] * c
                columns.append(col)
            else:
                columns.append(values[(source[1], source[3], source[4])])
        rows = list(zip(*columns, strict=True))
        out, at = [], 0
        for c in counts:
            out.append(rows[at:at + c])
            at += c
        return out


def _nothing(t: float) -> None:
    return None


def _constant(value: int, t: float) -> int:
    return value


def _servo_count(clock: Any, mask: int, t: float) -> int:
    """The servo counter register (:mod:`.registers`) at ``t``."""
    return (int(clock.index(t)) & 0xFFFFFF) & mask


def _position(at: Callable[[Any, float], float], spec: Any, t: float) -> float:
    return at(spec, t)


def _motor_register(position: Callable[[float], float], what: str,
                    raw: Callable[[float, float], int], scale: float, mask: int,
                    period_s: float, t: float) -> int:
    """A motor register at ``t``: the report through :func:`.registers.report_at`, the raw
    word as the register table converts it."""
    return raw(registers.report_at(position, what, t, period_s), scale) & mask


def _ramp(x_s: Any, v0: Any, v1: Any, tau: Any, length: Any) -> Any:
    """:func:`motionsim.sim.pmac.buffers.motion.ramp_position` on arrays, same operations."""
    import numpy as np

    clamped = np.minimum(np.maximum(tau, 0.0), length)
    with np.errstate(divide="ignore", invalid="ignore"):
        ramp = x_s + v0 * clamped + (v1 - v0) * clamped * clamped / (2 * length)
    return np.where(length > 0, ramp, x_s + v1 * tau)


def _linear_positions(t: Any, p_start: Any, v: Any, b_start: Any, ta_in: Any, v_prev: Any,
                      has_end: Any, b_end: Any, ta_out: Any) -> Any:
    """:func:`motionsim.sim.pmac.buffers.motion.position_at` on arrays (``has_end`` False
    where ``b_end`` is None), the same operations in the same order in each branch."""
    import numpy as np

    h_in = ta_in / 2
    ramp_in = _ramp(p_start - v_prev * h_in, v_prev, v, t - (b_start - h_in), ta_in)
    h = ta_out / 2
    ramp_out = _ramp(p_start + v * (b_end - h - b_start), v, 0.0, t - (b_end - h), ta_out)
    steady = p_start + v * (t - b_start)
    out_ramp = has_end & (t > b_end - ta_out / 2)
    return np.where(t < b_start + h_in, ramp_in, np.where(out_ramp, ramp_out, steady))


def _round1(x: Any) -> Any:
    """``round(x, 1)`` element by element, as Python rounds (the exact decimal value, half to
    even): ``rint(10x) / 10`` is the same double wherever ``10x`` is not within a few ulps of
    a half; those (and huge or non-finite values) are rounded by Python."""
    import numpy as np

    y = x * 10.0
    out = np.rint(y) / 10.0
    frac = y - np.floor(y)
    doubtful = ~(np.abs(frac - 0.5) > np.abs(y) * 1e-15 + 1e-300) | (np.abs(x) >= 1e14)
    for i in np.flatnonzero(doubtful):
        out[i] = round(float(x[i]), 1)
    return out


def _shared(parts: list[Callable[[float], int | None]],
            kinds: list[tuple[Any, ...] | None]) -> Callable[[float], Row]:
    """One sample's values, each distinct motor register computed once (a commanded and an
    actual position register of one motor show the same value)."""
    first: dict[tuple[Any, ...], int] = {}
    index: list[int] = []
    for i, kind in enumerate(kinds):
        key = kind[:4] if kind is not None and kind[0] == "motor" else (i,)
        index.append(first.setdefault(key, i))
    if index == list(range(len(parts))):
        return lambda t: tuple(p(t) for p in parts)
    own = [i for i, j in enumerate(index) if i == j]

    def row(t: float) -> Row:
        values: list[int | None] = [None] * len(parts)
        for i in own:
            values[i] = parts[i](t)
        return tuple(values[j] for j in index)

    return row


__all__ = ["Key", "Plan", "Row"]
