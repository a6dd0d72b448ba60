"""``TrioController`` (kind ``"trio"``): a simulated Trio Motion Coordinator.

Axes with MTYPE / NTYPE move buffers, one process buffer per process, Trio BASIC programs
running as processes 1..N, and the command line as process 0 — the buffering of TN20-16.

Config (``POST /controllers {"kind": "trio", "config": {...}}``), unknown keys refused:

* ``model`` (``"mc2xx"``): the generation — number word size and HEX width, language, default
  process count and VR / TABLE sizes (:mod:`motionsim.sim.trio.card.models`: ``series2``,
  ``mc2xx``, ``mc4xx``, ``mc6xx``);
* ``servo_period_ms`` (1.0): SERVO_PERIOD; moves start and end on servo periods;
* ``axes`` (8): number of axes, 0..axes-1;
* ``processes`` (the model's: 7 on mc2xx = MC206, 14 series2 = MC216, 22 mc4xx / mc6xx):
  BASIC processes 1..processes (process 0 is the command line on every model here);
* ``statement_us`` (100.0): simulated time one BASIC statement costs (spec §9.6 ``[INF]``);
* ``vr_count`` and ``table_size`` (the model's: 1024 / 16384 on series2 and mc2xx, 64000 /
  500000 on mc4xx, 65536 / 512000 on mc6xx): sizes of VR() and TABLE();
* ``ethercat_slaves`` (one per axis): the slaves of the EtherCAT network ETHERCAT() reports
  (:mod:`motionsim.sim.trio.card.fieldbus`);
* ``speed``, ``accel``, ``decel``, ``creep``, ``units``: axis parameter defaults for all axes.

The public methods act at the current simulated instant and never step the environment.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from ..bounds import TRIO_CONFIG
from ..controller import Controller, Port, Reply
from ..errors import (
    BufferFull,
    Conflict,
    InvalidValue,
    NotFound,
    NotSimulated,
    ParseError,
)
from ..recording import Recording
from ..timing import ServoClock
from .card.axis_status import StoredParams, axisstatus
from .card.basic_errors import BasicError
from .card.io import CHANNELS, IoImage
from .card.models import DEFAULT_MODEL, WORD_MAX, out_of_word
from .card.models import model as model_named
from .card.output import Channels
from .card.system import SystemParams
from .language.compiler import Code, compile_program
from .language.functions import FunctionDef, Library, visible
from .language.move_words import LINKED, MOVE_ARGS
from .language.parser import parse_program
from .language.scope import Decl, rebinding
from .language.statements import Program
from .motion.axis import DEFAULTS, Axis
from .motion.buffers import MotionBuffers, Waiter
from .motion.issue import new_move
from .motion.mtypes import MTYPE, axes_driven
from .run.context import Context
from .run.process import BasicProcess
from .run.scope import Scope
from .terminal import CommandLine

_CONFIG_DEFAULTS: dict[str, float] = {
    "servo_period_ms": 1.0,
    "axes": 8,
    "processes": 7,
    "statement_us": 100.0,
    "vr_count": 1024,
    "table_size": 16384,
    "ethercat_slaves": -1,  # -1: one per axis (sim/trio/card/fieldbus.py)
}
_VARIABLE = re.compile(r"^\s*(VR|TABLE|IN|OP)\s*\(\s*(\d+)\s*\)\s*$", re.I)
_PROGRAM_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]{0,31}$")


@dataclass(frozen=True, slots=True)
class Precompiled:
    """A program text parsed and compiled off the event loop (:meth:`TrioController.
    detached_compiler`), with what the compile read: the GLOBAL / CONSTANT version and the
    parsed programs it INCLUDEd."""

    parsed: Program
    code: Code
    version: int
    used: dict[str, Program | None]


class TrioController(Controller):
    """A simulated Trio Motion Coordinator (MC2xx series buffering)."""

    kind = "trio"
    event_types = ("offpos", "move_modify", "output", "wdog", "basic_error")

    #: The command line answers at the current instant and never moves a virtual clock
    #: (API.md): ``ControllerHandle.command`` returns a locked line pending at once.
    terminal_wait_s = 0.0

    #: Events of the motion modules: a set-up command ran, a DATUM sequence found its datum,
    #: a move was stopped at a software limit (``axis``, ``limit``, ``mtype``), ENDMOVE
    #: written at rest stepped the demand (``axis``, ``dpos``), a following error beyond
    #: FE_LIMIT (``axis``, ``fe``), a motion error (``axis``, ``axisstatus``).
    event_types += ("setup", "datum", "soft_limit", "endmove", "following_error",
                    "motion_error", "scope")

    def __init__(
        self, id: str, config: Mapping[str, Any] | None = None, *, log_capacity: int = 100_000
    ) -> None:
        super().__init__(id, config, log_capacity=log_capacity)
        settings: dict[str, float] = dict(_CONFIG_DEFAULTS)
        axis_defaults: dict[str, float] = {}
        self.model = model_named(self.config.get("model", DEFAULT_MODEL))
        settings["processes"] = self.model.processes
        settings["vr_count"] = self.model.vr_count
        settings["table_size"] = self.model.table_size
        for key, value in self.config.items():
            if key == "model":
                continue
            if key in DEFAULTS:
                axis_defaults[key] = value
                continue
            if key not in settings:
                known = ", ".join(sorted([*settings, *DEFAULTS, "model"]))
                raise InvalidValue(f"unknown trio config key {key!r}; known: {known}", field=key)
            TRIO_CONFIG[key].check(value, key)  # sim/bounds.py
            settings[key] = value
        self.clock = ServoClock(float(settings["servo_period_ms"]) / 1000.0)
        self.statement_s = float(settings["statement_us"]) / 1e6
        self.n_axes = int(settings["axes"])
        self.n_processes = int(settings["processes"])
        self.vr_count = int(settings["vr_count"])
        self.table_size = int(settings["table_size"])
        slaves = int(settings["ethercat_slaves"])
        self.ethercat_slaves = self.n_axes if slaves < 0 else slaves
        Axis(0, self.env, self.clock, axis_defaults)  # validates the axis defaults
        self._axis_defaults = axis_defaults
        self.channels = Channels(self.log)
        self._cursors: dict[str, int] = {}
        self._build()

    def _build(self) -> None:
        self.axes = [Axis(n, self.env, self.clock, self._axis_defaults) for n in range(self.n_axes)]
        self.buffers = MotionBuffers(self.env, self.clock, self.log, self.axes)
        self.vr: list[float] = [0.0] * self.vr_count
        self.table: dict[int, float] = {}
        self.programs: dict[str, tuple[str, Code]] = {}
        self.parsed: dict[str, Program] = {}  # for INCLUDE (sim/trio/language/declarations.py)
        self.declared: dict[str, Decl] = {}  # GLOBAL / CONSTANT names that have run
        self.libraries: dict[str, Library] = {}  # stored BASIC libraries (language/functions)
        self.declared_version = 0
        self.basic: dict[int, BasicProcess] = {}
        self.io = IoImage(self.log)
        self.system = SystemParams(self)
        self.buffers.on_axis_error = self._axis_error
        self.stored = [StoredParams() for _ in range(self.n_axes)]
        for ax, st in zip(self.axes, self.stored, strict=True):
            ax.stored = st
        self.command_line = CommandLine(self)
        self._move_waits: dict[int, Waiter] = {}
        old_scope = getattr(self, "scope", None)
        if old_scope is not None:
            old_scope.detach()
        #: SCOPE / TRIGGER sampling into TABLE (sim.trio.run.scope).
        self.scope = Scope(self)

    def _axis_error(self, n: int) -> None:
        """An error condition on axis ``n``: a motion error if AXISSTATUS meets ERRORMASK."""
        st = self.stored[n]
        self.system.axis_error(n, axisstatus(self.axes[n], st), int(st.read("ERRORMASK")))

    # -- life cycle --------------------------------------------------------------------------

    def reset(self) -> None:
        """Power cycle: programs, processes, buffers and VR gone; factory parameters."""
        for proc in list(self.basic.values()):
            if proc.state != "stopped":
                proc.stop()
        self.command_line.reset()
        self.buffers.shutdown()
        self._build()
        self.log.emit("reset")

    def modbus_registers(self) -> str:
        """What Modbus holding register n is: ``"VR"`` (VR(n), the default) or, after
        ``ETHERNET(2, slot, 9, 1)``, ``"TABLE"`` (TABLE(n); spec trio.md §3.3, M224-550)."""
        return "TABLE" if self.system.comms.ethernet.get(9) == 1.0 else "VR"

    def recording(self) -> Recording:
        """What the last SCOPE capture put in TABLE (sim.recording; sim.trio.run.scope)."""
        return self.scope.recording().shared()

    def status(self) -> dict[str, Any]:
        return {
            "servo_period_ms": self.clock.period_s * 1000.0,
            "axes": self.n_axes,
            "processes": self.n_processes,
            "terminal": self.terminal_state(),
        }

    # -- the command line --------------------------------------------------------------------

    def terminal(self, command: str, port: Port | None = None) -> Reply:
        """One line at the command line (process 0); pending while the terminal is locked."""
        return self.command_line.command(command)

    def terminal_state(self) -> dict[str, Any]:
        return self.command_line.state()

    def unread_output(self, reader: str) -> list[str]:
        """Channel-0 lines printed since ``reader`` last asked (the REST terminal: ``"rest"``;
        the first call returns the lines kept since power-up)."""
        lines, self._cursors[reader] = self.channels.since(self._cursors.get(reader, 0))
        return lines

    # -- axes --------------------------------------------------------------------------------

    def _axis(self, n: int) -> Axis:
        if not isinstance(n, int) or not 0 <= n < self.n_axes:
            raise NotFound(f"no axis {n} (axes 0..{self.n_axes - 1})", field="axis")
        return self.axes[n]

    def axis(self, n: int) -> dict[str, Any]:
        """The axis resource: MTYPE, NTYPE, DPOS, MPOS, ENDMOVE, REMAIN and parameters."""
        return self._axis(n).snapshot()

    def set_axis(self, n: int, **params: float) -> dict[str, Any]:
        """Write axis parameters (``speed``, ``accel``, ``decel``, ``units``, ``creep``,
        ``merge``, ``sramp``); all are checked before any is written."""
        ax = self._axis(n)
        ax.set(**params)
        if "fe_lag" in params:
            self.buffers.watch_fe(n)
        return ax.snapshot()

    def move(
        self,
        axis: int,
        type: str,
        args: list[float] | tuple[float, ...],
        process: int | None = None,
        wait: bool = False,
    ) -> str | Reply:
        """Issue a motion command with ``axis`` as its base axis, for ``process`` (default 0).

        Multi-axis commands drive ``axis`` and the axes after it (``MOVE(10,20)`` on axis 0
        drives axes 0 and 1). Returns where the move was placed (``"mtype"``, ``"ntype"``,
        ``"process_buffer"``). When the process buffer is full: without ``wait`` raise
        :class:`BufferFull` and change nothing; with ``wait`` return a :class:`Reply` that is
        done (``reply`` = the placement) in the servo period where the move is buffered —
        as a BASIC process waits at its move line. With ``wait`` a Reply is always returned.
        """
        self._axis(axis)
        kind = str(type).upper()
        if kind not in MTYPE:
            raise InvalidValue(
                f"unknown move type {type!r}; known: {', '.join(MTYPE)}", field="type"
            )
        lo, hi = MOVE_ARGS[kind]
        args = tuple(float(a) for a in args)
        if not lo <= len(args) <= hi:
            raise InvalidValue(f"{kind} takes {lo}..{hi} arguments, got {len(args)}", field="args")
        if kind == "DATUM" and int(args[0]) == 0:
            raise InvalidValue("DATUM(0) clears axis errors and buffers no move", field="args")
        if kind in LINKED:
            raise InvalidValue(
                f"{kind} links to another axis or the TABLE: issue it as Trio BASIC "
                "(POST /terminal or a program)", field="type")
        p = 0 if process is None else self.process_number(process, allow_zero=True)
        size = axes_driven(kind, len(args))
        axes = tuple(range(axis, axis + size))
        if axes[-1] >= self.n_axes:
            raise InvalidValue(
                f"{kind} with {len(args)} arguments drives axes {axes[0]}..{axes[-1]}; "
                f"there are {self.n_axes} axes",
                field="axis",
            )
        text = f"{kind}({','.join(f'{a:g}' for a in args)}) AXIS({axis})"
        try:
            move = new_move(self, kind, axes, args, p, text)
        except BasicError as exc:  # a DATUM sequence number it does not know
            raise InvalidValue(exc.message, field="args") from None
        if not wait:
            placed = self.buffers.place(move)
            if placed is None:
                raise BufferFull(
                    f"process {p}: MTYPE, NTYPE and the process buffer are full", process=p
                )
            return placed
        reply = Reply(text)

        def placed(where: str) -> None:
            self._move_waits.pop(id(reply), None)
            reply.resolve(where, None, self.env.now)

        result = self.buffers.place_or_wait(move, placed)
        if isinstance(result, Waiter):
            self._move_waits[id(reply)] = result
        else:
            reply.resolve(result, None, self.env.now)
        return reply

    def pmove(self, process: int) -> int:
        """PMOVE PROC(process): 1 while that process' move buffer holds a move (M206-320)."""
        return self.buffers.pmove(self.process_number(process, allow_zero=True))

    def withdraw_move(self, reply: Reply) -> bool:
        """Give up a ``move(..., wait=True)`` not yet placed; True if it was withdrawn (then
        nothing of it was queued)."""
        waiter = self._move_waits.pop(id(reply), None)
        if waiter is None or reply.done:
            return False
        waiter.cancel()
        return True

    # -- programs ----------------------------------------------------------------------------

    @staticmethod
    def _name(name: str) -> str:
        if not _PROGRAM_NAME.match(name or ""):
            raise InvalidValue(f"bad program name {name!r}", field="name")
        return name.upper()

    def _stored(self, name: str) -> str:
        """The key of the stored program ``name`` (NotFound when there is none)."""
        key = self._name(name)
        if key not in self.programs:
            raise NotFound(f"no program {key}", field="name")
        return key

    def detached_compiler(self, name: str) -> Callable[[str], Precompiled]:
        """A pure ``text -> Precompiled`` for a worker thread (``api/off_loop.py``): it parses
        and compiles against a snapshot, taken now, of the stored programs and the GLOBAL /
        CONSTANT names; :meth:`store_program` uses its result when nothing it read has
        changed since, and compiles again otherwise. A compile error is raised as the store
        would raise it."""
        key = self._name(name)
        model = self.model.name
        stored = dict(self.parsed)
        declared = dict(self.declared)
        version = self.declared_version
        functions = visible(self.libraries, replacing=key)

        def compile_text(text: str) -> Precompiled:
            try:
                parsed = parse_program(text, model)
            except (ParseError, NotSimulated) as exc:
                exc.details.setdefault("program", key)
                raise
            code = compile_program(
                parsed, key, lambda n: parsed if n == key else stored.get(n), declared, version,
                functions)
            used = {n: stored.get(n) for n in code.includes}
            return Precompiled(parsed, code, version, used)

        return compile_text

    def store_program(self, name: str, text: str, pre: Precompiled | None = None) -> None:
        """Parse and compile ``text`` in the model's language and store it; the programs that
        INCLUDE it are compiled again with it. A compile error (of it, or of a program that
        includes it) names the program, line and column and changes nothing. ``pre``: the
        result of :meth:`detached_compiler` for this text, or None."""
        key = self._name(name)
        if not text.strip():
            raise InvalidValue(
                f"program {key}: the text is empty (a program needs at least one line)",
                field="body",
            )
        if pre is not None and pre.version == self.declared_version and all(
            self.parsed.get(n) is p for n, p in pre.used.items()
        ) and key not in self.libraries:
            parsed, code = pre.parsed, pre.code
        else:
            try:
                parsed = pre.parsed if pre is not None else parse_program(text, self.model.name)
            except (ParseError, NotSimulated) as exc:
                exc.details.setdefault("program", key)
                raise
            code = self._compile(key, parsed, {key: parsed})
        library = code.library
        dependants = {
            other: self._compile(other, self.parsed[other], {key: parsed}, (key, library))
            for other, (_text, other_code) in self.programs.items()
            if key in other_code.includes and other in self.parsed
        }
        self.programs[key] = (text, code)
        self.parsed[key] = parsed
        for other, other_code in dependants.items():
            self.programs[other] = (self.programs[other][0], other_code)
        if library is not None or self.libraries.pop(key, None) is not None:
            if library is not None:
                self.libraries[key] = library
            self.declared_version += 1  # programs RUN from now on see the new functions

    def check_program(self, name: str, text: str) -> list[ParseError | NotSimulated]:
        """Every error storing ``text`` as program ``name`` would meet, in line order, and
        nothing stored: a line that does not parse is left out and the rest still parsed, a
        statement that does not compile is left out and the rest still compiled (the check
        tool, ``motionsim check``). Errors after the first may follow from it (a FOR left out
        makes its NEXT a NEXT without FOR)."""
        key = self._name(name)
        errors: list[ParseError | NotSimulated] = []
        parsed = parse_program(text, self.model.name, errors=errors)
        compiled: list[ParseError] = []

        def resolve(n: str) -> Program | None:
            return parsed if n == key else self.parsed.get(n)

        compile_program(parsed, key, resolve, self.declared, self.declared_version,
                        visible(self.libraries, replacing=key), errors=compiled)
        errors.extend(compiled)
        for err in errors:
            err.details.setdefault("program", key)
        return sorted(errors, key=lambda e: (e.details.get("program") != key,
                                             int(e.details.get("line") or 0),
                                             int(e.details.get("column") or 0)))

    def _compile(self, key: str, parsed: Program, pending: dict[str, Program],
                 library: tuple[str, Library | None] | None = None) -> Code:
        """Compile program ``key`` against the stored programs (``pending`` first), the
        GLOBAL / CONSTANT names declared so far and the functions of the stored libraries
        (``library``: a library being stored, ``(name, its functions or None)``)."""

        def resolve(name: str) -> Program | None:
            return pending.get(name) or self.parsed.get(name)

        replacing, new = library if library is not None else (key, None)
        return compile_program(parsed, key, resolve, self.declared, self.declared_version,
                               visible(self.libraries, replacing, new))

    def functions(self) -> dict[str, FunctionDef]:
        """The functions of every stored BASIC library (the command line calls them too)."""
        return visible(self.libraries)

    def declare(self, name: str, decl: Decl) -> None:
        """GLOBAL / CONSTANT ran: programs compiled (or RUN) from now on see ``name``.

        Raises:
            BasicError: ``name`` is already bound otherwise (:func:`~.scope.rebinding`).
        """
        why = rebinding(name, self.declared.get(name), decl)
        if why is not None:
            raise BasicError(why)
        if self.declared.get(name) != decl:
            self.declared[name] = decl
            self.declared_version += 1

    def program(self, name: str) -> str:
        key = self._stored(name)
        return self.programs[key][0]

    def program_names(self) -> list[str]:
        return sorted(self.programs)

    def delete_program(self, name: str) -> None:
        key = self._stored(name)
        for p, proc in self.basic.items():
            if proc.program == key and proc.state != "stopped":
                raise Conflict(f"program {key} is running in process {p}")
        del self.programs[key]
        if self.libraries.pop(key, None) is not None:
            self.declared_version += 1

    def process_number(self, p: Any, allow_zero: bool = False) -> int:
        lo = 0 if allow_zero else 1
        try:
            n = int(p)
        except (TypeError, ValueError):
            n = -1
        if n != p or not lo <= n <= self.n_processes:
            raise InvalidValue(
                f"process must be {lo}..{self.n_processes}, got {p!r}", field="process"
            )
        return n

    def run_program(self, name: str, process: int | None = None) -> int:
        """RUN "name"[, process]: start it; without a process the highest free one ``[BK]``."""
        key = self._stored(name)
        busy = {p for p, proc in self.basic.items() if proc.state != "stopped"}
        if process is None:
            free = [p for p in range(self.n_processes, 0, -1) if p not in busy]
            if not free:
                raise Conflict("every process is running a program")
            p = free[0]
        else:
            p = self.process_number(process)
            if p in busy:
                raise Conflict(f"process {p} is already running {self.basic[p].program}")
        text, code = self.programs[key]
        if code.library is not None:
            raise InvalidValue(f"{key} is a BASIC library: its FUNCTIONs are called from other "
                               "programs, it cannot be RUN", field="name")
        if code.shared_version != self.declared_version and key in self.parsed:
            code = self._compile(key, self.parsed[key], {})  # new GLOBAL / CONSTANT names
            self.programs[key] = (text, code)
        self.basic[p] = BasicProcess(self, p, key, code)
        return p

    def processes(self) -> list[dict[str, Any]]:
        return [proc.describe() for _p, proc in sorted(self.basic.items())]

    def proc_status(self, p: int) -> int:
        """PROC_STATUS PROC(p): 0 = not running, 1 = running (waiting at a line included);
        the command line (process 0) is always running ``[INF]`` (spec §10.7)."""
        if p == 0:
            return 1
        proc = self.basic.get(p)
        return 1 if proc is not None and proc.state != "stopped" else 0

    def data_bytes_in_use(self) -> int:
        """Program data memory the running processes' DIMs hold (sim.trio.data_memory)."""
        return sum(sum(proc.ctx.data_bytes.values()) for proc in self.basic.values()
                   if proc.state != "stopped")

    def context_of(self, p: int) -> Context:
        """The runtime context of process ``p`` (a fresh one for a process that never ran)."""
        if p == 0:
            return self.command_line.ctx
        proc = self.basic.get(p)
        if proc is None:
            return Context(self, p, lambda *_a: None)
        return proc.ctx

    def halt(self, except_process: int | None = None) -> None:
        """HALT: every running program stops at once (motion already buffered goes on,
        ``[BK]``: the TRM page was not reachable); ``except_process`` is left to stop itself."""
        for p, proc in sorted(self.basic.items()):
            if p != except_process and proc.state != "stopped":
                proc.stop()

    def process_table(self) -> list[str]:
        """PROCESS at the command line: one line per running program (``[BK]`` layout: the
        TRM page was not reachable) — process number, program, state, line."""
        rows = [f"Process {p:>2}: {proc.program:<14} {proc.state:<8} line {proc.current_line()}"
                for p, proc in sorted(self.basic.items()) if proc.state != "stopped"]
        return rows or ["No processes running"]

    def stop_process(self, p: int) -> dict[str, Any]:
        n = self.process_number(p)
        if n not in self.basic:
            raise NotFound(f"process {n} has not run a program", field="process")
        self.basic[n].stop()
        return self.basic[n].describe()

    # -- variables ---------------------------------------------------------------------------

    def _variable(self, name: str) -> tuple[str, int]:
        m = _VARIABLE.match(name)
        if not m:
            raise NotFound(
                f"no Trio variable {name!r} (VR(n), TABLE(n), IN(n) or OP(n))", field="name"
            )
        kind, index = m.group(1).upper(), int(m.group(2))
        size = {"VR": self.vr_count, "TABLE": self.table_size}.get(kind, CHANNELS)
        if index >= size:
            raise NotFound(f"{kind}({index}) is out of range 0..{size - 1}", field="name")
        return kind, index

    def get_variable(self, name: str) -> float:
        """VR(n), TABLE(n); IN(n) / OP(n): digital input / output n (1 = ON, 0 = OFF)."""
        kind, index = self._variable(name)
        if kind == "IN":
            return float(self.io.inputs[index])
        if kind == "OP":
            return float(self.io.outputs[index])
        return self.vr[index] if kind == "VR" else self.table.get(index, 0.0)

    def set_variable(self, name: str, value: float) -> None:
        kind, index = self._variable(name)
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise InvalidValue(f"{name} needs a number, got {value!r}", field="value") from None
        if kind in ("VR", "TABLE") and out_of_word(v, self.model):
            raise InvalidValue(f"{name} = {v:g} is beyond what the {self.model.word_bits}-bit "
                               f"number format of model {self.model.name} holds "
                               f"(±{WORD_MAX[self.model.word_bits]:g})", field="value")
        if kind == "VR":
            self.vr[index] = v
        elif kind == "TABLE":
            self.table[index] = v
        elif kind == "IN":  # an input driven by the outside world: ON when non-zero
            self.io.set_input(index, v)
        else:  # OP(n) as the BASIC OP(n, v) does it (an ``output`` event when it changes)
            self.io.op(index, v)


__all__ = ["TrioController"]
