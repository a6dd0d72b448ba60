"""BASIC libraries: ``FUNCTION`` ... ``ENDFUNC`` with ``RETURN value``, called from any program
(MC4xx / MC6xx language, issue 32).

What the MC4 help says of FUNCTION (quoted on cnblogs, "TRIO-basic指令--函数FUNCTION",
httpcc/p/10748045): a user-defined function resides in a *function library* for use by any
BASIC program of the multi-tasking system; it has a name and ends with ENDFUNC; its body may
hold any BASIC command that works inside a function; at most 16 parameters, in brackets,
parameters of one type separated by commas; an optional return type at the end of the line;
FUNCTION may be used **only within a function library**; a library supports a smaller subset of
commands — GOSUB and GOTO are not supported; library functions may call other library
functions. A library is the program type "BASIC Lib", file ``.BAL`` (program type 12, as a
host tool's table of Trio program types writes it).

What the simulator does with it:

* **A library is a stored program holding FUNCTION blocks** (the REST surface has no program
  types, so the content says it ``[INF]``): every statement of it outside FUNCTION ... ENDFUNC,
  and GOTO, GOSUB, labels, ``ON ... GOTO/GOSUB`` and ``ON BASICERROR`` inside one, are compile
  errors; FUNCTION in an ordinary program is one too. A library cannot be RUN.
* **Its functions are visible to every program compiled after it is stored** (the "any BASIC
  program" of the help, ``[INF]``: no import statement is documented): ``f(a, b)`` in an
  expression, ``f(a, b)`` alone as a statement (its value unused), ``f()`` / ``f`` with no
  arguments. Argument counts and types are checked when the caller is compiled; a caller stored
  before its library is refused (the name is not known yet, as for INCLUDE). Storing the library
  again compiles its callers again; a function name defined in two libraries is refused.
* **A call runs the function to its RETURN inside the calling statement, in the calling
  process** ``[INF]`` (the help: a function "can take any BASIC commands provided that they
  work in the context of the required function operation"): its parameters (by value,
  converted to their types as DIM does) and the names it uses are its own locals — the
  caller's are untouched — and it returns its value converted to its return type (no RETURN
  value: 0 or ""). Its statements take no simulated time of their own; a statement in it that
  waits (WA, WAIT IDLE / LOADED / UNTIL, a move into a full process buffer) makes the calling
  process wait there as the same statement inline would, and STOP in it stops the process. At
  the command line (which cannot wait inside an expression) and in a condition re-tested while
  waiting (WAIT UNTIL's, WAIT IDLE's), a function that waits is a run-time error naming the
  function. A run-time error in a function stops the caller at its line, the message naming the
  function and the library line. Calls nest (also recursively) :data:`CALL_DEPTH` deep and a
  call runs at most :data:`CALL_STEPS` statements ``[INF]``, so a function that never returns is
  an error, not a hung simulator.

How a wait inside a function is simulated (:class:`Frame`, :class:`Suspend`, :func:`call_site`):
the expressions of a statement are Python closures that cannot pause half-way, so a waiting
function *unwinds* the calling statement: each call in progress keeps its frame (where it is,
its locals), the process waits, then runs the calling statement again. On that second run the
calls the statement had already completed answer the values they returned (each in evaluation
order, not run twice), the call that waited goes on from the statement after its wait, and the
rest of the statement runs as usual. The only difference from a controller that pauses
mid-expression ``[INF]``: the parts of the statement that are not calls (a parameter such as
MPOS, a VR) are read again after the wait, as they would be if the program had written the
call on a line of its own first.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from ..card.basic_errors import BasicError
from . import statements as s
from .scope import Decl, ExprError

#: Calls nested inside each other (recursion included) before a run-time error ``[INF]``.
CALL_DEPTH = 64
#: Statements one call may run before a run-time error ``[INF]``.
CALL_STEPS = 1_000_000

#: Statements a BASIC library does not support inside a FUNCTION (FUNCTION help: "GOSUB and
#: GOTO are not supported"; labels and ON ... GOTO / GOSUB / BASICERROR go with them [INF]).
REFUSED_IN_LIBRARY: dict[type[s.Stmt], str] = {
    s.Goto: "GOTO", s.Gosub: "GOSUB", s.Label: "a label", s.OnBranch: "ON ... GOTO / GOSUB",
    s.OnError: "ON BASICERROR",
}


@dataclass(eq=False, slots=True)
class FunctionDef:
    """A library function: its signature and, once its library is compiled, its code."""

    name: str
    library: str
    params: tuple[tuple[str, Decl], ...]
    type: str | None  # the return type; None: returns no value
    line: int
    code: Any = None  # the compiled body (a compiler.Code)

    @property
    def is_str(self) -> bool:
        return self.type == "STRING"

    def default(self) -> float | str:
        return "" if self.is_str else 0.0

    def where(self, line: int) -> str:
        return f"FUNCTION {self.name}, {self.library} line {line}"


class FnReturn:
    """What a function's RETURN hands to :meth:`~motionsim.sim.trio.run.context.Context.
    call_function`."""

    __slots__ = ("value",)

    def __init__(self, value: float | str) -> None:
        self.value = value


class Frame:
    """One level of a process' calls: the process' own statements (``fn`` None) or one call of
    a library function in progress. A statement holding calls (:func:`call_site`) numbers them
    in evaluation order; ``memo`` holds the values of the calls of the current statement that
    have returned, so that running the statement again after a wait does not run them twice."""

    __slots__ = ("fn", "can_wait", "active", "replaying", "memo", "next_call", "resume",
                 "pc", "steps", "waited", "state")

    def __init__(self, fn: FunctionDef | None = None, can_wait: bool = False) -> None:
        self.fn = fn
        #: A statement of this level may wait (a process running it; the command line not).
        self.can_wait = can_wait
        self.active = False  # one of this level's call-site statements is running
        self.replaying = False  # the next call-site statement is the one a wait interrupted
        self.memo: list[Any] = []
        self.next_call = 0
        self.resume: Frame | None = None  # the call to go on with when the statement reruns
        # a suspended call: its pc, statements run, whether its own statement waited (else a
        # call inside that statement did), its locals / loops / SELECT values / data bytes
        self.pc = 0
        self.steps = 0
        self.waited = False
        self.state: tuple[Any, ...] | None = None


class Suspend(BaseException):  # noqa: N818 - a signal to the process, not an error
    """A statement inside a library function waits (``wait``: the compiler's Block / Sleep /
    WaitFor / Poll / HALT): unwinds the calling statement to the process, which waits and then
    runs that statement again (:class:`Frame`). A BaseException, as GeneratorExit is: no
    ``except Exception`` on the way may take it for an error. ``text``: the library line that waits;
    ``state``: the context while waiting (the innermost call's locals, loops, SELECT values,
    data bytes, call depth and frame)."""

    def __init__(self, wait: Any, text: str) -> None:
        super().__init__(text)
        self.wait = wait
        self.text = text
        self.state: tuple[Any, ...] | None = None
        self.where = ""  # "FUNCTION F, LIB line n" of the statement that waits


def in_function(exc: BasicError, where: str) -> BasicError:
    """A run-time error met in a library function, its message naming the function and the
    library line (``where``: :meth:`FunctionDef.where`) once — the innermost call's."""
    if " (in FUNCTION " in exc.message:
        return exc
    return BasicError(f"{exc.message} (in {where})", exc.number)


def call_site(op: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """The operation of a statement that calls library functions: its calls numbered afresh
    (or, when it runs again after a wait, answered from the values already returned)."""

    def site(c: Any) -> Any:
        fr = c.frame
        if fr.replaying:
            fr.replaying = False
        else:
            fr.memo.clear()
            fr.resume = None
        fr.next_call = 0
        fr.active = True
        try:
            return op(c)
        finally:
            fr.active = False

    return site


@dataclass(slots=True)
class Library:
    """The functions a library program defines, by name."""

    name: str
    functions: dict[str, FunctionDef] = field(default_factory=dict)


def signature(st: s.Function, library: str) -> FunctionDef:
    """The FunctionDef of a FUNCTION line (its body compiled later)."""
    params = tuple((name, Decl("DIM", kind)) for name, kind in st.params)
    return FunctionDef(st.name, library, params, st.type, st.line)


def call_of(fn: FunctionDef, args: tuple[s.Expr, ...], scope: Any, *, value: bool
            ) -> Callable[[Any], Any]:
    """A compiled call of ``fn`` with ``args``: counts and types checked now (``value``: the
    call's result is used, so the function must return one)."""
    from .expressions import compile_expr, kind_of

    if len(args) != len(fn.params):
        raise ExprError(f"{fn.name} takes {len(fn.params)} argument"
                        f"{'' if len(fn.params) == 1 else 's'}, got {len(args)}")
    if value and fn.type is None:
        raise ExprError(f"{fn.name} returns no value (FUNCTION {fn.name} has no AS type)")
    scope.calls += 1  # the compiler wraps the statement holding it (call_site)
    compiled = []
    for (pname, decl), arg in zip(fn.params, args, strict=True):
        if (kind_of(arg, scope) == "str") != decl.is_str:
            want = "a string" if decl.is_str else "a number"
            raise ExprError(f"type mismatch: argument {pname} of {fn.name} needs {want}")
        compiled.append(compile_expr(arg, scope))
    if len(compiled) == 1:
        (a0,) = compiled
        return lambda c: c.call_function(fn, (a0(c),))
    return lambda c: c.call_function(fn, tuple(a(c) for a in compiled))


def visible(stored: Mapping[str, Library], replacing: str | None = None,
            new: Library | None = None) -> dict[str, FunctionDef]:
    """The functions a program compiled now can call: every stored library's (with ``new``
    in place of the stored library ``replacing``)."""
    out: dict[str, FunctionDef] = {}
    for name, lib in stored.items():
        if name != replacing:
            out.update(lib.functions)
    if new is not None:
        out.update(new.functions)
    return out


__all__ = ["CALL_DEPTH", "CALL_STEPS", "REFUSED_IN_LIBRARY", "FnReturn", "Frame",
           "FunctionDef", "Library", "Suspend", "call_of", "call_site", "in_function",
           "signature", "visible"]


class Functions:
    """The compiler's side of libraries: a library program's FUNCTION blocks, RETURN value,
    a call standing as a statement. A mixin of
    :class:`motionsim.sim.trio.language.compiler._Compiler`."""

    program: s.Program
    name: str
    resolve: Any
    shared: Mapping[str, Decl] | None
    scope: Any
    includes: list[str]
    function: FunctionDef | None
    errors: Any
    emit: Callable[..., int]
    error: Callable[..., Any]

    def compile_library(self) -> Library:
        """Each FUNCTION of this library program, its signature first (so the functions call
        each other in any order), then its body compiled as a code of its own."""
        lib = Library(self.name)
        groups: list[tuple[s.Function, FunctionDef, list[s.Stmt]]] = []
        current: tuple[s.Function, FunctionDef, list[s.Stmt]] | None = None
        for st in self.program.statements:
            if isinstance(st, s.Function):
                if current is not None:
                    raise self.error(st, f"FUNCTION inside FUNCTION {current[0].name} (ENDFUNC "
                                         "closes a function first)")
                if st.name in lib.functions:
                    raise self.error(st, f"FUNCTION {st.name} is defined twice")
                other = self.scope.functions.get(st.name)
                if other is not None and other.library != self.name:
                    raise self.error(st, f"FUNCTION {st.name} is already defined in library "
                                         f"{other.library}")
                fn = signature(st, self.name)
                lib.functions[st.name] = fn
                current = (st, fn, [])
            elif isinstance(st, s.EndFunc):
                if current is None:
                    raise self.error(st, "ENDFUNC without FUNCTION")
                groups.append(current)
                current = None
            elif current is None:
                raise self.error(st, "a BASIC library holds only FUNCTION ... ENDFUNC blocks: "
                                     "this statement is outside a FUNCTION")
            else:
                current[2].append(st)
        if current is not None:
            raise self.error(current[0], f"FUNCTION {current[0].name} without ENDFUNC")
        functions = {**self.scope.functions, **lib.functions}
        compiler: Any = type(self)  # the compiler class this mixin is part of
        for _st, fn, body in groups:
            sub = compiler(s.Program(tuple(body), self.program.lines, self.program.dialect),
                             self.name, self.resolve, self.shared, functions=functions,
                             function=fn, errors=self.errors)
            fn.code = sub.run()
            self.includes.extend(n for n in sub.includes if n not in self.includes)
        return lib

    def refuse_in_library(self, st: s.Stmt) -> None:
        what = REFUSED_IN_LIBRARY.get(type(st))
        if what is not None and self.function is not None:
            raise self.error(st, f"{what} is not supported in a BASIC library (FUNCTION "
                                 f"{self.function.name})")

    def st_Function(self, st: s.Function) -> None:
        raise self.error(st, "FUNCTION may be used only within a BASIC library, on a line of "
                             "its own outside any block")

    def st_EndFunc(self, st: s.EndFunc) -> None:
        raise self.error(st, "ENDFUNC without FUNCTION")

    def return_value(self, st: s.Return) -> bool:
        """RETURN in a FUNCTION (True: compiled here); ``RETURN value`` elsewhere is an
        error."""
        from .expressions import compile_expr, kind_of
        from .scope import coerce

        fn = self.function
        if fn is None:
            if st.value is not None:
                raise self.error(st, "RETURN with a value is only allowed in a FUNCTION of a "
                                     "BASIC library")
            return False
        if st.value is None:
            default = fn.default()
            self.emit(lambda c: FnReturn(default), st)
            return True
        if fn.type is None:
            raise self.error(st, f"FUNCTION {fn.name} returns no value (no AS type): RETURN "
                                 "takes none")
        if (kind_of(st.value, self.scope) == "str") != fn.is_str:
            raise self.error(st, f"type mismatch: FUNCTION {fn.name} returns "
                                 f"{'a string' if fn.is_str else 'a number'}")
        value = compile_expr(st.value, self.scope)
        decl = Decl("DIM", fn.type)
        self.emit(lambda c: FnReturn(coerce(decl, value(c))), st)
        return True

    def st_CallStmt(self, st: s.CallStmt) -> None:
        call = st.call
        decl = self.scope.get(call.name)
        fn = self.scope.functions.get(call.name)
        if decl is not None or fn is None:
            what = (f"{call.name} is an array: an element cannot stand alone as a statement"
                    if decl is not None else
                    f"unknown command {call.name!r}: no stored BASIC library has a FUNCTION "
                    f"{call.name}")
            raise self.error(st, what)
        self.scope.used.add(fn.library)
        run = call_of(fn, call.indices, self.scope, value=False)

        def op(c: Any) -> None:
            run(c)

        self.emit(op, st)


__all__ += ["Functions"]
