"""``PmacController``: a simulated Delta Tau Turbo PMAC (kind ``"pmac"``).

Public surface (what ``app/`` and ``api/`` call): :meth:`terminal` (the host command line,
answered in the background cycle), :meth:`define_rotary`, :meth:`delete_rotary`,
:meth:`load_lines` (atomic batches with ``first_seq`` idempotency), :meth:`run`,
:meth:`quit`, :meth:`abort`, :meth:`coord`, :meth:`rotary`, :meth:`get_variable`,
:meth:`set_variable`, :meth:`reset`, :meth:`status`, :meth:`positions`, :meth:`wait_breq`.
Resource methods act at the current simulated instant and never move the clock.

Config keys are I-variables in lower case (``{"i16": 5, "i17": 10, "i8": 2, "i10": 3713707}``)
plus ``"servo_hz"`` (overrides I10) and ``"background_cycles"`` (servo cycles per background
cycle, default 1). Unknown keys are refused (``InvalidValue`` naming the field).

Buffer memory ``[INF]``: 65 536 words are shared by the rotary buffers and the gather buffer;
``SIZE`` reports what is free (negative while a buffer is open, TSRM SIZE).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Mapping
from typing import Any, NamedTuple, TypeVar

import simpy

from ..bounds import FINITE, PMAC_CONFIG, PMAC_CPU_COST
from ..controller import Controller, Port, Reply
from ..errors import BufferFull, Conflict, Halted, InvalidValue, NotFound, ParseError
from ..faults import CardFaults
from ..recording import Recording as SharedRecording
from ..timing import pmac_servo_period_s
from .buffers import lookahead_buffer
from .buffers.program import ProgramLine, compile_line
from .buffers.programs import MotionPrograms
from .buffers.rotary import RotaryBuffer
from .card import card_commands, comp_tables, pmac_float, registers, servo_ic
from .card.macro_station import MacroStations
from .card.timers import CountdownTimers
from .card.variables import N_CS, N_MOTORS, Variables, parse_name
from .host import commands
from .host.messages import HostMessages
from .host.messages import frame as frame_message
from .host.terminal import Terminal
from .kinematics.engine import Kinematics
from .language import axis_definitions
from .language import motor_statements as motor_st
from .lookahead import CoordSystem
from .lookahead.execution import AxisSpec, axis_position_at
from .lookahead.start_checks import check_start
from .motor.jog import Profile as JogProfile
from .motor.motor_status import motor_status_words
from .motor.motors import Motor, MotorTable
from .tasks.command_queue import CommandQueue
from .tasks.cpu import CONFIG_KEYS as CPU_CONFIG_KEYS
from .tasks.cpu import Processor
from .tasks.gather import Gather
from .tasks.gather_readers import Plan
from .tasks.plc import PlcTable
from .tasks.scheduler import Scheduler

MEMORY_WORDS = 65_536
_T = TypeVar("_T")

#: :meth:`PmacController.motor_position_spec`: the axis terms (None: no axis definition), the
#: definition's constant offset, the motor's jog profile.
MotorSpec = tuple[tuple[tuple[AxisSpec, float], ...] | None, float, JogProfile]


def motor_position_at(spec: MotorSpec, t: float) -> float:
    """Motor position (counts) at ``t`` from a :meth:`PmacController.motor_position_spec`:
    the same sums, in the same order, as :meth:`PmacController._motor_base` plus
    :meth:`Motor.position`'s jog profile."""
    terms, offset, profile = spec
    if terms is None:
        return 0.0 + profile.position(t)
    if len(terms) == 1:
        a, s = terms[0]
        return (axis_position_at(a, t) * s + offset) + profile.position(t)
    return (sum(axis_position_at(a, t) * s for a, s in terms) + offset) + profile.position(t)

#: Parsed lines by text: streams repeat line texts, and a parse is the costliest per-line step.
_LINE_CACHE: dict[str, ProgramLine] = {}
_LINE_CACHE_SIZE = 8192

#: Longest program line accepted: 255 characters. [INF] from the Ethernet protocol's one-byte
#: command length (spec pmac.md §5: dls-pmaclib cannot send a command over 255 characters) and
#: the command-line buffer of 256 characters [BK]; the Turbo SRM pages searched give no figure.
MAX_LINE_CHARS = 255
#: A terminal reply this little past the 1 s wait is still on time: the float rounding the
#: clock tolerates when it steps a POST to its deadline (app/clock.py), so a reply the POST
#: returned is not also announced as a ``terminal_reply`` event.
_WAIT_EPS_S = 1e-9
_CONFIG_KEY = re.compile(r"^i(\d{1,4})$")
#: Config keys that are true / false: ``strict_cs_motors`` — ``R`` / ``S`` in a coordinate
#: system with no motors answers ERR014 as the card does (sim.pmac.lookahead.start_checks).
FLAG_CONFIG = ("strict_cs_motors",)


class LoadResult(NamedTuple):
    """What :meth:`PmacController.load_lines` reports (``stored`` = newly stored lines)."""

    accepted: int
    stored: int
    lines_ahead: int
    free_words: int
    breq: bool


_new_result = tuple.__new__  # builds a LoadResult without the Python-level __new__ frame


