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

    def __init__(self, ctl: PmacController, sources: list[tuple[str, int, int]]) -> None:
        self._ctl = ctl
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
                consts.append(lambda a=address: memory.long(a))
            else:
                consts.append(lambda s=space, a=address: memory.word(s, a))
            self.kinds.append(("const", len(consts) - 1))
        self._motors = tuple(motors)
        self._ivars = tuple(ivars)
        self._consts = tuple(consts)
        #: Some source is read through card memory at every sample.
        self.always_per_sample = None in self.kinds
        self._marks: tuple[Any, ...] | None = None
        self._specs: tuple[Any, ...] = ()

    def key(self) -> Key:
        """Everything the batch form of the sources depends on, now. The motor specs are
        kept from the last call while what they are made of is unchanged (each motor's jog
        profile and axis definition, its CS's :meth:`Execution.axis_spec_key`)."""
        ctl = self._ctl
        ivar = ctl.vars.I
        motors = ctl.motor_table
        haves = tuple(ctl.motors.get(m) for m in self._motors)
        marks = (haves, tuple(motors[m].profile for m in self._motors),
                 tuple(ctl.coord_systems[h[0]].axis_spec_key() for h in haves if h))
        if marks != self._marks:
            spec = ctl.motor_position_spec
            self._specs = tuple(spec(m) for m in self._motors)
            self._marks = marks
        return (self._specs, tuple(ivar(n) for n in self._ivars),
                tuple(read() for read in self._consts))

    def per_sample(self, key: Key) -> bool:
        """Does some source need reading through card memory at each sample of a batch
        with this key?"""
        if self.always_per_sample:
            return True
        return None in key[0]

    def rows(self, key: Key) -> Callable[[int, float], Row]:
        """``row(k, t)``: the raw values at servo cycle ``k`` (instant ``t``) of a batch with
        this key; None for a source without a batch form in it."""
        from ..controller import motor_position_at

        ctl = self._ctl
        period_s = ctl.scheduler.period_s
        clock = ctl.scheduler.clock
        report_at = registers.report_at
        specs, ivals, consts = key
        positions = [None if s is None else (lambda t, s=s: motor_position_at(s, t))
                     for s in specs]
        parts: list[Callable[[float], int | None]] = []
        for kind in self.kinds:
            if kind is None:
                parts.append(lambda t: None)
            elif kind[0] == "const":
                value = consts[kind[1]]
                parts.append(lambda t, v=value: v)
            elif kind[0] == "servo":
                parts.append(lambda t, m=kind[1]: (int(clock.index(t)) & 0xFFFFFF) & m)
            else:
                _, i, what, j, mask = kind
                position = positions[i]
                if position is None:
                    parts.append(lambda t: None)
                    continue
                raw = registers.velocity_raw if what == "V" else registers.position_raw
                scale = ivals[j]
                parts.append(lambda t, p=position, w=what, r=raw, s=scale, m=mask:
                             r(report_at(p, w, t, period_s), s) & m)
        shared = _shared(parts, self.kinds)

        def row(_k: int, t: float) -> Row:
            return shared(t)

        return row


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
