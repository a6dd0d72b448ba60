"""Compiling the MC4 declarations — INCLUDE, DIM, GLOBAL, CONSTANT — and assignments to what
they declare (typed locals, array elements, named VRs, bits of a value).

``INCLUDE "X"`` (spec §11.2, ``[BK]`` MC4 help): when the including program is compiled, the
stored program X's declarations and ``name = value`` lines are compiled into it at the INCLUDE
line — so its names are this process' own locals, set before the next line runs — at no run
time cost (they are resolved at compile time). X may hold only comments, DIM / GLOBAL /
CONSTANT and assignments to names; X must exist, may not be the including program, and may not
INCLUDE another program (no nesting, ``[BK]``). Each is a compile error naming the program, line
and column; nothing is stored. When X is stored again, the programs that include it are
compiled again (the controller refuses the new X if one of them would no longer compile).

A mixin of :class:`motionsim.sim.trio.language.compiler._Compiler`: it uses ``scope``, ``emit``,
``error``, ``statement`` and the include bookkeeping of that class.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from . import statements as s
from .expressions import compile_expr, index_of, kind_of
from .names import VARIABLE_CHARS
from .scope import Decl, ExprError, coerce, rebinding
from .strings import DEFAULT_LENGTH

#: Finds a stored program's parsed text by name (None when there is none).
Resolver = Callable[[str], "s.Program | None"]
Writer = Callable[[Any, Any], None]

#: Statements an INCLUDEd program may hold.
INCLUDABLE = (s.Dim, s.DimList, s.Global, s.Constant)


class Declarations:
    """INCLUDE / DIM / GLOBAL / CONSTANT and typed assignment targets."""

    scope: Any
    name: str
    resolve: Resolver | None
    includes: list[str]
    source: tuple[str, tuple[str, ...]]
    line_override: int | None
    context: str
    emit: Callable[..., int]
    error: Callable[..., Any]
    statement: Callable[[s.Stmt], None]

    # -- INCLUDE -----------------------------------------------------------------------------

    def st_Include(self, st: s.Include) -> None:
        name = st.program
        if self.line_override is not None:
            raise self.error(st, f'nested INCLUDE "{name}": an INCLUDEd program cannot '
                                 "INCLUDE another")
        if name == self.name:
            raise self.error(st, f'INCLUDE "{name}": a program cannot include itself')
        if self.resolve is None:
            raise self.error(st, "INCLUDE is only allowed in a stored program")
        included = self.resolve(name)
        if included is None:
            raise self.error(st, f'INCLUDE "{name}": there is no program {name}')
        saved = (self.source, self.line_override, self.context)
        self.source = (name, included.lines)
        self.line_override = st.line
        self.context = f'in "{name}" (INCLUDEd by {self.name or "this program"} line {st.line}): '
        try:
            for sub in included.statements:
                if not (isinstance(sub, (*INCLUDABLE, s.Include)) or (
                        isinstance(sub, s.Assign) and isinstance(sub.target, s.Local))):
                    raise self.error(sub, "an INCLUDEd program may hold only DIM, GLOBAL, "
                                          "CONSTANT and name = value lines")
                self.statement(sub)
        finally:
            self.source, self.line_override, self.context = saved
        self.includes.append(name)

    # -- declarations ------------------------------------------------------------------------

    def st_Dim(self, st: s.Dim) -> None:
        old = self.scope.get(st.name)
        if old is not None and old.kind == "DIM":
            why = (f"; only the first {VARIABLE_CHARS} characters of a name are significant"
                   if len(st.name) == VARIABLE_CHARS else "")
            raise self.error(st, f"DIM {st.name}: {st.name} is already declared (DIM twice"
                                 f"{why})")
        if old is not None:
            raise self.error(st, f"DIM {st.name}: {st.name} is already a {old.kind} name")
        if st.name in self.scope.untyped:
            raise self.error(st, f"DIM {st.name}: {st.name} is already used as a local above "
                                 "(DIM comes before the first use)")
        decl = Decl("DIM", st.type, st.size, st.length or DEFAULT_LENGTH, dims=st.dims)
        init = None
        if st.init is not None:  # DIM x AS INTEGER = 0: checked like x = 0
            init = self.value_for(s.Local(st.name), st.init, decl)
        self.scope.names[st.name] = decl
        name = st.name
        if init is None:
            self.emit(lambda c: c.declare_local(name, decl), st)
        else:
            value = init

            def op(c: Any) -> None:
                c.declare_local(name, decl)
                c.set_local(name, coerce(decl, value(c)))

            self.emit(op, st)

    def st_DimList(self, st: s.DimList) -> None:
        for dim in st.dims:
            self.st_Dim(dim)

    def st_Global(self, st: s.Global) -> None:
        self._shared(st, st.name, Decl("GLOBAL", index=st.index))

    def st_Constant(self, st: s.Constant) -> None:
        self._shared(st, st.name, Decl("CONSTANT", value=st.value))

    def _shared(self, st: s.Stmt, name: str, decl: Decl) -> None:
        old = self.scope.get(name)
        if old is not None and old.kind == "DIM":
            raise self.error(st, f"{name} is already a local (DIM) of this program")
        why = rebinding(name, old, decl)
        if why is not None:
            raise self.error(st, why)
        self.scope.names[name] = decl
        self.emit(lambda c: c.declare(name, decl), st)

    # -- assignment targets ------------------------------------------------------------------

    def value_for(self, target: Any, value: s.Expr, decl: Decl | None = None
                  ) -> Callable[[Any], Any]:
        """The assigned value compiled, checked against the target's kind (``decl``: the
        declaration the target is about to have, for a DIM's initial value)."""
        if decl is not None:
            want = "str" if decl.is_str else "num"
        elif isinstance(target, (s.Local, s.Element)):
            want = kind_of(target, self.scope)
        else:
            want = "num"
        got = kind_of(value, self.scope)
        if want != got:
            if got == "str" and isinstance(target, s.Local) and self.scope.get(target.name) is None:
                raise ExprError(f"type mismatch: {target.name} holds numbers (a string needs "
                                f"DIM {target.name} AS STRING)")
            raise ExprError(f"type mismatch: cannot assign a {_word(got)} to a {_word(want)}")
        return compile_expr(value, self.scope)

    def writer(self, target: Any) -> Writer | None:
        """How to store into ``target``; None for an untyped local and for VR / TABLE /
        parameter targets (the compiler's fast paths)."""
        if isinstance(target, s.Local):
            decl = self.scope.plain(target.name)
            if decl is None:
                return None
            name = target.name
            if decl.kind == "CONSTANT":
                raise ExprError(f"{name} is a CONSTANT: it cannot be written")
            if decl.kind == "GLOBAL":
                index = float(decl.index)
                return lambda c, v: c.set_vr(index, v)
            if decl.size is not None:
                raise ExprError(f"{name} is an array: it needs an index, {name}(i)")
            return lambda c, v: c.set_local(name, coerce(decl, v))
        if isinstance(target, s.Element):
            decl = self.scope.get(target.name)
            if decl is None or decl.size is None:
                raise ExprError(f"{target.name} is not an array (DIM {target.name}(n) AS ... "
                                "declares one)")
            idx = index_of(target, decl, self.scope)
            name = target.name
            return lambda c, v: c.set_element(name, decl, idx(c), coerce(decl, v))
        if isinstance(target, s.Bit):
            return self._bit_writer(target)
        return None

    def _bit_writer(self, target: s.Bit) -> Writer:
        operand, bit = target.operand, target.bit
        read = compile_expr(operand, self.scope)
        store = self.writer(operand)
        if store is None:
            if isinstance(operand, s.Local):
                name = operand.name

                def store(c: Any, v: Any) -> None:
                    c.set_local(name, v)

            elif isinstance(operand, s.VrRef):
                idx = compile_expr(operand.index, self.scope)

                def store(c: Any, v: Any) -> None:
                    c.set_vr(idx(c), v)

            else:
                raise ExprError("a bit can be set only in a variable or a VR")
        mask = 1 << bit

        def write(c: Any, v: Any) -> None:
            old = int(read(c))
            store(c, float(old | mask if v != 0.0 else old & ~mask))

        return write


def _word(kind: str) -> str:
    return "string" if kind == "str" else "number"


__all__ = ["INCLUDABLE", "Declarations", "Resolver"]
