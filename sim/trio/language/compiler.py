"""Compile parsed Trio BASIC into a flat list of operations with resolved jump targets.

The controller compiles a program before it runs: comments stripped, expressions turned to
reverse Polish, loop-structure destinations embedded (spec §2.1, TJ1P-31). Here each
statement becomes one closure ``op(ctx)`` returning what the driver does next:

* ``None`` — go on with the next operation;
* an ``int`` — jump there;
* a :class:`Block` — the move could not be buffered: wait at this line for the process buffer;
* :class:`WaitFor` / :class:`Poll` / :class:`Sleep` — ``WAIT IDLE`` / ``WAIT LOADED``,
  ``WAIT UNTIL``, ``WA(ms)``;
* :data:`HALT` — ``STOP``: the program ends.

MC4 declarations (INCLUDE, DIM, GLOBAL, CONSTANT) and typed assignment targets are compiled by
:mod:`motionsim.sim.trio.language.declarations`, ``ON ... GOSUB/GOTO`` and ``ON BASICERROR`` by
:mod:`motionsim.sim.trio.language.branches`; names resolve against a
:mod:`motionsim.sim.trio.language.scope`.

Structure errors (NEXT without FOR, IF without ENDIF, unknown label ...) are
:class:`motionsim.sim.errors.ParseError` with the line and column of the statement at fault, raised
before anything runs. ``costs[pc]`` is 1 for a statement the interpreter executes and 0 for
the jumps structure adds (an ELSE reached at the end of the THEN branch).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from ...errors import ParseError
from ..card.basic_errors import GOSUB_DEPTH, RETURN_WITHOUT_GOSUB, BasicError
from . import statements as s
from .branches import GOSUB_LIMIT, Branches
from .declarations import Declarations, Resolver
from .expressions import ALWAYS_NUM, compile_expr, kind_of
from .functions import FunctionDef, Functions, Library, call_site
from .names import LABEL_CHARS
from .scope import Decl, ExprError, Scope
from .structure import Structure

Op = Callable[[Any], Any]


class Block:
    """A move line whose process buffer is full: wait there until the move is buffered."""

    __slots__ = ("move",)

    def __init__(self, move: Any) -> None:
        self.move = move


class WaitFor:
    """Wait until ``predicate()`` holds after a change of the move buffers."""

    __slots__ = ("predicate",)

    def __init__(self, predicate: Callable[[], bool]) -> None:
        self.predicate = predicate


class Poll:
    """Wait until ``predicate()`` holds, re-tested once per servo period."""

    __slots__ = ("predicate",)

    def __init__(self, predicate: Callable[[], bool]) -> None:
        self.predicate = predicate


class Sleep:
    __slots__ = ("seconds",)

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds


HALT = object()


@dataclass(slots=True)
class Code:
    """A compiled program: operations, their source lines and costs, labels."""

    ops: list[Op]
    lines: list[int]
    costs: list[int]
    texts: tuple[str, ...]
    labels: dict[str, int]
    includes: tuple[str, ...] = ()  # programs INCLUDEd (and libraries called), in order
    shared_version: int = 0  # the controller's GLOBAL / CONSTANT table it was compiled with
    library: Library | None = None  # a BASIC library's functions (then there are no ops)

    def text(self, pc: int) -> str:
        ln = self.lines[pc]
        return self.texts[ln - 1].strip() if 0 < ln <= len(self.texts) else ""


class _Compiler(Declarations, Branches, Structure, Functions):
    def __init__(
        self,
        program: s.Program,
        name: str = "",
        resolve: Resolver | None = None,
        shared: Mapping[str, Decl] | None = None,
        functions: Mapping[str, FunctionDef] | None = None,
        function: FunctionDef | None = None,
        errors: list[ParseError] | None = None,
    ) -> None:
        self.program = program
        #: Collect the errors and go on past them (the check tool) instead of raising the first.
        self.errors = errors
        self.compilers = program.dialect.compilers
        self.name = name
        self.resolve = resolve
        self.shared = shared
        self.function = function  # the FUNCTION whose body this compiles (a library's)
        self.scope = Scope(shared, functions)
        if function is not None:  # the parameters: the function's own typed locals
            self.scope.names.update(function.params)
        self.ops: list[Op] = []
        self.lines: list[int] = []
        self.costs: list[int] = []
        self.labels: dict[str, int] = {}
        # (pc, labels, stmt, build(targets) -> op) for GOTO / GOSUB / ON ... / ON BASICERROR
        self.patches: list[tuple[int, tuple[str, ...], s.Stmt, Callable[[list[int]], Op]]] = []
        self.blocks: list[tuple[str, s.Stmt, dict[str, Any]]] = []
        self.includes: list[str] = []
        self.source: tuple[str, tuple[str, ...]] = (name, program.lines)  # INCLUDE switches it
        self.line_override: int | None = None  # the INCLUDE line, while its program compiles
        self.context = ""  # 'in "X" (INCLUDEd at line n): ' while an INCLUDEd program compiles
        #: The operations holding library function calls: an op is built (emitted or set)
        #: right after the expressions it evaluates are compiled, so the op built first after
        #: a call was compiled holds it; each is wrapped by ``call_site`` (functions.py).
        self.call_sites: set[int] = set()
        self._calls_seen = 0

    def error(self, st: s.Stmt, message: str) -> ParseError:
        name, lines = self.source
        text = lines[st.line - 1] if 0 < st.line <= len(lines) else None
        return ParseError(self.context + message, line=st.line, column=st.column, text=text,
                          program=name or None)

    def emit(self, op: Op, st: s.Stmt, cost: int = 1) -> int:
        if self.scope.calls != self._calls_seen:  # op holds the library calls just compiled
            self._calls_seen = self.scope.calls
            self.call_sites.add(len(self.ops))
        self.ops.append(op)
        if self.line_override is None:
            self.lines.append(st.line)
            self.costs.append(cost)
        else:  # an INCLUDEd definition: compiled in, at the INCLUDE line, costing nothing
            self.lines.append(self.line_override)
            self.costs.append(0)
        return len(self.ops) - 1

    def num(self, e: s.Expr) -> Callable[[Any], Any]:
        """A numeric expression compiled against this program's names (a string: an error)."""
        if e.__class__ not in ALWAYS_NUM and kind_of(e, self.scope) == "str":
            raise ExprError("type mismatch: a number is needed here, not a string")
        return compile_expr(e, self.scope)

    def placeholder(self, st: s.Stmt, cost: int = 1) -> int:
        return self.emit(_unpatched, st, cost)

    def set_op(self, pc: int, op: Op) -> None:
        if self.scope.calls != self._calls_seen:
            self._calls_seen = self.scope.calls
            self.call_sites.add(pc)
        self.ops[pc] = op

    # -- driving ---------------------------------------------------------------------------

    def report(self, err: ParseError) -> None:
        """A compile error: raised, or (collecting) kept and the compile goes on."""
        if self.errors is None:
            raise err
        self.errors.append(err)

    def run(self) -> Code:
        statements = self.program.statements
        if self.function is None and any(isinstance(st, s.Function) for st in statements):
            try:
                library = self.compile_library()
            except ParseError as err:  # a library's layout error: no further recovery
                self.report(err)
                library = None
            return Code([], [], [], self.program.lines, {}, tuple(self.includes),
                        library=library)
        for st in statements:
            self.statement(st)
        closers = {"FOR": "NEXT", "IF": "ENDIF", "WHILE": "WEND", "REPEAT": "UNTIL",
                   "SELECT": "END_CASE"}
        for kind, st, _ in reversed(self.blocks):  # the innermost first, as raised
            self.report(self.error(st, f"{'SELECT_CASE' if kind == 'SELECT' else kind} "
                                       f"without {closers[kind]}"))
        for pc, labels, st, build in self.patches:
            missing = [label for label in labels if label not in self.labels]
            if missing:
                self.report(self.error(st, f"label {missing[0]!r} is not defined"))
                continue
            self.set_op(pc, build([self.labels[label] for label in labels]))
        for pc in self.call_sites:
            self.ops[pc] = call_site(self.ops[pc])
        self.includes.extend(sorted(self.scope.used - {self.name, *self.includes}))
        return Code(self.ops, self.lines, self.costs, self.program.lines, self.labels,
                    tuple(self.includes))

    def statement(self, st: s.Stmt) -> None:
        """Emit one statement's operations: the compile function its row in the program's
        statement table names (:mod:`motionsim.sim.trio.language.commands`)."""
        try:
            compile_fn = self.compilers[type(st)]
            blocks = self.blocks
            if blocks and blocks[-1][0] == "SELECT":
                self.before_in_select(st)
            if self.function is not None:
                self.refuse_in_library(st)
            try:
                compile_fn(self, st)
            except ExprError as exc:
                raise self.error(st, str(exc)) from None
        except ParseError as err:
            self.report(err)

    # -- simple statements -----------------------------------------------------------------

    def st_Assign(self, st: s.Assign) -> None:
        value = self.value_for(st.target, st.value)
        write = self.writer(st.target)
        tgt = st.target
        if isinstance(tgt, s.Local) and write is None:  # an untyped local: the common case
            name = tgt.name

            def op(c: Any) -> None:
                c.set_local(name, value(c))

        elif write is not None:

            def op(c: Any) -> None:
                write(c, value(c))

        elif isinstance(tgt, s.VrRef):
            idx = compile_expr(tgt.index, self.scope)

            def op(c: Any) -> None:
                c.set_vr(idx(c), value(c))

        elif isinstance(tgt, s.TableRef):
            idx = compile_expr(tgt.index, self.scope)

            def op(c: Any) -> None:
                c.set_table(idx(c), value(c))

        else:
            assert isinstance(tgt, s.Param)
            pname = tgt.name
            axis = compile_expr(tgt.axis, self.scope) if tgt.axis is not None else None

            def op(c: Any) -> None:
                c.set_param(pname, axis(c) if axis is not None else None, value(c))

        self.emit(op, st)

    def st_TableWrite(self, st: s.TableWrite) -> None:
        start = self.num(st.start)
        values = [self.num(v) for v in st.values]

        def op(c: Any) -> None:
            base = start(c)
            for i, v in enumerate(values):
                c.set_table(base + i, v(c))

        self.emit(op, st)

    def st_Base(self, st: s.Base) -> None:
        axes = [self.num(a) for a in st.axes]
        self.emit(lambda c: c.set_base([a(c) for a in axes]), st)

    def st_MoveCmd(self, st: s.MoveCmd) -> None:
        kind = st.kind
        args = [self.num(a) for a in st.args]
        axis = self.num(st.axis) if st.axis is not None else None
        lines = self.program.lines
        text = lines[st.line - 1].strip() if 0 < st.line <= len(lines) else kind
        if (len(args) == 1 and axis is not None and st.args[0].__class__ is s.Num
                and st.axis.__class__ is s.Num):
            # MOVE(1) AXIS(0): the literals' readers read once (a literal's reader only
            # returns its value)
            values, at = (args[0](None),), axis(None)

            def op(c: Any) -> Any:
                return c.issue(kind, values, at, text)

        elif len(args) == 1 and axis is not None:
            (a0,) = args

            def op(c: Any) -> Any:
                return c.issue(kind, (a0(c),), axis(c), text)

        else:

            def op(c: Any) -> Any:
                return c.issue(
                    kind, tuple(a(c) for a in args), axis(c) if axis is not None else None, text
                )

        self.emit(op, st)

    def st_SetupCmd(self, st: s.SetupCmd) -> None:
        name = st.name
        args = [compile_expr(a) for a in st.args]
        axis = compile_expr(st.axis) if st.axis is not None else None
        self.emit(lambda c: c.setup_command(
            name, tuple(a(c) for a in args), axis(c) if axis is not None else None), st)

    def st_ScopeCmd(self, st: s.ScopeCmd) -> None:
        """SCOPE: the parameters stay compiled readers, sampled by the scope
        (:mod:`motionsim.sim.trio.run.scope`) with the context of the process that ran it."""
        args = [self.num(a) for a in st.args]
        readers, names = args[4:], tuple(_param_name(a, i) for i, a in enumerate(st.args[4:]))

        def op(c: Any) -> None:
            period = args[1](c) if len(args) > 1 else None
            table = (args[2](c), args[3](c)) if len(args) > 2 else None
            c.ctrl.scope.set(c, args[0](c), period, table, readers, names)

        self.emit(op, st)

    def st_BusCall(self, st: s.BusCall) -> None:
        name = st.name
        args = [self.num(a) for a in st.args]

        def op(c: Any) -> None:
            c.bus_call(name, tuple(a(c) for a in args), True)

        self.emit(op, st)

    def st_OpWrite(self, st: s.OpWrite) -> None:
        args = [self.num(a) for a in st.args]
        self.emit(lambda c: c.op_write([a(c) for a in args]), st)

    def st_Cancel(self, st: s.Cancel) -> None:
        mode = self.num(st.mode) if st.mode is not None else None
        axis = self.num(st.axis) if st.axis is not None else None
        self.emit(
            lambda c: c.cancel(
                mode(c) if mode is not None else 0.0, axis(c) if axis is not None else None
            ),
            st,
        )

    def st_RapidStop(self, st: s.RapidStop) -> None:
        mode = self.num(st.mode) if st.mode is not None else None
        self.emit(lambda c: c.rapidstop(mode(c) if mode is not None else 0.0), st)

    def st_Print(self, st: s.Print) -> None:
        parts: list[tuple[Callable[[Any], str], str]] = []
        formats = st.formats or (None,) * len(st.items)
        for (e, sep), fmt in zip(st.items, formats, strict=True):
            if isinstance(e, s.Str):
                txt = e.value
                parts.append((lambda c, txt=txt: txt, sep))
            elif isinstance(e, s.Hex):
                f = self.num(e.value)
                parts.append((lambda c, f=f: c.hex(f(c)), sep))
            elif kind_of(e, self.scope) == "str":
                f = compile_expr(e, self.scope)
                parts.append((f, sep))
            else:
                f = compile_expr(e, self.scope)
                w, d = fmt if fmt is not None else (0, 4)
                parts.append((lambda c, f=f, w=w, d=d: c.number(f(c), d, w), sep))
        newline = not st.items or st.items[-1][1] != ";"
        channel = self.num(st.channel) if st.channel is not None else None

        def op(c: Any) -> None:
            out = []
            for fn, sep in parts:
                out.append(fn(c))
                if sep == ",":
                    out.append("\t")
            c.output("".join(out), newline, channel(c) if channel is not None else None)

        self.emit(op, st)

    def st_DefPos(self, st: s.DefPos) -> None:
        values = [self.num(v) for v in st.values]
        axis = self.num(st.axis) if st.axis is not None else None
        self.emit(
            lambda c: c.defpos([v(c) for v in values], axis(c) if axis is not None else None), st
        )

    def st_Halt(self, st: s.Halt) -> None:
        self.emit(lambda c: c.halt(), st)

    def st_ProcessList(self, st: s.ProcessList) -> None:
        self.emit(lambda c: c.process_list(), st)

    def st_Stop(self, st: s.Stop) -> None:
        if st.program is None:
            self.emit(lambda c: HALT, st)
        else:
            name = st.program
            self.emit(lambda c: c.stop_program(name), st)

    def st_Run(self, st: s.Run) -> None:
        name = st.program
        proc = self.num(st.process) if st.process is not None else None
        self.emit(lambda c: c.run_program(name, proc(c) if proc is not None else None), st)

    def st_Wa(self, st: s.Wa) -> None:
        ms = self.num(st.ms)
        self.emit(lambda c: Sleep(max(0.0, ms(c)) / 1000.0), st)

    def st_WaitIdle(self, st: s.WaitIdle) -> None:
        axis = self.num(st.axis) if st.axis is not None else None
        self.emit(lambda c: c.wait_axis("IDLE", axis(c) if axis is not None else None), st)

    def st_WaitLoaded(self, st: s.WaitLoaded) -> None:
        axis = self.num(st.axis) if st.axis is not None else None
        self.emit(lambda c: c.wait_axis("LOADED", axis(c) if axis is not None else None), st)

    def st_WaitUntil(self, st: s.WaitUntil) -> None:
        cond = self.num(st.cond)

        def op(c: Any) -> Any:
            if cond(c) != 0.0:
                return None
            return Poll(lambda: cond(c) != 0.0)

        self.emit(op, st)

    # -- flow ------------------------------------------------------------------------------

    def st_Label(self, st: s.Label) -> None:
        if st.name in self.labels:
            why = (f" (only the first {LABEL_CHARS} characters of a label are significant)"
                   if len(st.name) == LABEL_CHARS else "")
            raise self.error(st, f"label {st.name!r} is defined twice{why}")
        self.labels[st.name] = len(self.ops)

    def st_Goto(self, st: s.Goto) -> None:
        self.patches.append((self.placeholder(st), (st.label,), st, lambda t: _jump(t[0])))

    def st_Gosub(self, st: s.Gosub) -> None:
        pc = self.placeholder(st)
        self.patches.append((pc, (st.label,), st, lambda t: _gosub(t[0], pc + 1)))

    def st_Return(self, st: s.Return) -> None:
        if self.return_value(st):
            return

        def op(c: Any) -> int:
            if not c.gosub_stack:
                raise BasicError(RETURN_WITHOUT_GOSUB)
            return c.gosub_stack.pop()

        self.emit(op, st)

    def st_For(self, st: s.For) -> None:
        pc = self.placeholder(st)
        self.blocks.append(("FOR", st, {"pc": pc}))

    def st_Next(self, st: s.Next) -> None:
        if not self.blocks or self.blocks[-1][0] != "FOR":
            raise self.error(st, "NEXT without FOR")
        _, fst, info = self.blocks.pop()
        assert isinstance(fst, s.For)
        if st.var is not None and st.var != fst.var:
            raise self.error(st, f"NEXT {st.var} does not match FOR {fst.var}")
        var = fst.var
        decl = self.scope.plain(var)
        if decl is not None and (decl.kind != "DIM" or decl.is_str or decl.size is not None):
            raise self.error(fst, f"FOR {var}: the loop variable must be a numeric local")
        scope = self.scope
        start, end = compile_expr(fst.start, scope), compile_expr(fst.end, scope)
        step = compile_expr(fst.step, scope) if fst.step is not None else None
        for_pc = info["pc"]
        body = for_pc + 1
        next_pc = len(self.ops)
        after = next_pc + 1

        def op_for(c: Any) -> int | None:
            v0, v1 = start(c), end(c)
            inc = step(c) if step is not None else 1.0
            c.locals[var] = v0
            c.loops[for_pc] = (v1, inc)
            if (inc >= 0 and v0 > v1) or (inc < 0 and v0 < v1):
                return after
            return None

        def op_next(c: Any) -> int | None:
            v1, inc = c.loops[for_pc]
            v = c.locals.get(var, 0.0) + inc
            c.locals[var] = v
            if (inc >= 0 and v <= v1) or (inc < 0 and v >= v1):
                return body
            return None

        self.set_op(for_pc, op_for)
        self.emit(op_next, st)
        self.close_exits(info, after)

    def st_If(self, st: s.If) -> None:
        cond = self.num(st.cond)
        test = self.placeholder(st)
        for sub in st.then:
            self.statement(sub)
        if st.orelse:
            skip = self.placeholder(st, cost=0)
            else_pc = len(self.ops)
            for sub in st.orelse:
                self.statement(sub)
            self.set_op(skip, _jump(len(self.ops)))
        else:
            else_pc = len(self.ops)
        self.set_op(test, _branch(cond, else_pc))

    def st_IfBlock(self, st: s.IfBlock) -> None:
        test = self.placeholder(st)
        self.blocks.append(("IF", st, {"test": test, "cond": st.cond, "ends": [], "else": False}))

    def _if_info(self, st: s.Stmt, word: str) -> dict[str, Any]:
        if not self.blocks or self.blocks[-1][0] != "IF":
            raise self.error(st, f"{word} without IF")
        info = self.blocks[-1][2]
        if info["else"]:
            raise self.error(st, f"{word} after ELSE")
        return info

    def _close_branch(self, st: s.Stmt, info: dict[str, Any]) -> None:
        info["ends"].append(self.placeholder(st, cost=0))
        if info["test"] is not None:
            self.set_op(info["test"], _branch(self.num(info["cond"]), len(self.ops)))
            info["test"] = None

    def st_ElseIf(self, st: s.ElseIf) -> None:
        info = self._if_info(st, "ELSEIF")
        self._close_branch(st, info)
        info["test"] = self.placeholder(st)
        info["cond"] = st.cond

    def st_Else(self, st: s.Else) -> None:
        info = self._if_info(st, "ELSE")
        self._close_branch(st, info)
        info["else"] = True

    def st_EndIf(self, st: s.EndIf) -> None:
        if not self.blocks or self.blocks[-1][0] != "IF":
            raise self.error(st, "ENDIF without IF")
        _, _, info = self.blocks.pop()
        end = len(self.ops)
        if info["test"] is not None:
            self.set_op(info["test"], _branch(self.num(info["cond"]), end))
        for pc in info["ends"]:
            self.set_op(pc, _jump(end))

    def st_While(self, st: s.While) -> None:
        pc = self.placeholder(st)
        self.blocks.append(("WHILE", st, {"pc": pc}))

    def st_Wend(self, st: s.Wend) -> None:
        if not self.blocks or self.blocks[-1][0] != "WHILE":
            raise self.error(st, "WEND without WHILE")
        _, wst, info = self.blocks.pop()
        assert isinstance(wst, s.While)
        self.emit(_jump(info["pc"]), st)
        self.set_op(info["pc"], _branch(self.num(wst.cond), len(self.ops)))
        self.close_exits(info, len(self.ops))

    def st_Repeat(self, st: s.Repeat) -> None:
        self.blocks.append(("REPEAT", st, {"pc": len(self.ops)}))

    def st_Until(self, st: s.Until) -> None:
        if not self.blocks or self.blocks[-1][0] != "REPEAT":
            raise self.error(st, "UNTIL without REPEAT")
        _, _, info = self.blocks.pop()
        self.emit(_branch(self.num(st.cond), info["pc"]), st)
        self.close_exits(info, len(self.ops))


