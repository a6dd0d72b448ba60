"""Turbo PMAC data gathering: registers copied into the gather buffer on servo interrupts.

What the Turbo SRM says (TSRM p170-171, global I-variables; p307 ``DEFINE GATHER``; p315
``DELETE GATHER``):

* ``I5001``..``I5048`` are the addresses of up to 48 sources, in the card's "modified address"
  form: the low five hex digits are the word address (bit 19 must be 0), the first hex digit
  says which part of the word is read. The SRM's list of the four values was cut off in the
  pages found; the form used here is the one Delta Tau's gathering tool writes and decodes
  (dls-pmac-control ``gatherchannel.py``): ``$0`` the Y word (24 bits), ``$4`` the X word
  (24 bits), ``$8`` X and Y as one 48-bit fixed-point word, ``$C`` the same 48 bits read as a
  floating-point value (an ``L`` word). The range $000000-$C7FFFF (p170) fits exactly these.
* ``I5050`` selects which of I5001..I5024 are gathered (bit 0 = I5001), ``I5051`` which of
  I5025..I5048 (p171).
* ``I5049`` is the period in servo cycles; 0 gathers one sample per ``GATHER`` (single shot)
  (p171). The SRM's default is 1 (the factory table takes it, :mod:`..card.factory`).
* ``I5000`` (p170): 0 / 2 stop when the buffer is full, 1 / 3 wrap around (2 / 3 put the
  buffer in DPRAM, which the simulator does not model: they behave as 0 / 1 ``[INF]``).
* ``DEFINE GATHER [n]`` reserves ``n`` long words (all free memory without ``n``) and
  prepares gathering at the start of the buffer; on an existing buffer it rewinds the
  storage address without erasing, after which ``LIST GATHER`` lists nothing (p307).
  ``DEFINE GATHER`` and ``DELETE GATHER`` while gathering is in progress (no ``ENDGATHER``
  yet, buffer not full) are refused (p307, p315; the code ERR003 is ``[INF]``).

Gathering itself (``GATHER`` / ``ENDGATHER``; the Turbo SRM's own ``GATHER`` page was not in
the corpora searched, so this part is ``[BK]``/``[INF]`` and says so in docs/pmac.md):

* ``GATHER`` latches the sources, the masks and I5049, and takes its first sample on the next
  servo cycle after the command (the servo interrupt after the background cycle that ran it),
  then one every I5049 cycles until ``ENDGATHER``, the buffer is full (I5000 = 0) or, with
  I5049 = 0, after the one sample. Each ``GATHER`` records from the start of the buffer
  ``[INF]``. A selected source the simulator does not model (:meth:`MVariables.holds`) is
  refused at ``GATHER`` naming it (ERR003), never gathered as zeros; so are no selected
  source, no gather buffer, and ``GATHER`` while one runs ``[INF]``.
* ``GATHER TRIGGER`` ``[INF]`` (its text was not found either): latched and rewound as
  ``GATHER``, but armed: the trigger input (:data:`TRIGGER_INPUT`, the Geo Brick's first
  general-purpose input) is polled at every servo cycle from the next one on, and the first
  cycle that finds it high after a poll (or the command) found it low takes the first sample;
  then as ``GATHER``. Armed counts as gathering in progress; ``ENDGATHER`` disarms.
* A sample is the selected sources in order I5001..I5048: a 24-bit source one 24-bit word, a
  48-bit source two (low half first); the buffer holds them two to a long word, and a sample
  with an odd number of 24-bit words is padded with one word (0 here) so each sample starts
  on a long word. A sample never straddles the end of the buffer ``[INF]``: the buffer holds
  ``n // longs_per_sample`` samples.
* ``LIST GATHER`` answers the stored long words in memory order, each as 12 hex digits: the
  second 24-bit word of the pair in the first six digits, the first in the last six
  (dls-pmac-control ``gather.py`` splits each token so: characters 6-11 first) — so a
  48-bit source on its own long word reads as its own 12 digits. Eight words to a line,
  separated by blanks ``[INF]``. A wrapped buffer lists all its slots in memory order.

Cost: nothing while no gather runs (no SimPy event, no hook). While one runs there is no
wake-up per sample either: :func:`motionsim.sim.simpy_adapter.pre_step` calls
:meth:`Gather._before_event` before each event the simulation processes, and it records the
samples whose wake-ups a per-cycle sampler would have processed first — the pending one if its
queue key (its instant, normal priority, the tie-break number its wake-up would have drawn)
orders before the event's, then every later one strictly before the event's instant — as one
batch. Nothing but time changes between two events, so a batch keeps only what its sources
depend on (:class:`.gather_readers.Plan`'s key), and is merged into the previous one when the
key is unchanged; values are computed when the buffer is read (``LIST GATHER``,
:meth:`recording`), only for the samples a wrapped buffer still holds. Sources without a
batch form (status words, the timing registers, motors under kinematics or in other move
modes) are read through card memory (:mod:`motionsim.sim.pmac.card.registers`, the one home
of what an address shows) at each sample's instant inside the batch, the clock set to it.
:attr:`Gather.per_cycle` keeps the per-cycle sampler (a wake-up per sample, every read
through card memory) as the reference ``tests/sim/pmac/test_gather_batches.py`` pins the
batches to. Each start and stop is a ``gather`` event (and an ``armed`` one for
``GATHER TRIGGER``).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final

import simpy

from ...errors import Conflict
from ...recording import Recording as SharedRecording
from ...simpy_adapter import (
    NORMAL,
    Wake,
    cancel,
    clear_pre_step,
    next_eid,
    pre_step,
    set_now,
    wake_at,
)
from ...timing import ServoClock
from ..card import pmac_float
from ..card.mvars import MVariables
from .gather_readers import Plan

#: First hex digit of I50nn -> (memory space read, bits). ``L`` reads the 48 bits as ``D``
#: does; the host interprets them as a float (module docstring).
PARTS: Final[dict[int, tuple[str, int]]] = {0x0: ("Y", 24), 0x4: ("X", 24), 0x8: ("D", 48),
                                            0xC: ("L", 48)}
N_SOURCES: Final = 48
WORDS_PER_LINE: Final = 8
_WORD: Final = 0xFFFFFF
_LONG: Final = (1 << 48) - 1


#: ``GATHER TRIGGER``'s trigger input ``(space, address, bit)``: the Geo Brick's first
#: general-purpose input (``IN1``, Y:$078800 bit 0; plain memory here, set with ``W`` or an
#: M-variable) ``[INF]`` — the Turbo SRM's ``GATHER`` page was not in the corpora searched.
TRIGGER_INPUT: Final = ("Y", 0x078800, 0)
TRIGGER_INPUT_NAME: Final = "Y:$078800,0"


def _count_before(period_s: float, k: int, period: int, t_e: float) -> int:
    """How many of cycles ``k``, ``k + period``, .. come before ``t_e``: the first always
    (the caller checked it), the others at an instant (``ServoClock.t``: the cycle times
    ``period_s``) strictly before ``t_e``."""
    j = int((t_e / period_s - k) / period)
    if j < 0:
        j = 0
    while (k + (j + 1) * period) * period_s < t_e:
        j += 1
    while j > 0 and (k + j * period) * period_s >= t_e:
        j -= 1
    return j + 1


def _err(message: str) -> Conflict:
    return Conflict(message, pmac_error="ERR003")


@dataclass(frozen=True, slots=True)
class Source:
    """One gathered source: ``I50nn`` (``number`` = nn), what it reads, its ``bits``."""

    number: int
    spec: int
    space: str
    address: int
    bits: int

    @property
    def name(self) -> str:
        """``I5001=$800088``-style label, and the column name of a recording."""
        return f"I{5000 + self.number}"

    @property
    def address_text(self) -> str:
        return f"{self.space}:${self.address:06X}"


def decode_source(number: int, value: float) -> Source:
    """The source ``I{5000+number}`` = ``value`` names.

    Raises:
        Conflict: ERR003 — a first hex digit other than 0 / 4 / 8 / C, or bit 19 set
            (TSRM p170).
    """
    spec = int(value)
    name = f"I{5000 + number}"
    if not 0 <= spec <= 0xC7FFFF or spec != value:
        raise _err(f"{name}={value:g}: a gather address is $000000..$C7FFFF (TSRM p170)")
    part = spec >> 20
    address = spec & 0xFFFFF
    name = f"{name}=${spec:06X}"
    if part not in PARTS:
        raise _err(f"{name}: the first hex digit must be 0 (Y), 4 (X), 8 (D) or C (L)")
    if address & 0x80000:
        raise _err(f"{name}: bit 19 of a gather address must be 0 (TSRM p170)")
    space, bits = PARTS[part]
    return Source(number, spec, space, address, bits)


@dataclass(frozen=True, slots=True)
class Recording:
    """The samples of the last ``GATHER``, oldest first: ``cycles[i]`` is the servo cycle of
    sample ``i`` and ``values[i]`` its raw words, one per source (48-bit ones whole)."""

    sources: tuple[Source, ...]
    period_cycles: int
    servo_period_s: float
    cycles: tuple[int, ...]
    values: tuple[tuple[int, ...], ...]
    running: bool
    wrapped: bool
    capacity: int

    def shared(self) -> SharedRecording:
        """As :class:`motionsim.sim.recording.Recording`: each word a signed integer of its
        width, a ``$C`` source's 48 bits as the float they hold."""
        columns = []
        for i, s in enumerate(self.sources):
            raw = [v[i] for v in self.values]
            if s.space == "L":
                columns.append(tuple(pmac_float.decode(r) for r in raw))
            else:
                half = 1 << (s.bits - 1)
                columns.append(tuple(float(r - 2 * half if r >= half else r) for r in raw))
        return SharedRecording(
            "gather", tuple(s.name for s in self.sources),
            tuple({"name": s.name, "spec": f"${s.spec:06X}", "address": s.address_text,
                   "bits": s.bits} for s in self.sources),
            self.cycles, tuple(columns), self.period_cycles, self.servo_period_s,
            self.running, self.wrapped, self.capacity)