class PmacController(Controller):
    """A Turbo PMAC with 16 coordinate systems, rotary buffers and a host command line."""

    kind = "pmac"

    #: Simulated seconds a virtual-clock terminal POST waits before answering "pending"; a
    #: reply that comes later is also published as a ``terminal_reply`` event.
    terminal_wait_s = 1.0

    def __init__(
        self,
        id: str = "pmac",
        config: Mapping[str, Any] | None = None,
        *,
        log_capacity: int = 100_000,
    ) -> None:
        super().__init__(id, config, log_capacity=log_capacity)
        self._check_config(self.config)
        self.vars = Variables(self._m_written)
        self.flash = card_commands.Flash()  # what SAVE stored; survives resets
        #: MACRO stations' variables (no ring simulated); separate hardware, kept on reset.
        self.macro_stations = MacroStations()
        #: Injected faults inside the card (sim.faults); they outlive a reset.
        self.card_faults = CardFaults(self.log.emit)
        self._power_on()

    # -- construction ---------------------------------------------------------------------

    @staticmethod
    def _check_config(config: Mapping[str, Any]) -> None:
        """Every key known and every value within its bound (sim/bounds.py)."""
        for key, value in config.items():
            if key in CPU_CONFIG_KEYS:
                PMAC_CPU_COST.check(value, key)  # processor-time costs in µs (sim.pmac.cpu)
                continue
            m = _CONFIG_KEY.match(key)
            if key in FLAG_CONFIG:
                if not isinstance(value, bool):
                    raise InvalidValue(f"{key} is true or false, not {value!r}", field=key)
            elif key in PMAC_CONFIG:
                PMAC_CONFIG[key].check(value, key)
            elif m:
                if int(m.group(1)) > 8191:
                    raise InvalidValue(f"no I-variable {key}", field=key)
                FINITE.check(value, key)
            else:
                known = ", ".join(sorted([*PMAC_CONFIG, *FLAG_CONFIG, *CPU_CONFIG_KEYS]))
                raise InvalidValue(f"unknown PMAC config key {key!r}; known: {known} and "
                                   "i0 .. i8191 (I-variables)", field=key)

    def _power_on(self) -> None:
        self.vars.reset()
        for key, value in self.config.items():
            m = _CONFIG_KEY.match(key)
            if m:
                self.vars.write("I", int(m.group(1)), float(value))
        hz = self.config.get("servo_hz")
        period = 1.0 / hz if hz else pmac_servo_period_s(int(self.vars.I(10)))
        for n, value in servo_ic.ivars(period).items():  # the clock chain gives this period
            if f"i{n}" not in self.config:
                self.vars.i[n] = value
        if not hasattr(self, "scheduler"):
            self.scheduler = Scheduler(self.env, period, lambda: int(self.vars.I(8)) + 1)
            self.background = Processor(self, int(self.config.get("background_cycles", 1)))
            self._terminal = Terminal(self)
            clock = self.scheduler.clock
            self.vars.timers = CountdownTimers(
                lambda: clock.index(self.env.now),
                lambda n, v: self.log.emit("timer", var=f"I{n}", value=v),
            )
        #: Axis positions by CS while one instant's registers are read (_at_one_instant).
        self._positions_memo: dict[Any, Any] | None = None
        self.halted = False  # the watchdog tripped (sim.pmac.watchdog); until reset
        #: The bounded queue of CMD"..." commands (sim.pmac.tasks.command_queue).
        self.commands = CommandQueue(self._place_program_command)
        self.plcs = PlcTable(self)
        #: SEND lines on their way to the host ports (sim.pmac.host.messages).
        self.messages = HostMessages(self.log.emit, lambda: self.env.now)
        self._message_cursors: dict[str, int] = {}
        self.background.power_on()
        self.coord_systems = {n: CoordSystem(self, n) for n in range(1, N_CS + 1)}
        self.vars.mvars.registers = registers.for_controller(self)
        self.kinematics = Kinematics(self)  # OPEN FORWARD / INVERSE, #n->I (sim.pmac.kinematics)
        old_gather = getattr(self, "gather", None)
        if old_gather is not None:
            old_gather.detach()
        #: The gather buffer and data gathering (sim.pmac.tasks.gather).
        self.gather = Gather(self.env, self.scheduler.clock, self.vars.I, self.vars.mvars,
                             self.log.emit, self._at_one_instant,
                             lambda sources, period: Plan(
                                 self, [(s.space, s.address, s.bits) for s in sources], period,
                                 motor_position_at))
        #: ``DEFINE COMP`` tables by owning motor (:mod:`.card.comp_tables`).
        self.comp_tables: dict[int, comp_tables.CompTable] = {}
        self.programs = MotionPrograms()
        self.buffer_holder: Port | None = None
        self.motors: dict[int, tuple[int, str]] = {}  # axis definitions: n -> (cs, "1000X")
        if hasattr(self, "motor_table"):
            self.motor_table.detach()
        self.motor_table = MotorTable(
            self.scheduler, self.vars, self.log.emit, self._motor_axis, self._axis_position,
            self._cs_running,
        )  # fmt: skip
        self.motor_table.base_of = self._motor_base

    def _alive(self) -> None:
        """Refuse anything that acts on the card once the watchdog has tripped (TSRM p57: it
        stops and will not communicate until the power is cycled); reads stay available to
        the REST observer.

        Raises:
            Halted: the watchdog has tripped.
        """
        if self.halted:
            raise Halted("the watchdog has tripped: the controller answers nothing until reset")

    def _m_written(self, n: int, value: float, sync: bool) -> None:
        self.log.emit("mvar", name=f"M{n}", value=value, sync=sync)

    def _thresholds(self) -> tuple[float, float]:
        """``(I16, I17)`` now (each rotary buffer caches them by ``vars.version``)."""
        v = self.vars
        return v.I(16), v.I(17)

    # -- ports and the terminal -----------------------------------------------------------

    def open_port(self, name: str) -> Port:
        port = Port(name)
        port.state.update(cs=1, motor=1)
        return port

    def close_port(self, port: Port) -> None:
        if hasattr(self, "plcs"):
            self.plcs.abandon(port)
        if getattr(self, "buffer_holder", None) is port:
            self.buffer_holder = None
        super().close_port(port)

    def terminal(self, command: str, port: Port | None = None) -> Reply:
        """Send one command line; it is answered in the next background cycle.

        Raises:
            Halted: the watchdog has tripped; the controller answers nothing until reset.
        """
        self._alive()
        port = port or self.rest_port
        reply = Reply(command)
        t0 = self.env.now

        def job() -> None:
            self.messages.active = port  # the active response port (PSRM p347)
            text, error = self._terminal.execute(command, port)
            reply.detail = self._terminal.detail if error is not None else None
            reply.resolve(text, error, self.env.now)
            if reply.answered_pending or self.env.now - t0 > self.terminal_wait_s + _WAIT_EPS_S:
                self.log.emit("terminal_reply", command=command, reply=text, error=error)

        self.background.submit(job)
        return reply

    def unread_output(self, reader: str) -> list[str]:
        """The ``SEND`` lines of the card's programs since ``reader`` last asked, whatever
        port they were sent to (the REST terminal: ``"rest"``; the first call returns the
        lines kept since power-up, at most ``MAX_LINES``)."""
        port = self.rest_port if reader == "rest" else None
        lines, self._message_cursors[reader] = self.messages.since(
            self._message_cursors.get(reader, 0), port)
        return lines

    def host_messages(self, port: Port) -> list[tuple[bytes, str]]:
        """The ``SEND`` lines sent to host port ``port`` not yet delivered to it, framed per
        I3 and I64 (``(bytes, text)``, oldest first): the Ethernet port queues them."""
        msgs = self.messages.take_for(port)
        if not msgs:
            return []
        i3, i64 = int(self.vars.I(3)), int(self.vars.I(64))
        return [(frame_message(m.text, i3, i64), m.text) for m in msgs]

    def send_message(self, source: str, port: str, text: str) -> None:
        """``SEND{port}"text"`` from a PLC or motion program (sim.pmac.host.messages)."""
        self.messages.send(source, port, text)

    def submit_program_command(self, text: str, cs: int = 1, motor: int = 1) -> None:
        """``CMD"text"`` from an unnamed program source (PLC 0's slot is not used): queued as
        :meth:`issue_program_commands` does."""
        self.issue_program_commands((False, -1), [(text, cs, motor)])

    def issue_program_commands(self, source: tuple[bool, int],
                               commands: list[tuple[str, int, int]]) -> None:
        """The ``CMD"text"`` commands one scan of PLC ``source`` (``(compiled, n)``) issued,
        as ``(text, cs, motor)``: into the card's bounded command queue; what does not fit
        halts that PLC until there is room (sim.pmac.tasks.command_queue, TSRM p423)."""
        self.commands.issue(source, commands)

    def _place_program_command(self, command: tuple[str, int, int],
                               taken: Callable[[], bool]) -> None:
        """One program command into the background queue for the command interpreter.

        Runs on a port of its own whose addressing starts at the PLC's ``ADDRESS`` (motor 1 /
        CS 1 unless set) for every command (non-modal, TSRM p422); replies and errors go
        nowhere (no host asked) ``[INF]``. ``taken()`` frees its place in the command queue and
        says whether the command is still to run (its PLC's DISABLE ended it otherwise).
        """
        text, cs, motor = command
        port = self.plcs._cmd_port

        def job() -> None:
            if not taken():
                return
            port.state.update(cs=cs, motor=motor)
            self._terminal.execute(text, port)

        self.background.submit(job)

    # -- coordinate systems and rotary buffers --------------------------------------------

    def coord_system(self, cs: int) -> CoordSystem:
        """Coordinate system ``cs`` (1..16). Raises NotFound."""
        try:
            return self.coord_systems[cs]
        except (KeyError, TypeError):
            raise NotFound(f"no coordinate system {cs!r} (1..{N_CS})") from None

    def _rotary_of(self, cs: int) -> RotaryBuffer:
        rot = self.coord_system(cs).rotary
        if rot is None:
            raise NotFound(f"coordinate system {cs} has no rotary buffer (DEFINE ROT first)")
        return rot

    def size_words(self) -> int:
        """Free buffer memory in words; negative while a buffer is open (``SIZE``)."""
        used = sum(c.rotary.size_words for c in self.coord_systems.values() if c.rotary)
        free = MEMORY_WORDS - used - (self.gather_words or 0) - self.programs.words()
        return -free if self.buffer_holder is not None else free

    def define_rotary(self, cs: int, words: int, *, entered: bool = False) -> dict[str, Any]:
        """``&cs DEFINE ROT words``; ``entered``: the host also enters the new buffer.

        ``entered`` is how the REST rotary resource defines a buffer (API.md): its lines go
        straight into the buffer, so defining it counts as entering it with ``OPEN ROT``, and
        BREQ is evaluated as ``OPEN ROT`` does (seed 000: low, then high below I17 lines ahead
        -- an empty buffer asks for lines) while the terminal's open state is left alone. At
        the terminal ``DEFINE ROT`` alone leaves BREQ low until ``OPEN ROT`` ``[INF]``.

        Ordering (seed 000, TUM p337, API.md): refused while a gather buffer exists or any CS
        numbered lower than ``cs`` has a rotary buffer — define from the highest CS down.
        ``[INF]`` also refused (ERR003) when ``cs`` already has one, ERR007 while buffers are
        open, ERR006 when memory is short.
        """
        self._alive()
        c = self.coord_system(cs)
        if isinstance(words, bool) or not isinstance(words, int) or words < 1:
            raise InvalidValue("size_words must be a positive whole number", field="size_words")
        if self.buffer_holder is not None:
            raise Conflict("close the open buffers first", pmac_error="ERR007")
        if self.gather_words is not None:
            raise Conflict(
                "a gather buffer exists: DELETE GATHER before DEFINE ROT", pmac_error="ERR003"
            )
        lower = [n for n, o in self.coord_systems.items() if n < cs and o.rotary is not None]
        if lower:
            raise Conflict(
                f"CS {lower[0]} (lower-numbered) already has a rotary buffer: define rotary "
                "buffers from the highest-numbered CS down",
                pmac_error="ERR003",
            )
        if c.rotary is not None:
            raise Conflict(f"CS {cs} already has a rotary buffer", pmac_error="ERR003")
        if words > self.size_words():
            raise BufferFull(f"only {self.size_words()} words of memory free", pmac_error="ERR006")
        c.rotary = RotaryBuffer(cs, words, self.log, self._thresholds, self.vars,
                                self.card_faults, self.programs)
        if entered:
            c.rotary.reevaluate()
        return self.rotary(cs)  # type: ignore[return-value]

    def delete_rotary(self, cs: int) -> None:
        """``&cs DELETE ROT``: erase the buffer and free its memory (ERR001 while running)."""
        self._alive()
        c = self.coord_system(cs)
        if c.rotary is None:
            return
        if c.running or c.moving:
            raise Conflict(f"CS {cs} is running its program", pmac_error="ERR001")
        c.rotary = None

    @property
    def gather_words(self) -> int | None:
        """Long words the gather buffer holds (None: no buffer)."""
        return self.gather.words

    def define_gather(self, words: int | None) -> None:
        """``DEFINE GATHER [n]`` (TSRM p307): ``n`` long words, all free memory without it; on
        an existing buffer it rewinds the storage address (its words count as free for the
        new size). ERR006 when memory is short, ERR003 while gathering
        (:mod:`motionsim.sim.pmac.tasks.gather`)."""
        self._alive()
        free = abs(self.size_words()) + (self.gather.words or 0)
        if words is not None and words > free:
            raise BufferFull(f"only {free} words of memory free for the gather buffer",
                             pmac_error="ERR006")
        self.gather.define(free if words is None else words)

    def start_gather(self, trigger: bool = False) -> None:
        """``GATHER``: data gathering from the next servo cycle; ``GATHER TRIGGER``: from the
        servo cycle that finds the trigger input risen (sim.pmac.tasks.gather)."""
        self._alive()
        self.gather.start(trigger)

    def end_gather(self) -> None:
        """``ENDGATHER``."""
        self.gather.end()

    def recording(self) -> SharedRecording:
        """What the last ``GATHER`` recorded (sim.recording; sim.pmac.tasks.gather)."""
        return self.gather.recording().shared()

    def delete_gather(self) -> None:
        """``DELETE GATHER`` (TSRM p315): ERR003 while gathering."""
        self.gather.delete()

    def define_lookahead(self, cs: int, segments: int, outputs: int) -> None:
        """``&cs DEFINE LOOKAHEAD segments,outputs`` (ordering: :mod:`.lookahead_buffer`)."""
        self._alive()
        self.coord_system(cs)
        lookahead_buffer.define(
            self.coord_systems, cs, segments, outputs, self.gather_words is not None
        )

    def delete_lookahead(self, cs: int) -> None:
        """``&cs DELETE LOOKAHEAD``."""
        self._alive()
        self.coord_system(cs)
        lookahead_buffer.delete(self.coord_systems, cs, self.gather_words is not None)

    def open_rotary(self, port: Port) -> None:
        """``OPEN ROT`` on ``port``: ERR007 if another port holds a buffer open."""
        if self.buffer_holder is not None and self.buffer_holder is not port:
            raise Conflict("another port holds a buffer open", pmac_error="ERR007")
        if self.programs.editing() is not None:
            raise Conflict("a PROG is open: CLOSE it first", pmac_error="ERR007")
        rotaries = [c.rotary for c in self.coord_systems.values() if c.rotary is not None]
        if not rotaries:
            raise Conflict("no rotary buffer is defined", pmac_error="ERR003")
        self.buffer_holder = port
        for rot in rotaries:
            rot.reevaluate()

    def close_buffers(self, port: Port) -> None:
        """``CLOSE``: this port's open buffers stop accepting lines; execution goes on."""
        if self.buffer_holder is port:
            self.buffer_holder = None
        self.programs.close(port)

    def open_program(self, n: int, port: Port) -> None:
        """``OPEN PROG n`` (:mod:`motionsim.sim.pmac.buffers.programs`): ERR007 with any buffer
        open,
        ERR001 while any CS runs a program; afterwards every CS must be pointed again with
        ``B`` before it may run (TSRM p381)."""
        self._alive()
        if self.buffer_holder is not None:
            raise Conflict("a buffer is open: CLOSE it first", pmac_error="ERR007")
        running = [c.cs for c in self.coord_systems.values() if c.running]
        if running:
            raise Conflict(f"CS {running[0]} is running a program", pmac_error="ERR001")
        self.programs.open(n, port)
        self.buffer_holder = port
        for c in self.coord_systems.values():
            c.program = None

    def program_lines(self, n: int) -> list[str] | None:
        """The lines of fixed program ``n`` as entered (what ``LIST PROG n`` decompiles), or
        None when there is no such program or it is empty."""
        lines = self.programs.programs.get(n)
        return [line.text for line in lines] if lines else None

    def store_program_line(self, line: ProgramLine) -> None:
        """One line into the open fixed program (ERR006 when buffer memory is full)."""
        if line.words > abs(self.size_words()):
            raise BufferFull("buffer memory is full", pmac_error="ERR006")
        self.programs.store(line)

    def store_line(self, c: CoordSystem, line: ProgramLine) -> None:
        """Store one compiled line in ``c``'s rotary buffer (ERR006 if it does not fit)."""
        rot = c.rotary
        if rot is None:
            raise NotFound(f"coordinate system {c.cs} has no rotary buffer")
        if not rot.fits(line.words):
            raise rot.no_room(line.words)
        rot.store(line)
        c.lines_arrived()

    def load_lines(
        self, cs: int, lines: Iterable[str], first_seq: int | None = None,
        precompiled: Mapping[str, ProgramLine] | None = None,
    ) -> LoadResult:
        """Store a batch of program lines in ``cs``'s rotary buffer, all or nothing.

        Every line is parsed and the batch sized before anything is stored. With
        ``first_seq`` the lines are numbered ``first_seq, first_seq+1, ...``; a line whose
        number was already stored with exactly this text is acknowledged and not stored
        again (the rules: :mod:`motionsim.sim.pmac.buffers.line_numbers`).
        ``precompiled``: lines the caller has compiled already (by text, e.g. in slices beside
        the event loop: ``api/line_slices.py``), used instead of parsing them again (a text
        missing from it is parsed here); like the lines parsed here, they are remembered for
        the next batches once stored.

        Raises:
            NotFound: no such CS or no rotary buffer.
            ParseError: a bad line (``index``, ``column``, ``text``; ERR003).
            BufferFull: the new lines do not fit (ERR006); nothing stored.
            Conflict: ``first_seq`` refused (a gap, a different repeat, out of range).
        """
        if self.halted:
            self._alive()
        c = self.coord_systems.get(cs) if type(cs) is int else None
        if c is None or c.rotary is None:
            rot = self._rotary_of(cs)  # raises NotFound
            c = self.coord_systems[cs]
        else:
            rot = c.rotary
        texts = lines if type(lines) is list else list(lines)
        cache = _LINE_CACHE
        if first_seq is None and len(texts) == 1:
            # The streaming case: one line, no sequence numbers.
            text = texts[0]
            line = cache.get(text) if type(text) is str else None
            if line is None:
                line = (
                    precompiled.get(text) if precompiled and type(text) is str else None
                ) or self._compile(text, 0)
                if not rot.fits(line.words):
                    raise rot.no_room(line.words)
                rot.store(line)
                self._remember(texts, [line])
            else:
                if not rot.fits(line.words):
                    raise rot.no_room(line.words)
                rot.store(line)
            c.lines_arrived()  # (it wants more with 2 calculated in the special lookahead)
            return _new_result(
                LoadResult, (1, 1, len(rot.pending), rot.size_words - rot.used_words, rot.breq)
            )
        pre = precompiled or {}
        compiled: list[ProgramLine] = []
        fresh: list[int] = []
        for i, text in enumerate(texts):
            line = cache.get(text) if type(text) is str else None
            if line is None:
                line = (pre.get(text) if type(text) is str else None) or self._compile(text, i)
                fresh.append(i)
            compiled.append(line)
        skip = 0 if first_seq is None else rot.numbering.repeated(first_seq, texts)
        new = compiled[skip:]
        words = sum(line.words for line in new)
        if not rot.fits(words):
            raise rot.no_room(words, len(new))
        store = rot.store
        for line in new:
            store(line)
        if fresh:
            self._remember([texts[i] for i in fresh], [compiled[i] for i in fresh])
        if new:
            c.lines_arrived()
        if first_seq is not None:
            rot.numbering.record(first_seq, texts, skip)
        return LoadResult(len(texts), len(new), rot.lines_ahead, rot.free_words, rot.breq)

    @staticmethod
    def line_compiled(text: str) -> bool:
        """Whether ``text``'s compiled form is at hand (streams repeat their line texts): a
        caller compiling a batch beforehand leaves it out."""
        return text in _LINE_CACHE

    @staticmethod
    def _compile(text: Any, index: int) -> ProgramLine:
        """Parse one batch line (cached by text); errors carry the batch ``index``."""
        if not isinstance(text, str):
            raise InvalidValue(f"line {index} is not text", field="lines", index=index)
        if len(text) > MAX_LINE_CHARS:
            raise ParseError(
                f"program line of {len(text)} characters is longer than the "
                f"{MAX_LINE_CHARS} a PMAC command line holds", index=index, line=index + 1,
                column=MAX_LINE_CHARS + 1, text=text[:80] + "...", pmac_error="ERR003")
        try:
            return compile_line(text)
        except ParseError as e:
            raise e.at(index=index, line=index + 1) from None

    @staticmethod
    def _remember(texts: list[str], compiled: list[ProgramLine]) -> None:
        """Cache the compiled form of lines just stored (never of refused ones)."""
        if len(_LINE_CACHE) + len(texts) > _LINE_CACHE_SIZE:
            _LINE_CACHE.clear()
        for text, line in zip(texts[:_LINE_CACHE_SIZE], compiled, strict=False):
            _LINE_CACHE[text] = line

    def point_program(self, cs: int, program: float) -> None:
        """``B{n}``: point the CS at program ``n`` (0 = rotary) at its top. ERR001 while
        running."""
        c = self.coord_system(cs)
        if c.running:
            raise Conflict(f"CS {cs} is running", pmac_error="ERR001")
        if program != int(program) or not 0 <= program <= 32767:
            raise InvalidValue(f"no program {program}", field="program", pmac_error="ERR003")
        c.program = int(program)
        c.fixed = None
        if c.planned:  # moves a ``/`` stop kept belong to the program pointed away from
            c.planned.clear()
            c.calc_pos = dict(c.rest_pos)
            if c.rotary is not None:
                c.rotary.free_calculated()

    def run(self, cs: int, pointer: float | None = 0, single_step: bool = False) -> None:
        """``R`` (``S`` with ``single_step``); REST's run is ``B0 R`` (``pointer=0``).

        ``B0`` runs the rotary buffer; ``B{n}`` fixed program n (:mod:`.programs`), which
        continues where it stopped (``Q``, ``S``, ``A``) or, once it has ended, from the top.

        Raises:
            Conflict: ERR015 when the CS does not point at a valid program (no ``B`` since a
                PROG was opened, no rotary buffer, no such PROG, a PROG open for entry).
        """
        self._alive()
        c = self.coord_system(cs)
        if not c.running:  # a running CS's R / S only changes its mode
            check_start(cs, self._cs_motors(cs), self.vars, bool(self.config.get(
                "strict_cs_motors", False)))
        if pointer is not None and not c.running:
            c.program = pointer
        if c.program is None or (c.program == 0 and c.rotary is None):
            raise Conflict(
                f"CS {cs} does not point to a valid program buffer (B0 with a rotary buffer, "
                "or B{n} of a PROG)",
                pmac_error="ERR015",
            )
        if self.programs.editing() is not None:
            raise Conflict("a PROG is open for entry: CLOSE first", pmac_error="ERR015")
        if c.program != 0 and not c.running:
            run = c.fixed
            # a program whose last lines were calculated before a ``/`` stop has not ended:
            # its calculated moves run first (CoordSystem.stop_at_end)
            if run is None or run.number != c.program or (run.finished and not c.planned):
                c.fixed = self.programs.run_of(cs, int(c.program), self.log.emit, self.vars)
            else:
                run.resume()  # after Q, A, S or a STOP: on from the program counter
        self.kinematics.program_start(cs)
        c.run(single_step)

    def _cs_motors(self, cs: int) -> list[Motor]:
        """The motors with an axis definition in ``cs``."""
        return [self.motor_table[n] for n, (c, _d) in self.motors.items() if c == cs]

    def enable_cs(self, cs: int) -> None:
        """``E``: close the loop of every killed / open-loop motor of ``cs`` at its present
        position (:mod:`motionsim.sim.pmac.language.cs_enable`)."""
        self._alive()
        for m in self._cs_motors(cs):
            if m.loop != "closed_loop":
                m.enable()

    def quit(self, cs: int) -> None:
        """``Q``."""
        self._alive()
        self.coord_system(cs).quit()

    def mflush(self, cs: int) -> None:
        """``MFLUSH``: empty the synchronous M-variable queue of ``cs`` (TUM p250)."""
        self._alive()
        self.coord_system(cs).mflush()

    def abort(self, cs: int) -> None:
        """``A``; the host's ``first_seq`` numbering of the CS's rotary lines starts again."""
        self._alive()
        c = self.coord_system(cs)
        c.abort()
        if c.rotary is not None:
            c.rotary.numbering.reset()

    def kill_all(self) -> None:
        """CTRL-K: kill every motor at once; a running program is aborted with
        ``error="killed"``, its lookahead and queued synchronous writes lost (TUM p319)."""
        self._alive()
        for c in self.coord_systems.values():
            c.kill("killed")
        self.motor_table.kill_all()

    def coord(self, cs: int) -> dict[str, Any]:
        """``{"cs", "program": {"state", "line"?}, "rotary": Rotary | None}`` (API.md)."""
        c = self.coord_system(cs)
        return {"cs": cs, "program": c.to_dict(), "rotary": self.rotary(cs)}

    def rotary(self, cs: int) -> dict[str, Any] | None:
        rot = self.coord_system(cs).rotary
        return None if rot is None else rot.to_dict(self.rotary_open())

    def rotary_open(self) -> bool:
        """The rotary buffers are open for entry: ``OPEN ROT`` and no ``CLOSE`` yet.

        ``buffer_holder`` is the port holding *any* buffer open (only one may, ERR007); while
        it holds a PLC open (``OPEN PLC n``) the rotary buffers stay closed.
        """
        return (
            self.buffer_holder is not None
            and self.plcs.editing() is None
            and self.programs.editing() is None
        )

    def positions(self, cs: int, t: float | None = None) -> dict[str, float]:
        """Commanded axis positions of ``cs`` now (or at a ``t`` within the current move)."""
        return self.coord_system(cs).positions(t)

    def wait_breq(self, cs: int) -> simpy.Event:
        """An event that fires at the next rising BREQ edge of ``cs`` (a host's interrupt)."""
        ev = self.env.event()
        self._rotary_of(cs).on_rise(ev.succeed)
        return ev

    # -- motors ----------------------------------------------------------------------------

    def _motor_axis(self, motor: int) -> tuple[int, str, float] | None:
        have = self.motors.get(motor)
        if have is None:
            return None
        d = axis_definitions.lookup(have[1])
        if d.inverse:  # #n->I: its position comes from the kinematic programs
            return have[0], f"I{motor}", 1.0
        terms = d.terms
        if not terms:
            return None
        return have[0], terms[0][0], terms[0][1]

    def _at_one_instant(self, read: Callable[[], _T]) -> _T:
        """Run ``read`` (reads only, no state change: a gather sample's registers) with each
        coordinate system's axis positions computed once for the instant, not once per
        register read."""
        self._positions_memo = {}
        try:
            return read()
        finally:
            self._positions_memo = None

    def _cs_positions(self, cs: int, t: float) -> Mapping[str, float]:
        memo = self._positions_memo
        if memo is None:
            return self.coord_systems[cs].positions(t)
        key = (cs, t)  # a velocity report asks for two instants
        pos = memo.get(key)
        if pos is None:
            pos = memo[key] = self.coord_systems[cs].positions(t)
        return pos

    def _motor_base(self, motor: int, t: float) -> float:
        """Motor ``motor``'s position from its CS axes (counts): the sum of its definition's
        terms plus its constant offset (``#3->2000Z-6000``: Z=3 puts the motor at 0, TSRM
        p268), or the inverse kinematics for ``#n->I``."""
        have = self.motors.get(motor)
        if have is None:
            return 0.0
        d = axis_definitions.lookup(have[1])
        if d.inverse:
            return self.kinematics.motor_base(have[0], motor, t)
        terms = d.terms
        if len(terms) == 1:
            return (self._cs_positions(have[0], t).get(terms[0][0], 0.0)
                    * terms[0][1] + d.offset)
        pos = self._cs_positions(have[0], t) if terms else {}
        return sum(pos.get(a, 0.0) * s for a, s in terms) + d.offset

    def axis_offset_changed(self, motor: int, delta: float) -> None:
        """A new axis definition moved motor ``motor``'s offset by ``delta`` counts: a
        definition commands no motion, so a motor at rest keeps its position (its jog offset
        absorbs the change) until ``PMATCH`` starts the axes from the motors ``[INF]``."""
        self.motor_table[motor].offset_moved(delta)

    def _axis_position(self, cs: int, axis: str, t: float) -> float:
        if axis[0] == "I":  # ``I{n}``: motor n defined #n->I
            return self.kinematics.motor_base(cs, int(axis[1:]), t)
        return self.coord_systems[cs].positions(t).get(axis, 0.0)

    def _cs_running(self, cs: int) -> bool:
        return self.coord_systems[cs].running

    def motor(self, n: int) -> Motor:
        """Motor ``n`` (1..32). Raises NotFound."""
        if type(n) is not int or not 1 <= n <= N_MOTORS:
            raise NotFound(f"no motor {n!r} (1..{N_MOTORS})")
        return self.motor_table[n]

    def run_statement(self, stmt: Any, cs: int, motor: int) -> list[str]:
        """Run an on-line command statement as a PLC program does (no port; ``cs`` / ``motor``
        addressed): its row of :mod:`motionsim.sim.pmac.host.commands`. The data lines it
        answers (a PLC sends them nowhere)."""
        out: list[str] = []
        commands.run(commands.Call(self, None, {"cs": cs, "motor": motor}, out), stmt)
        return out

    def motor_command(self, stmt: Any, n: int) -> None:
        """An on-line motor command (:mod:`motionsim.sim.pmac.language.motor_statements`) for motor
        ``n``; ERR001 while its CS runs a program (:mod:`motionsim.sim.pmac.motor.motors`)."""
        self._alive()
        m = self.motor(n)
        self.motor_table.check_free(n)
        t = type(stmt)
        if t is motor_st.Jog:
            value = stmt.value
            if stmt.variable:  # J=* J^* J:*: Mxx72, read as the command runs
                value = pmac_float.decode(
                    self.vars.mvars.long(registers.variable_jog_address(n)))
            m.jog(stmt.command, value, stmt.trigger)
        elif t is motor_st.Home:
            if stmt.zero:
                m.home_zero()
            else:
                m.home()
        elif t is motor_st.Kill:
            m.kill()
        elif t is motor_st.OpenLoop:
            m.open_loop(stmt.percent)
        elif t is motor_st.Enable:
            if stmt.absolute:
                m.absolute_read()
            else:
                m.enable()
        else:  # pragma: no cover - MOTOR_TYPES are all handled above
            raise InvalidValue(f"not a motor command: {stmt!r}")

    def motor_position(self, n: int, t: float | None = None) -> float:
        """Commanded (= actual) position of motor ``n`` in counts, now or at ``t``."""
        return self.motor(n).position(self.env.now if t is None else t)

    def motor_report(self, motor: int, what: str) -> float:
        """``P`` (position, counts to 1/10), ``V`` (counts per servo cycle, averaged over the
        last cycle) or ``F`` (following error: 0, the loop tracks perfectly ``[INF]``)."""
        if what == "F":
            return 0.0
        memo = self._positions_memo
        if memo is None:
            return self._report(motor, what)
        key = (motor, what)  # one instant's reads (_at_one_instant): each report once
        value = memo.get(key)
        if value is None:
            value = memo[key] = self._report(motor, what)
        return float(value)

    def _report(self, motor: int, what: str) -> float:
        m = self.motor(motor)
        return registers.report_at(m.position, what, self.env.now, self.scheduler.period_s)

    def motor_position_spec(self, motor: int) -> MotorSpec | None:
        """What :meth:`motor_position` of ``motor`` is as a function of ``t`` alone while
        nothing about its motion changes, as numbers and objects copied out of the present
        state (:func:`motor_position_at` evaluates it: the sums of :meth:`_motor_base` over
        :meth:`Execution.axis_position_spec`, plus the jog profile): data gathering reads the
        servo cycles between two events with it (:mod:`.tasks.gather_readers`). None where
        the axis positions have no such form (``#n->I``, move modes other than LINEAR)."""
        profile = self.motor(motor).profile
        have = self.motors.get(motor)
        if have is None:
            return None, 0.0, profile
        d = axis_definitions.lookup(have[1])
        if d.inverse:
            return None
        c = self.coord_systems[have[0]]
        terms = []
        for axis, scale in d.terms:
            spec = c.axis_position_spec(axis)
            if spec is None:
                return None
            terms.append((spec, scale))
        return tuple(terms), d.offset, profile

    def set_motor_position(self, motor: int, counts: float) -> None:
        """Make motor ``motor``'s present position ``counts`` without motion: a write of its
        actual-position register Mxx62 (:mod:`motionsim.sim.pmac.card.registers`), as a backup
        tool restores positions after CTRL-K. ``[INF]`` the position reference moves (like
        ``HMZ`` to a given value); the motor does not."""
        if 1 <= motor <= N_MOTORS:
            m = self.motor(motor)
            m.profile = m.profile.shifted(counts - m.position(self.env.now))

    def motor_status(self, motor: int) -> tuple[int, int]:
        """The two 24-bit words of ``#n?`` (:mod:`motionsim.sim.pmac.motor.motor_status`)."""
        m = self.motor(motor)
        axis = self._motor_axis(motor)
        cs = self.coord_systems[axis[0]] if axis is not None else None
        return motor_status_words(m, axis, cs, self.vars, self.env.now)

    # -- variables ------------------------------------------------------------------------

    def get_variable(self, name: str) -> float:
        kind, n, cs = parse_name(name)
        return self.vars.read(kind, n, cs)

    def set_variable(self, name: str, value: float) -> None:
        self._alive()
        kind, n, cs = parse_name(name)
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise InvalidValue("value must be a number", field="value")
        if not math.isfinite(value):
            raise InvalidValue("value must be finite", field="value")
        self.vars.write(kind, n, float(value), cs)
        if kind == "I":
            self.background.poke()  # I5 / I8 / I40 may change what the processor runs

    # -- life cycle -----------------------------------------------------------------------

    def reset(self) -> None:
        """Power cycle: factory defaults (plus config), buffers and programs gone."""
        self.background.queue.clear()
        for c in self.coord_systems.values():
            c.detach()
        self._power_on()
        self.log.emit("reset")

    def status(self) -> dict[str, Any]:
        """The controller resource's PMAC part: processor shares (``cpu``, with
        ``last_background_s``), the watchdog and its reload margin, per-PLC scan figures."""
        bg = self.background
        wd = bg.watchdog
        cpu: dict[str, Any] = dict(bg.load())
        cpu["last_background_s"] = bg.last_background_s
        return {
            "cpu": cpu,
            "watchdog": {"tripped": self.halted, "t": wd.t_trip, **wd.margin(bg.active)},
            "plcs": {
                str(p.n): {"statements_last_scan": p.last_statements, "scans": p.scans}
                for p in self.plcs.plcs
                if p.program is not None or p.scans
            },
            "servo_period_s": self.scheduler.period_s,
            "rti_period_s": self.scheduler.rti_period_s(),
            "coord": {
                str(n): c.state
                for n, c in self.coord_systems.items()
                if c.rotary is not None or c.state != "idle"
            },
        }


__all__ = ["LoadResult", "PmacController"]