def _unpatched(c: Any) -> None:  # pragma: no cover - replaced before any program runs
    raise AssertionError("jump target not patched")


def _jump(target: int) -> Op:
    return lambda c: target


def _branch(cond: Callable[[Any], float], if_false: int) -> Op:
    """Go on when ``cond`` is TRUE (non-zero), else jump to ``if_false``."""
    return lambda c: None if cond(c) != 0.0 else if_false


def _gosub(target: int, ret: int) -> Op:
    def op(c: Any) -> int:
        if len(c.gosub_stack) >= GOSUB_LIMIT:
            raise BasicError(GOSUB_DEPTH)
        c.gosub_stack.append(ret)
        return target

    return op


def compile_program(
    program: s.Program,
    name: str = "",
    resolve: Resolver | None = None,
    shared: Mapping[str, Decl] | None = None,
    shared_version: int = 0,
    functions: Mapping[str, FunctionDef] | None = None,
    errors: list[ParseError] | None = None,
) -> Code:
    """Compile a parsed program; structure errors raise :class:`ParseError` (with ``program``
    = ``name`` or the INCLUDEd program at fault). ``resolve`` finds the parsed program an
    ``INCLUDE`` names (None: INCLUDE is refused, as at the command line); ``shared`` holds the
    controller's GLOBAL / CONSTANT names (:mod:`motionsim.sim.trio.language.scope`),
    ``functions`` the functions of its stored BASIC libraries (:mod:`.functions`); a program of
    FUNCTION blocks compiles to a library (``Code.library``). With ``errors`` (a list) every
    compile error it can go on past is appended there instead of raised: the code returned
    is then only good for its messages (the check tool), never for running."""
    code = _Compiler(program, name, resolve, shared, functions, errors=errors).run()
    code.shared_version = shared_version
    return code


__all__ = ["HALT", "Block", "Code", "Poll", "Sleep", "WaitFor", "compile_program"]


def _param_name(e: s.Expr, i: int) -> str:
    """A SCOPE parameter's column name: ``MPOS AXIS(5)``, ``VR(3)``, else ``p{i}``."""
    if isinstance(e, s.Param):
        if e.axis is None:
            return e.name
        if isinstance(e.axis, s.Num):
            return f"{e.name} AXIS({e.axis.value:g})"
    if isinstance(e, s.VrRef) and isinstance(e.index, s.Num):
        return f"VR({e.index.value:g})"
    return f"p{i}"