class Gather:
    """The gather buffer and the gathering task of one card.

    Args:
        env: the controller's environment.
        clock: its servo clock.
        ivar: reads an I-variable.
        memory: card memory (registers, M-variable targets, plain words).
        emit: the event log's ``emit``.
        at_one_instant: runs a sample's reads as one instant's (the controller computes
            each CS's positions once for all of them); plain call if None.
        plan: makes the batch plan of a ``GATHER``'s sources (:mod:`.gather_readers`);
            None: every source is read through card memory at each sample.
    """

    #: True: one wake-up per sample, reads through card memory (the reference the batched
    #: samples are pinned to, ``tests/sim/pmac/test_gather_batches.py``).
    per_cycle = False

    def __init__(self, env: simpy.Environment, clock: ServoClock, ivar: Callable[[int], float],
                 memory: MVariables, emit: Callable[..., Any],
                 at_one_instant: Callable[[Callable[[], Any]], Any] | None = None,
                 plan: Callable[[tuple[Source, ...], int], Plan] | None = None) -> None:
        self._env = env
        self._at_one_instant = at_one_instant or (lambda read: read())
        self._clock = clock
        self._period_s = clock.period_s
        self._ivar = ivar
        self._memory = memory
        self._emit = emit
        self._make_plan = plan
        #: Long words reserved by DEFINE GATHER; None: no buffer.
        self.words: int | None = None
        self.running = False
        self._sources: tuple[Source, ...] = ()
        self._period = 1
        self._wrap = False
        self._capacity = 0
        self._longs = 1
        #: (cycle, values) by memory slot
        self._slots: list[tuple[int, tuple[Any, ...]]] = []
        self._stored = 0  # samples stored since GATHER (beyond capacity when wrapped)
        self._next_k = 0
        self._wake: Wake | None = None
        #: Samples recorded but not yet computed, oldest first: (first sample number, first
        #: cycle, count, the plan's key, or the rows read through card memory).
        self._batches: deque[list[Any]] = deque()
        self._plan: Plan | None = None
        self._eid = 0  # queue tie-break of the next (virtual) sample or trigger poll
        self._armed = False  # GATHER TRIGGER waiting for its trigger
        self._level = 0  # the trigger input at the last poll

    # -- buffer -----------------------------------------------------------------------------

    def define(self, words: int) -> None:
        """``DEFINE GATHER`` of ``words`` long words (the caller checks memory)."""
        self._refuse_while_running("DEFINE GATHER")
        self.words = words
        self._clear()

    def delete(self) -> None:
        """``DELETE GATHER``."""
        self._refuse_while_running("DELETE GATHER")
        self.words = None
        self._clear()

    def _clear(self) -> None:
        self._slots = []
        self._batches.clear()
        self._stored = 0
        self._sources = ()

    def detach(self) -> None:
        """Power-down: a pending sample does nothing."""
        cancel(self._wake)
        clear_pre_step(self._env)
        self.running = False

    def _refuse_while_running(self, what: str) -> None:
        if self.running:
            raise _err(f"{what}: data gathering is in progress (ENDGATHER first)")

    # -- gathering --------------------------------------------------------------------------

    def selected(self) -> tuple[Source, ...]:
        """The sources I5050 / I5051 select, in order I5001..I5048 (TSRM p171)."""
        masks = (int(self._ivar(5050)) & _WORD, int(self._ivar(5051)) & _WORD)
        out = []
        for n in range(1, N_SOURCES + 1):
            if masks[(n - 1) // 24] >> ((n - 1) % 24) & 1:
                out.append(decode_source(n, self._ivar(5000 + n)))
        return tuple(out)

    def start(self, trigger: bool = False) -> None:
        """``GATHER``: latch the set-up and take the first sample at the next servo cycle;
        with ``trigger`` (``GATHER TRIGGER``) at the first servo cycle from the next on that
        finds the trigger input (:data:`TRIGGER_INPUT`) high after one that found it low
        (or after the command found it low) ``[INF]``.

        Raises:
            Conflict: ERR003 — no buffer, already gathering, nothing selected, a source
                address that is malformed or not modelled (named).
        """
        if self.words is None:
            raise _err("GATHER: no gather buffer is defined (DEFINE GATHER first)")
        self._refuse_while_running("GATHER")
        sources = self.selected()
        if not sources:
            raise _err("GATHER: I5050 / I5051 select no source")
        for s in sources:
            space = "D" if s.bits == 48 else s.space
            if not self._memory.holds(space, s.address):
                raise _err(f"GATHER: {s.name}=${s.spec:06X} ({s.address_text}) is an address "
                           "the simulator does not model")
        words24 = sum(s.bits // 24 for s in sources)
        self._sources = sources
        self._longs = (words24 + 1) // 2
        self._capacity = self.words // self._longs
        self._period = int(self._ivar(5049))
        self._wrap = int(self._ivar(5000)) in (1, 3)
        self._slots = []
        self._batches.clear()
        self._stored = 0
        self.running = True
        self._next_k = self._clock.after(self._env.now)
        self._armed = trigger and self._capacity > 0
        if self._armed:
            self._level = self._trigger_input()
            self._emit("gather", state="armed", input=TRIGGER_INPUT_NAME)
        else:
            self._started()
        if self._capacity == 0:
            self._stop("full")
            return
        if self.per_cycle:
            self._wake = wake_at(self._env, self._clock.t(self._next_k),
                                 self._poll if self._armed else self._sample, self._wake)
            return
        make_plan = self._make_plan
        self._plan = make_plan(sources, self._period) if make_plan is not None else None
        self._eid = next_eid(self._env)  # where the first sample's wake-up would queue
        pre_step(self._env, self._before_event)

    def _started(self) -> None:
        self._armed = False
        self._emit("gather", state="started", sources=[s.name for s in self._sources],
                   period=self._period, capacity=self._capacity)

    def _trigger_input(self) -> int:
        space, address, bit = TRIGGER_INPUT
        return self._memory.word(space, address) >> bit & 1

    def end(self) -> None:
        """``ENDGATHER``: stop; what was gathered stays for ``LIST GATHER``."""
        if self.running:
            cancel(self._wake)
            self._stop("endgather")

    def _stop(self, reason: str) -> None:
        self.running = False
        self._armed = False
        clear_pre_step(self._env)
        self._emit("gather", state="stopped", reason=reason, samples=min(self._stored,
                                                                         self._capacity))

    def _read(self) -> tuple[int, ...]:
        """The selected sources now, through card memory (the per-cycle reads)."""
        memory = self._memory
        sources = self._sources
        values: tuple[int, ...] = self._at_one_instant(lambda: tuple(
            memory.long(s.address) if s.bits == 48 else memory.word(s.space, s.address)
            for s in sources
        ))
        return values

    def _poll(self, _event: Any) -> None:
        """The per-cycle reference of an armed ``GATHER TRIGGER``: the trigger input read at
        every servo cycle; the cycle that finds it risen takes the first sample."""
        if not self.running:
            return
        level = self._trigger_input()
        if level and not self._level:
            self._started()
            self._sample(_event)
            return
        self._level = level
        self._next_k += 1
        self._wake = wake_at(self._env, self._clock.t(self._next_k), self._poll, self._wake)

    def _sample(self, _event: Any) -> None:
        """The per-cycle reference: one wake-up per sample (:attr:`per_cycle`)."""
        if not self.running:
            return
        values = self._read()
        k = self._next_k
        slot = self._stored % self._capacity
        if slot < len(self._slots):
            self._slots[slot] = (k, values)
        else:
            self._slots.append((k, values))
        self._stored += 1
        if self._period == 0:
            self._stop("single")
            return
        if self._stored >= self._capacity and not self._wrap:
            self._stop("full")
            return
        self._next_k = k + self._period
        self._wake = wake_at(self._env, self._clock.t(self._next_k), self._sample, self._wake)

    def _before_event(self, t_e: float, priority: int, eid: int) -> None:
        """Record the samples whose wake-ups a per-cycle sampler would process before the
        event at queue key ``(t_e, priority, eid)``: the pending one if it orders first,
        then every later one strictly before ``t_e`` (their wake-ups would be queued after
        the event was). Nothing but time changes in between, so one capture per source
        serves the whole batch (:mod:`.gather_readers`)."""
        k = self._next_k
        t = k * self._period_s  # clock.t(k)
        if t > t_e or (t == t_e and (priority < NORMAL or (priority == NORMAL
                                                           and eid < self._eid))):
            return
        if self._armed:
            # The polls of the trigger input before the event all read what it holds now.
            level = self._trigger_input()
            if not (level and not self._level):
                self._level = level
                self._next_k = k + _count_before(self._period_s, k, 1, t_e)
                self._eid = next_eid(self._env)
                return
            set_now(self._env, t)
            self._started()  # the first poll finds it risen: that cycle's sample is next
        period = self._period
        n = 1
        if period > 0:
            n = _count_before(self._period_s, k, period, t_e)
        if not self._wrap:
            n = min(n, self._capacity - self._stored)
        self._record(k, n)
        if period == 0 or (self._stored >= self._capacity and not self._wrap):
            set_now(self._env, (k + (n - 1) * period) * self._period_s)  # the last sample's
            self._stop("single" if period == 0 else "full")
            return
        self._next_k = k + n * period
        self._eid = next_eid(self._env)

    def _record(self, k: int, n: int) -> None:
        """Samples ``k``, ``k + period`` .. (``n`` of them) as one batch: the plan's key (merged
        into the last batch when that ends just before with the same key), or, when some
        source has no batch form now, every sample read through card memory at its instant
        (those of the batch a wrapped buffer keeps)."""
        env, clock, period = self._env, self._clock, self._period
        first = self._stored
        self._stored = first + n
        plan = self._plan
        batches = self._batches
        key = plan.key() if plan is not None else None
        if batches:
            last = batches[-1]
            if last[3] is key and key is not None and last[0] + last[2] == first \
                    and last[1] + last[2] * period == k:
                last[2] += n  # same key object: nothing changed since that batch
                if self._wrap:
                    self._prune()
                return
        if plan is not None and key is not None and not plan.per_sample(key):
            batches.append([first, k, n, key, []])
        else:
            skip = max(0, n - self._capacity) if self._wrap else 0
            rows: list[tuple[int, ...]] = [()] * skip
            for j in range(skip, n):
                set_now(env, clock.t(k + j * period))
                rows.append(self._read())
            batches.append([first, k, n, None, rows])
        if self._wrap:
            self._prune()

    def _prune(self) -> None:
        """Forget batches a wrapped buffer has overwritten entirely."""
        if self._wrap:
            oldest = self._stored - self._capacity
            batches = self._batches
            while batches and batches[0][0] + batches[0][2] <= oldest:
                batches.popleft()

    def _materialize(self) -> None:
        """Compute the recorded batches into their slots (those a wrapped buffer still
        holds)."""
        batches = self._batches
        if not batches:
            return
        capacity, period, plan = self._capacity, self._period, self._plan
        slots = self._slots
        oldest = self._stored - capacity if self._wrap else 0
        if self._stored > capacity and len(slots) < capacity:
            slots.extend([(0, ())] * (capacity - len(slots)))
        kept = [(first, k, max(0, oldest - first), n, key, rows)
                for first, k, n, key, rows in batches]
        batches.clear()
        keyed = [(key, k, j0, n) for _, k, j0, n, key, _ in kept if key is not None]
        computed = iter(plan.evaluate(keyed) if plan is not None and keyed else [])
        for first, k, j0, n, key, rows in kept:
            values = next(computed) if key is not None else rows[j0:]
            cycles = range(k + j0 * period, k + n * period, period) if period else [k] * (n - j0)
            pairs = list(zip(cycles, values, strict=True))
            at = (first + j0) % capacity  # the slots they go to: at.., wrapping at capacity
            while pairs:
                room = capacity - at
                part, pairs = pairs[:room], pairs[room:]
                end = at + len(part)
                if at == len(slots):
                    slots.extend(part)
                else:
                    slots[at:end] = part
                at = 0

    # -- reading ----------------------------------------------------------------------------

    def recording(self) -> Recording:
        """The samples in time order (wrapped: the newest ``capacity`` of them)."""
        self._materialize()
        slots = self._slots
        if self._stored > self._capacity:
            head = self._stored % self._capacity
            slots = slots[head:] + slots[:head]
        return Recording(self._sources, self._period, self._clock.period_s,
                         tuple(k for k, _ in slots), tuple(v for _, v in slots),
                         self.running, self._stored > self._capacity, self._capacity)

    def words24(self, values: tuple[int, ...]) -> list[int]:
        """One sample as the buffer stores it: 24-bit words, 48-bit ones low half first,
        padded to a whole long word."""
        out: list[int] = []
        for s, v in zip(self._sources, values, strict=True):
            if s.bits == 48:
                v &= _LONG
                out += (v & _WORD, v >> 24)
            else:
                out.append(v & _WORD)
        if len(out) % 2:
            out.append(0)
        return out

    def listing(self) -> list[str]:
        """``LIST GATHER``: the stored long words, 12 hex digits each (module docstring).

        Raises:
            Conflict: ERR003 — no gather buffer.
        """
        if self.words is None:
            raise _err("no gather buffer is defined (DEFINE GATHER)")
        self._materialize()
        tokens: list[str] = []
        for _, values in self._slots:  # memory order (wrapped: slot 0 on, not time order)
            w = self.words24(values)
            tokens += (f"{w[i + 1]:06X}{w[i]:06X}" for i in range(0, len(w), 2))
        return [" ".join(tokens[i:i + WORDS_PER_LINE])
                for i in range(0, len(tokens), WORDS_PER_LINE)]


__all__ = ["PARTS", "Gather", "Recording", "Source", "decode_source"]
