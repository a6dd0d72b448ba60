"""What a running statement sees: one process' variables and the controller behind them.

Each BASIC process (and the command line, process 0) has its own named locals, its own BASE
axis group and its own FOR / GOSUB bookkeeping; VR(), TABLE(), the axes and the move buffers
are the controller's and shared by all processes (spec §2.2, §9.3).

Indices are truncated to integers. Out-of-range VR / TABLE / axis numbers raise a
:class:`~motionsim.sim.trio.card.basic_errors.BasicError`, which stops the process that hit it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ...errors import InvalidValue
from ..card import basic_errors as msg
from ..card import fieldbus
from ..card.axis_status import computed
from ..card.basic_errors import BasicError
from ..card.data_memory import DATA_BYTES, dim_bytes, out_of_memory
from ..card.models import EDGES_MAX, WORD_MAX, format_number, hex_text, out_of_word
from ..card.parameters import (
    AXIS_COMPUTED,
    AXIS_PARAMS,
    AXIS_STORED,
    SYSTEM_PARAMS,
)
from ..language.compiler import HALT, Block, Poll, Sleep, WaitFor
from ..language.functions import (
    CALL_DEPTH,
    CALL_STEPS,
    FnReturn,
    Frame,
    FunctionDef,
    Suspend,
    in_function,
)
from ..language.scope import Decl, coerce
from ..motion.issue import new_move
from ..motion.linked import LINKED, LinkedMove, check_linked, link_axis_of
from ..motion.moves import Move
from ..motion.mtypes import axes_driven

if TYPE_CHECKING:
    from ..controller import TrioController

class _NoLocals(dict):
    """The command line has no local variables (TJ1P-26): reading one is an error."""

    def get(self, key: Any, default: Any = None) -> Any:
        raise BasicError(msg.LOCALS_AT_COMMAND_LINE + f": {key}")


class Context:
    """Runtime state of one process, and the operations statements call."""

    def __init__(
        self,
        ctrl: TrioController,
        process: int,
        output: Callable[[str, bool, float | None], None],
        *,
        command_line: bool = False,
    ) -> None:
        self.ctrl = ctrl
        self.process = process
        self.output = output
        self.command_line = command_line
        self.locals: dict[str, float] = _NoLocals() if command_line else {}
        self.loops: dict[int, tuple[float, float]] = {}
        #: SELECT_CASE values being compared, by the SELECT_CASE's operation (structure.py).
        self.selected: dict[int, Any] = {}
        #: Library function calls in progress (functions.py): their depth, and the frame of
        #: the innermost (this process' own statements' at depth 0; a process sets
        #: ``frame.can_wait``: the command line cannot wait inside a statement).
        self.calls = 0
        self.frame = Frame()
        #: Bytes of program data memory each DIMmed name of this process holds.
        self.data_bytes: dict[str, int] = {}
        self.gosub_stack: list[int] = []
        self.base: list[int] = list(range(len(ctrl.axes)))
        self.outdevice = 0  # OUTDEVICE: the channel PRINT writes to (M206-320)
        # ON BASICERROR: the handler's pc (None: no trap), whether it is running, and the
        # process parameters RUN_ERROR / ERROR_LINE (spec §11.3)
        self.trap: int | None = None
        self.in_handler = False
        self.run_error = 0
        self.error_line = 0
        # TICKS: the value written and the servo period it was written in (constants.py)
        self._ticks = 0.0
        self._ticks_at = ctrl.clock.index(ctrl.env.now)

    # -- variables -------------------------------------------------------------------------

    def set_local(self, name: str, value: float) -> None:
        if self.command_line and not self.calls:
            raise BasicError(msg.LOCALS_AT_COMMAND_LINE + f": {name}")
        self.locals[name] = value

    def declare_local(self, name: str, decl: Decl) -> None:
        """DIM: the local (or array) at its initial value, its bytes reserved in the
        controller's program data memory first (sim.trio.data_memory)."""
        if self.command_line and not self.calls:
            raise BasicError(msg.LOCALS_AT_COMMAND_LINE + f": {name}")
        self._reserve(name, decl)
        initial = decl.initial()
        self.locals[name] = initial if decl.size is None else [initial] * decl.size

    def _reserve(self, name: str, decl: Decl) -> None:
        need = dim_bytes(decl.type, decl.size, decl.length)
        free = DATA_BYTES - self.ctrl.data_bytes_in_use() + self.data_bytes.get(name, 0)
        if need > free:
            raise BasicError(out_of_memory(name, need, free))
        self.data_bytes[name] = need

    def _array(self, name: str, decl: Decl) -> list[Any]:
        arr = self.locals.get(name)
        if not isinstance(arr, list):  # its DIM line was jumped over: declared on first use
            self._reserve(name, decl)
            arr = self.locals[name] = [decl.initial()] * (decl.size or 0)
        return arr

    def _element_index(self, name: str, decl: Decl, i: Any) -> int:
        """The element ``i`` (``(i, j)`` of a two-dimensional array) names, each index from 0
        and below its dimension's size; beyond, a run-time error naming the element."""
        if decl.dims and len(decl.dims) > 1:
            flat = 0
            for k, size in zip(i, decl.dims, strict=True):
                n = int(k)
                if not 0 <= n < size:
                    shown = ", ".join(f"{v:g}" for v in i)
                    raise BasicError(msg.ARRAY_RANGE.format(name=name, index=shown))
                flat = flat * size + n
            return flat
        n = int(i)
        if not 0 <= n < (decl.size or 0):
            raise BasicError(msg.ARRAY_RANGE.format(name=name, index=f"{i:g}"))
        return n

    def element(self, name: str, decl: Decl, i: float) -> Any:
        return self._array(name, decl)[self._element_index(name, decl, i)]

    def set_element(self, name: str, decl: Decl, i: float, value: Any) -> None:
        self._array(name, decl)[self._element_index(name, decl, i)] = value

    def declare(self, name: str, decl: Decl) -> None:
        """GLOBAL / CONSTANT ran: the name is known to every program compiled from now on."""
        if decl.kind == "GLOBAL":
            self._vr_index(decl.index)
        self.ctrl.declare(name, decl)

    def set_trap(self, target: int) -> None:
        """ON BASICERROR GOTO: arm this process' error handler — again, too, from inside the
        handler (a program that restarts itself after an error, ``[INF]``)."""
        if self.command_line:
            raise BasicError(msg.TRAP_AT_COMMAND_LINE)
        self.trap = target
        self.in_handler = False

    def enter_handler(self, number: int, line: int) -> int | None:
        """A run-time error (or a STOP) at ``line``: the handler's pc when one is armed and
        not already running (an error inside the handler stops the process), else None.
        RUN_ERROR / ERROR_LINE are set either way and the GOSUB stack is cleared."""
        self.run_error, self.error_line = number, line
        if self.trap is None or self.in_handler:
            return None
        self.in_handler = True
        self.gosub_stack.clear()
        return self.trap

    def _vr_index(self, i: float) -> int:
        n = int(i)
        if not 0 <= n < len(self.ctrl.vr):
            raise BasicError(msg.VR_RANGE.format(index=f"{i:g}"))
        return n

    def vr(self, i: float) -> float:
        return self.ctrl.vr[self._vr_index(i)]

    def set_vr(self, i: float, value: float) -> None:
        n = self._vr_index(i)
        self._check_word(f"VR({n})", value)
        self.ctrl.vr[n] = value

    def _check_word(self, what: str, value: float) -> None:
        """A store the model's number format cannot hold is a run-time error (sim.trio.models:
        ``VR(2)=1e300*1e300`` is not kept as inf)."""
        m = self.ctrl.model
        if out_of_word(value, m):
            raise BasicError(msg.OUT_OF_WORD.format(what=what, value=value, bits=m.word_bits,
                                                    limit=WORD_MAX[m.word_bits]))

    def _table_index(self, i: float) -> int:
        n = int(i)
        if not 0 <= n < self.ctrl.table_size:
            raise BasicError(msg.TABLE_RANGE.format(index=f"{i:g}"))
        return n

    def table(self, i: float) -> float:
        return self.ctrl.table.get(self._table_index(i), 0.0)

    def set_table(self, i: float, value: float) -> None:
        n = self._table_index(i)
        self._check_word(f"TABLE({n})", value)
        self.ctrl.table[n] = value

    def bus_call(self, name: str, args: tuple[float, ...], alone: bool) -> float:
        """A system / fieldbus function (``alone``: as a statement; card/fieldbus.py)."""
        return fieldbus.call(self, name, args, alone)

    # -- library functions -------------------------------------------------------------------

    def call_function(self, fn: FunctionDef, args: tuple[Any, ...]) -> Any:
        """Run library function ``fn`` to its RETURN inside the calling statement
        (:mod:`motionsim.sim.trio.language.functions`): its parameters and names are locals
        of its own, the caller's are put back afterwards, whatever happens. A statement of it
        that waits raises :class:`~.functions.Suspend` when the calling process can wait
        there (its frame kept for the statement's second run, which goes on with it), else
        it is a run-time error."""
        fr = self.frame
        resume = None
        if fr.active:  # a call of a call-site statement: numbered, perhaps already returned
            k = fr.next_call
            fr.next_call = k + 1
            if k < len(fr.memo):
                return fr.memo[k]
            resume, fr.resume = fr.resume, None
        if self.calls >= CALL_DEPTH:
            raise BasicError(f"Stack overflow: FUNCTION calls nested deeper than {CALL_DEPTH} "
                             f"({fn.name})")
        code = fn.code
        saved = (self.locals, self.loops, self.selected, dict(self.data_bytes))
        if resume is not None and resume.fn is fn and resume.state is not None:
            callee = resume  # the call that waited: on from where it was
            self.locals, self.loops, self.selected, self.data_bytes = resume.state
            resume.state = None
            pc, steps = resume.pc, resume.steps
            if resume.waited:
                pc += 1  # its own statement waited: the wait is over
            else:
                resume.replaying = True  # a call inside that statement waited: run it again
        else:
            callee = Frame(fn, fr.active and fr.can_wait)
            own: dict[str, Any] = {name: coerce(decl, v)
                                   for (name, decl), v in zip(fn.params, args, strict=True)}
            self.locals = own
            self.loops, self.selected = {}, {}
            pc, steps = 0, 0
        self.frame = callee
        self.calls += 1
        ops = code.ops
        try:
            while True:
                if pc >= len(ops):
                    value = fn.default()
                    break
                steps += 1
                if steps > CALL_STEPS:
                    raise BasicError(f"FUNCTION {fn.name} ran {CALL_STEPS} statements without "
                                     "returning")
                r = ops[pc](self)
                if r is None:
                    pc += 1
                elif r.__class__ is int:
                    pc = r
                elif r.__class__ is FnReturn:
                    value = r.value
                    break
                elif callee.can_wait:
                    raise Suspend(r, code.text(pc))
                else:
                    raise BasicError(f"{_waits(r)} inside a FUNCTION would wait: waiting in a "
                                     "library function is not simulated here (at the command "
                                     "line, or in a condition tested while waiting)")
        except Suspend as sus:
            callee.pc, callee.steps = pc, steps
            callee.waited = sus.state is None  # the first level it reaches: its own wait
            callee.state = (self.locals, self.loops, self.selected, self.data_bytes)
            if sus.state is None:
                line = code.lines[pc] if pc < len(code.lines) else fn.line
                sus.state = (*callee.state, self.calls, callee)
                sus.where = fn.where(line)
            fr.resume = callee
            raise
        except BasicError as exc:
            line = code.lines[pc] if pc < len(code.lines) else fn.line
            err = in_function(exc, fn.where(line))
            if err is exc:
                raise
            raise err from None
        finally:
            self.calls -= 1
            self.frame = fr
            self.locals, self.loops, self.selected, self.data_bytes = saved
        if fr.active:
            fr.memo.append(value)
        return value

    # -- parameters ------------------------------------------------------------------------

    def axis_number(self, a: float) -> int:
        n = int(a)
        if not 0 <= n < len(self.ctrl.axes) or n != a:
            raise BasicError(msg.AXIS_RANGE.format(axis=f"{a:g}"))
        return n

    def base_axis(self, axis: float | None) -> int:
        """``AXIS(n)`` when the statement gives one, else the first axis of the BASE group."""
        return self.base[0] if axis is None else self.axis_number(axis)

    def param(self, name: str, axis: float | None, proc: float | None) -> float:
        if name == "TICKS":
            return self.ctrl.context_of(self.proc_number(proc)).ticks()
        if name == "LAST_AXIS":
            return float(len(self.ctrl.axes) - 1)
        if name in AXIS_PARAMS:
            n = self.base_axis(axis)
            if name in AXIS_STORED:
                return self.ctrl.stored[n].read(name)
            if name in AXIS_COMPUTED:
                return self._computed(name, n)
            return self.ctrl.axes[n].read(name)
        if name in SYSTEM_PARAMS:
            return self.ctrl.system.read(name)
        if name == "PMOVE":
            return float(self.ctrl.buffers.pmove(self.proc_number(proc)))
        if name == "PROCNUMBER":
            return float(self.process)
        if name == "PROC_STATUS":
            return float(self.ctrl.proc_status(self.proc_number(proc)))
        if name == "OUTDEVICE":
            return float(self.ctrl.context_of(self.proc_number(proc)).outdevice)
        if name in ("RUN_ERROR", "ERROR_LINE"):
            return self._last_error(name, self.proc_number(proc))
        raise BasicError(f"Unknown parameter {name}")

    def _computed(self, name: str, n: int) -> float:
        return computed(name, self.ctrl.axes[n])

    def _last_error(self, name: str, p: int) -> float:
        """RUN_ERROR / ERROR_LINE PROC(p): 0 until the process meets a run-time error; then
        RUN_ERROR is its number (:mod:`motionsim.sim.trio.card.basic_errors`: 31 = stopped, else 1
        ``[INF]``) and ERROR_LINE the program line — also inside an ON BASICERROR handler. A
        new RUN of the process clears both ``[INF]``. The command line keeps no error."""
        if p == 0 or p not in self.ctrl.basic:
            return 0.0
        ctx = self.ctrl.context_of(p)
        return float(ctx.run_error if name == "RUN_ERROR" else ctx.error_line)

    def ticks(self) -> float:
        """TICKS: the value last written, less one per servo period since (constants.py)."""
        now = self.ctrl.clock.index(self.ctrl.env.now)
        return self._ticks - float(now - self._ticks_at)

    # -- digital I/O -----------------------------------------------------------------------

    def io_read(self, name: str, args: list[float]) -> float:
        """IN / READ_OP / OP / AIN as values (:mod:`motionsim.sim.trio.card.io`); ``IN`` with no
        argument reads inputs 0..23 as one number ``[BK]``."""
        io = self.ctrl.io
        if name == "IN":
            return io.read_in(*args) if args else io.read_in(0, 23)
        if name == "AIN":
            return io.ain(args[0])
        return io.read_op(args[0])

    def setup_command(self, name: str, args: tuple[float, ...], axis: float | None) -> None:
        """A set-up command (ADDAX, ENCODER_RATIO, SETCOM ...): :mod:`~motionsim.sim.trio.
        setup_commands`."""
        from ..card.setup_commands import run_command  # the motion tables' module

        run_command(self, name, args, axis)

    def op_write(self, args: list[float]) -> None:
        if len(args) == 2:
            self.ctrl.io.op(args[0], args[1])
        else:
            self.ctrl.io.op_pattern(args[0])

    def proc_number(self, proc: float | None) -> int:
        """``PROC(n)``: process n, 0 (the command line) included; none = this process."""
        if proc is None:
            return self.process
        try:
            return self.ctrl.process_number(proc, allow_zero=True)
        except InvalidValue:
            raise BasicError(msg.PROCESS_RANGE.format(process=f"{proc:g}")) from None

    def set_param(self, name: str, axis: float | None, value: float) -> None:
        if not math.isfinite(value):
            raise BasicError(msg.NOT_FINITE.format(name=name, value=value))
        if name == "TICKS":
            self._ticks = float(value)
            self._ticks_at = self.ctrl.clock.index(self.ctrl.env.now)
            return
        if name == "OUTDEVICE":
            self.outdevice = self.ctrl.channels.check(value)
            return
        if name in SYSTEM_PARAMS:  # WDOG, LIMIT_BUFFERED
            self.ctrl.system.write(name, value)
            return
        n = self.base_axis(axis)
        if name in AXIS_STORED:
            self.ctrl.stored[n].write(name, value, self.ctrl.axes[n].units)
            if name in ("FS_LIMIT", "RS_LIMIT"):
                self.ctrl.buffers.limits_changed(n)
            return
        if name == "OFFPOS":
            self.ctrl.axes[n].offset = value
            self.ctrl.buffers.offset(n)
            return
        if name == "ENDMOVE":
            self.ctrl.buffers.step_demand(n, value)
            return
        try:
            self.ctrl.axes[n].set(**{name.lower(): value})
        except InvalidValue:
            raise BasicError(msg.BAD_VALUE.format(name=name, value=f"{value:g}")) from None

    def set_base(self, axes: list[float]) -> None:
        nums = [self.axis_number(a) for a in axes]
        if len(set(nums)) != len(nums):
            raise BasicError(msg.BAD_VALUE.format(name="BASE", value=",".join(map(str, nums))))
        self.base = nums

    # -- motion ----------------------------------------------------------------------------

    def group(self, size: int, axis: float | None) -> tuple[int, ...]:
        """The axes a command drives: the BASE group (or ``AXIS(n)`` then the rest of it),
        continued in ascending axis order if the command needs more axes."""
        if size == 1:
            return (self.base[0] if axis is None else self.axis_number(axis),)  # base_axis
        if axis is None:
            axes = list(self.base)
        else:
            first = self.axis_number(axis)
            axes = [first] + [a for a in self.base if a != first]
        if len(axes) < size:
            axes += [a for a in range(len(self.ctrl.axes)) if a not in axes]
        if len(axes) < size:
            raise BasicError(msg.AXIS_RANGE.format(axis=size))
        return tuple(axes[:size])

    def _check_edges(self, kind: str, args: tuple[float, ...], axes: tuple[int, ...]) -> None:
        """A move argument beyond the axis position counter (in encoder edges: the argument
        times UNITS) is refused: ``MOVE(1e38)`` cannot be counted ``[INF]``."""
        bits = self.ctrl.model.word_bits
        limit = EDGES_MAX[bits]
        ctrl_axes = self.ctrl.axes
        units = 0.0
        for n in axes:
            u = abs(ctrl_axes[n].units)
            if u > units:
                units = u
        for a in args:
            if abs(a) * units > limit:
                raise BasicError(msg.EDGES_RANGE.format(name=kind, value=a, edges=a * units,
                                                        limit=limit, bits=bits))

    def issue(self, kind: str, args: tuple[float, ...], axis: float | None, text: str) -> Any:
        """A motion command: place it (None) or report that the process must wait (Block).
        An infinite or NaN argument is the run-time error the REST surface answers with a 422
        (nothing is buffered)."""
        for a in args:
            if not math.isfinite(a):
                raise BasicError(msg.NOT_FINITE.format(name=kind, value=a))
        if kind == "DATUM" and int(args[0]) == 0:
            self.group(1, axis)  # DATUM(0) clears axis errors; no move is buffered
            self.ctrl.system.clear_motion_error()
            return None
        size = axes_driven(kind, len(args))
        axes = self.group(size, axis)
        self._check_edges(kind, args, axes)
        move: Move
        if kind in LINKED:
            move = self._linked(kind, args, axes[0], text)
        else:
            move = new_move(self.ctrl, kind, axes, args, self.process, text)
        if self.ctrl.buffers.place(move) is None:
            return Block(move)
        return None

    def _linked(self, kind: str, args: tuple[float, ...], base: int, text: str) -> LinkedMove:
        check_linked(kind, args, base, self.ctrl.table_size)
        link = link_axis_of(kind, args)
        link_axis = self.ctrl.axes[self.axis_number(link)] if link is not None else None
        table: list[float] = []
        if kind in ("CAM", "CAMBOX"):
            lo, hi = int(args[0]), int(args[1])
            step = 1 if hi >= lo else -1
            table = [self.table(i) for i in range(lo, hi + step, step)]
        move = LinkedMove(self.ctrl.buffers.new_id(), kind, (base,), args, self.process, text)
        move.bind(link_axis, table, self.ctrl.table, self.ctrl.model.mc4)
        return move

    def defpos(self, values: list[float], axis: float | None = None) -> None:
        """DEFPOS(p1, ...): the BASE axes are declared at p1, ... at the next servo period."""
        axes = self.group(len(values), axis)
        for n, v in zip(axes, values, strict=True):
            self.ctrl.axes[n].defpos = v
            self.ctrl.buffers.offset(n)

    def cancel(self, mode: float, axis: float | None) -> None:
        n = self.base_axis(axis)
        if int(mode) == 1:
            self.ctrl.buffers.cancel_next(n)
        elif int(mode) == 2:  # MC4 template "CANCEL(2)": the buffered move too ([BK])
            self.ctrl.buffers.cancel_next(n)
            self.ctrl.buffers.cancel(n)
        else:
            self.ctrl.buffers.cancel(n)

    def rapidstop(self, mode: float = 0.0) -> None:
        if int(mode) not in (0, 2):
            raise BasicError(f"RAPIDSTOP({mode:g}) not simulated (modes 0 and 2 are)")
        self.ctrl.buffers.rapidstop(int(mode))

    # -- output ----------------------------------------------------------------------------

    def number(self, value: float, decimals: int = 4, width: int = 0) -> str:
        """PRINT of a number in the model's word (default four decimals)."""
        return format_number(value, self.ctrl.model, decimals, width)

    def hex(self, value: float) -> str:
        return hex_text(value, self.ctrl.model)

    def halt(self) -> Any:
        """HALT: every running program stops; the one that wrote it too."""
        self.ctrl.halt(except_process=self.process)
        return None if self.command_line else HALT

    def process_list(self) -> None:
        for line in self.ctrl.process_table():
            self.output(line, True, None)

    def wait_axis(self, what: str, axis: float | None) -> WaitFor | None:
        """WAIT IDLE: the axis' moves have ended — the executing one, the one in NTYPE and one
        still in a process buffer (each move transits it, TRM p. 8-130, so ``MOVE(10)`` then
        ``WAIT IDLE`` waits for that move, ``[INF]``); WAIT LOADED: nothing buffered ahead of
        the executing move (NTYPE empty, MOVELINK help text), process buffers included."""
        n = self.base_axis(axis)
        ax, buffers = self.ctrl.axes[n], self.ctrl.buffers
        if what == "IDLE":

            def pred() -> bool:
                return ax.mtype is None and ax.ntype is None and not buffers.queued_for(n)

        else:

            def pred() -> bool:
                return ax.ntype is None and not buffers.queued_for(n)

        return None if pred() else WaitFor(pred)

    # -- programs --------------------------------------------------------------------------

    def run_program(self, name: str, proc: float | None) -> None:
        try:
            self.ctrl.run_program(name, None if proc is None else int(proc))
        except Exception as exc:  # NotFound / Conflict / InvalidValue -> a BASIC error
            raise BasicError(getattr(exc, "message", str(exc))) from None

    def stop_program(self, name: str) -> Any:
        for p, proc in sorted(self.ctrl.basic.items()):
            if proc.program == name and proc.state != "stopped":
                if p == self.process:
                    return HALT
                proc.stop(trap=True)  # an armed ON BASICERROR handler sees RUN_ERROR 31
        return None


def _waits(r: Any) -> str:
    """The statement kind behind a wait an operation asked for."""
    if r is HALT:
        return "STOP"
    kinds = {Sleep: "WA", WaitFor: "WAIT IDLE / WAIT LOADED", Poll: "WAIT UNTIL",
             Block: "a move into a full process buffer"}
    return kinds.get(type(r), "a waiting statement")


__all__ = ["Context"]
