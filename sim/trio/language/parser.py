"""Trio BASIC text -> typed statements (:mod:`motionsim.sim.trio.language.statements`).

One source line holds an optional label (``name:`` as its first item) and statements
separated by ``:``. ``IF c THEN`` ending a line opens a block closed by ``ENDIF``; with
statements after ``THEN`` it is the one-line form (``IF c THEN a ELSE b``). Expression
precedence follows the manual (spec §9.2), highest first: unary ``-`` and ``NOT``; ``^``;
``*`` ``/``; ``MOD``; ``+`` ``-``; comparisons; ``AND`` ``OR`` ``XOR``; equal precedence
left to right.

The language is the model's (config ``model``, spec §11): on ``mc4xx`` / ``mc6xx`` also
``INCLUDE``, ``DIM``, ``GLOBAL``, ``CONSTANT``, ``SELECT_CASE``, ``EXIT_LOOP``, ``FUNCTION``
(BASIC libraries), string values and functions, bit access ``v.n`` and the shifts; on
``series2`` / ``mc2xx`` those words are the syntax error that generation answers and otherwise
ordinary names. A Trio keyword (:data:`RESERVED`, plus the MC4 words on ``mc4xx``) is never a
local variable. ``ON BASICERROR GOTO`` and ``ON e GOSUB/GOTO`` are every model's.

A statement that starts with a keyword is a row of the model's statement table (:data:`BASE`,
:data:`MC4` at the foot of this module; :mod:`motionsim.sim.trio.language.commands`): the
keyword leads to its parse handler here and to the compile handler of each statement class it
builds. Before the table come the parameters (``SPEED = 100``) and the commands refused as not
simulated; a name that is neither is an assignment to a variable.

Errors raise :class:`motionsim.sim.errors.ParseError` with the 1-based ``line`` and ``column``; the
structure of blocks (FOR/NEXT, IF/ENDIF, labels) and the declarations are checked by
:mod:`motionsim.sim.trio.language.compiler`.
"""

from __future__ import annotations

import math
import re

from ...errors import NotSimulated, ParseError
from ..card.fieldbus import BUS_FUNCTIONS
from ..card.models import DEFAULT_MODEL
from ..card.parameters import ALL_PARAMS, WRITABLE
from ..card.setup_commands import COMMANDS as SETUP_COMMANDS
from . import statements as s
from .commands import Dialect, Row
from .compiler import _Compiler
from .constants import CONSTANTS, LANGUAGE_PARAMS
from .declaration_parser import DeclarationParser
from .expressions import FUNCTIONS
from .keywords import INDEX, MC4_MODELS, MC4_WORDS, NOT_SIMULATED
from .lexer import Token, tokenize
from .move_words import MOVE_ARGS
from .names import label, variable
from .strings import STRING_FUNCTIONS
from .structure_parser import StructureParser

#: The deepest a line may nest ``[INF]`` (no figure in the manuals): sub-expressions (brackets,
#: function arguments, indexes), unary operators, the binary operators of one expression and
#: one-line ``IF ... THEN`` statements inside each other each count one level; level
#: ``MAX_NESTING + 1`` is a syntax error naming the limit, so neither the parser nor the
#: compiled program recurses deeper than Python's stack allows.
MAX_NESTING = 100

#: I/O functions read as values, with the argument counts they accept
#: (:mod:`motionsim.sim.trio.card.io`).
IO_ARGS: dict[str, tuple[int, int]] = {
    "IN": (0, 2), "READ_OP": (1, 1), "OP": (1, 1), "AIN": (1, 1),
}

#: Short forms of commands (TJ2P-71: CO; MOVELINK help: ML; TRM MC216 p. 220 listing: DP).
ALIASES = {"CO": "CONNECT", "ML": "MOVELINK", "DP": "DEFPOS"}

_KEYWORDS = frozenset(
    {
        "PRINT", "FOR", "TO", "STEP", "NEXT", "IF", "THEN", "ELSE", "ELSEIF", "ENDIF",
        "WHILE", "WEND", "REPEAT", "UNTIL", "WAIT", "IDLE", "LOADED", "WA", "GOTO", "GOSUB",
        "RETURN", "STOP", "RUN", "BASE", "AXIS", "PROC", "CANCEL", "RAPIDSTOP", "VR", "TABLE",
        "AND", "OR", "XOR", "NOT", "MOD", "DEFPOS", "HALT", "PROCESS", "HEX", "OP", "ON",
        "INCLUDE", "DIM", "GLOBAL", "CONSTANT",
    }
) | frozenset(MOVE_ARGS) | frozenset(ALIASES)

#: Every parameter name, the language's own (TICKS, LAST_AXIS) included, and the writable ones.
PARAMS = ALL_PARAMS | frozenset(LANGUAGE_PARAMS)
PARAMS_WRITABLE = WRITABLE | frozenset(k for k, (_kind, w) in LANGUAGE_PARAMS.items() if w)

#: Names that are Trio keywords on every model: never a local variable (spec §11.10).
RESERVED = (
    (_KEYWORDS - MC4_WORDS) | frozenset(FUNCTIONS) | frozenset(CONSTANTS) | PARAMS
    | NOT_SIMULATED | frozenset({"BASICERROR", "IDLE", "LOADED", "STEP", "PROC"})
    | frozenset(BUS_FUNCTIONS)
    | frozenset(w for kws in INDEX.values() for k in kws
                for w in re.findall(r"[A-Z_][A-Z0-9_]*", k))
)

_CMP = frozenset({"=", "<>", "<", "<=", ">", ">="})

#: Binary operators and their precedence, highest last (spec §9.2); unary - and NOT bind
#: tighter than all of them. The MC4 shifts ``<<`` ``>>`` (:data:`SHIFTS`) bind between the
#: comparisons and ``+`` ``-`` (no manual figure reached: the place C and most BASICs with
#: shifts give them, ``[INF]``), so ``a << 2 + 1`` is ``a << 3`` and ``x >> 4 = 1`` compares.
_PRECEDENCE: dict[str, int] = {
    "AND": 1, "OR": 1, "XOR": 1,
    **dict.fromkeys(_CMP, 2),
    "<<": 3, ">>": 3,
    "+": 4, "-": 4,
    "MOD": 5,
    "*": 6, "/": 6,
    "^": 7,
}
#: The shift operators: MC4xx / MC6xx language only ``[INF]`` (issue 32: in MC4xx programs).
SHIFTS = frozenset({"<<", ">>"})
_EOL: Token = ("eol", "", 0)
_PAD = [_EOL] * 4


_SPECIAL: dict[int, tuple[Dialect, tuple[frozenset[str], frozenset[str]]]] = {}


def special_words(dialect: Dialect) -> tuple[frozenset[str], frozenset[str]]:
    """The names a rule of ``dialect`` treats specially, at the start of a statement and in an
    expression: every set :meth:`_Line.one_statement` / :meth:`_Line.named_special` test a
    name against, so a name in neither is an assignment / a variable without those tests
    (pinned by tests/sim/trio/test_parser_fast_paths.py)."""
    got = _SPECIAL.get(id(dialect))
    if got is None or got[0] is not dialect:
        common = RESERVED | dialect.keywords | dialect.later_words
        statement = common | PARAMS | NOT_SIMULATED | frozenset(dialect.parsers) | frozenset(
            ALIASES)
        value = (common | frozenset(CONSTANTS) | frozenset(FUNCTIONS) | frozenset(BUS_FUNCTIONS)
                 | frozenset(STRING_FUNCTIONS) | PARAMS | frozenset(IO_ARGS) | NOT_SIMULATED
                 | {"VR", "TABLE", "HEX"})
        got = _SPECIAL[id(dialect)] = (dialect, (statement, value))
    return got[1]


class _Line(DeclarationParser, StructureParser):
    """Recursive-descent parser over the tokens of one source line."""

    def __init__(self, text: str, line_no: int, model: str = DEFAULT_MODEL,
                 dialect: Dialect | None = None) -> None:
        self.model = model
        self.dialect = dialect or dialect_of(model)
        self.special = special_words(self.dialect)
        self.start(text, line_no)

    def start(self, text: str, line_no: int) -> None:
        """Parse ``text`` (line ``line_no``) next: a program's lines share one parser."""
        self.text = text
        self.line_no = line_no
        self.toks = tokenize(text, line_no)
        self.toks += _PAD  # end-of-line tokens: peek() past the end needs no bounds check
        self.i = 0
        self.word = ""  # the keyword of the statement being parsed (aliases resolved)
        self.in_print = False
        #: Nesting level (:data:`MAX_NESTING` at most): the line's first statement and its
        #: top expression are level 0.
        self.depth = -2

    # -- token helpers ------------------------------------------------------------------

    def peek(self, ahead: int = 0) -> Token:
        try:
            return self.toks[self.i + ahead]
        except IndexError:
            return _EOL

    def take(self) -> Token:
        tok = self.toks[self.i]  # never past the end-of-line padding (_PAD)
        self.i += 1
        return tok

    def at(self, text: str) -> bool:
        # a string's text keeps its quotes and a number's is digits: only op / name match
        return self.toks[self.i][1] == text

    def accept(self, text: str) -> bool:
        if self.toks[self.i][1] == text:
            self.i += 1
            return True
        return False

    def col(self) -> int:
        tok = self.toks[self.i]
        return tok[2] if tok[0] != "eol" else len(self.text.rstrip()) + 1

    def error(self, message: str, col: int | None = None) -> ParseError:
        return ParseError(
            message, line=self.line_no, column=col or self.col(), text=self.text
        )

    def expect(self, text: str) -> Token:
        tok = self.toks[self.i]
        if tok[1] != text:
            got = tok[1] or "end of line"
            raise self.error(f"expected {text!r}, found {got!r}")
        self.i += 1
        return tok

    def end_of_statement(self) -> bool:
        tok = self.toks[self.i]
        return tok[0] == "eol" or tok[1] == ":"

    def name(self) -> str:
        tok = self.toks[self.i]
        if tok[0] != "name":
            raise self.error(f"expected a name, found {tok[1] or 'end of line'!r}")
        self.i += 1
        return tok[1]

    def string(self, what: str = "program name") -> str:
        """A quoted name, also in brackets (``RUN("X")``, ``STOP("X")``, MC4 form ``[INF]``)."""
        bracket = self.accept("(")
        tok = self.peek()
        if tok[0] != "string":
            raise self.error(f"expected a quoted {what}")
        self.i += 1
        if bracket and not self.at(","):
            self.expect(")")
        return tok[1][1:-1].upper()

    def reserved(self, word: str) -> bool:
        """A Trio keyword of this model: never a local variable."""
        return word in RESERVED or word in self.dialect.keywords

    def later_only(self, word: str, col: int) -> ParseError:
        return self.error(
            f"{word} is not Trio BASIC on the {self.model} model: it came with the MC4xx / "
            "MC6xx language (firmware 2.x)", col)

    def variable_name(self, what: str = "variable") -> str:
        """A name a program may use for its own variable: not a keyword."""
        tok = self.peek()
        word = self.name()
        if self.reserved(word):
            raise self.error(f"{word} is a Trio BASIC keyword: it cannot be a {what}", tok[2])
        return variable(word)

    def label_name(self) -> str:
        """A label a GOTO / GOSUB / ON names: its significant characters (:mod:`.names`)."""
        return label(self.name())

    def bit_suffix(self, node: s.Expr) -> s.Expr:
        """``value.n`` (MC4): a ``.digits`` number written straight after a name, ``)`` or
        ``]`` is bit ``n`` of that value (spec §11.8; ``a .4`` with a space stays a number)."""
        tok = self.peek()
        if tok[0] != "number" or tok[1][0] != "." or not tok[1][1:].isdigit():
            return node
        prev = self.toks[self.i - 1] if self.i else None
        if prev is None or prev[2] + len(prev[1]) != tok[2]:
            return node
        if not self.dialect.bit_access:
            raise self.error(
                f"bit access '{prev[1]}{tok[1]}' is not Trio BASIC on the {self.model} "
                "model: it came with the MC4xx / MC6xx language (firmware 2.x)", tok[2])
        bit = int(tok[1][1:])
        if bit > 63:
            raise self.error(f"bit {bit} is out of range 0..63", tok[2])
        self.i += 1
        return s.Bit(node, bit)

    # -- lines and statements ----------------------------------------------------------

    def parse(self) -> list[s.Stmt]:
        out: list[s.Stmt] = []
        toks = self.toks
        first, second = toks[0], toks[1]  # the padding makes both exist
        if (
            first[0] == "name"
            and second[0] == "op"
            and second[1] == ":"
            and first[1] not in _KEYWORDS
        ):
            out.append(s.Label(self.line_no, first[2], label(first[1])))
            self.i += 2
        out.extend(self.statements(stop=()))
        if toks[self.i][0] != "eol":
            raise self.error(f"unexpected {toks[self.i][1]!r}")
        return out

    def statements(self, stop: tuple[str, ...]) -> list[s.Stmt]:
        """``:``-separated statements up to end of line or a word in ``stop``."""
        out: list[s.Stmt] = []
        toks = self.toks
        while True:
            while toks[self.i][1] == ":":
                self.i += 1
            tok = toks[self.i]
            if tok[0] == "eol" or tok[1] in stop:
                return out
            out.append(self.statement())
            tok = toks[self.i]
            if tok[0] == "eol" or tok[1] in stop:
                return out
            if tok[1] != ":":
                raise self.error(f"unexpected {tok[1]!r} after the statement")

    def nest(self, levels: int = 1) -> None:
        """``levels`` more levels of nesting; a syntax error past :data:`MAX_NESTING`."""
        self.depth += levels
        if self.depth > MAX_NESTING:
            raise self.too_deep()

    def too_deep(self) -> ParseError:
        return self.error(f"expression or statement nested deeper than {MAX_NESTING} "
                          "levels (the limit)")

    def statement(self) -> s.Stmt:
        """One statement (nesting counted: :data:`MAX_NESTING`): a parameter assignment, a
        row of the dialect's statement table (:mod:`motionsim.sim.trio.language.commands`),
        or an assignment to a variable."""
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise self.too_deep()
        tok = self.toks[self.i]
        if tok[0] == "name" and tok[1] not in self.special[0]:
            stmt = self.assignment(self.line_no, tok[2])  # a name no row or rule claims
        else:
            stmt = self.one_statement()
        self.depth -= 1
        return stmt

    def one_statement(self) -> s.Stmt:
        """A statement starting with ``?`` or a name (:meth:`statement` has sent a name no
        set below holds straight to :meth:`assignment`, as this would)."""
        tok = self.toks[self.i]
        ln, col = self.line_no, tok[2]
        if tok[0] == "op" and tok[1] == "?":
            word = "?"
        elif tok[0] != "name":
            raise self.error(f"a statement cannot start with {tok[1]!r}")
        else:
            word = ALIASES.get(tok[1], tok[1])
        if word in self.dialect.later_words:
            nxt = self.peek(1)
            if not (nxt[0] == "op" and nxt[1] in ("=", "(")):
                raise self.later_only(word, col)
            return self.assignment(ln, col)  # an ordinary name on this model
        nxt = self.peek(1)
        if nxt[0] == "op" and nxt[1] == "=" and word not in PARAMS and self.reserved(word):
            if word in CONSTANTS:
                raise self.error(f"{word} is a constant: it cannot be written", col)
            raise self.error(f"{word} is a Trio BASIC keyword: it cannot be a variable", col)
        if word in PARAMS:
            self.i += 1
            target = self.param_ref(word, col)
            if word not in PARAMS_WRITABLE:
                raise self.error(f"{word} cannot be written", col)
            self.expect("=")
            return s.Assign(ln, col, target, self.expr())
        if word in NOT_SIMULATED:
            raise self.not_simulated(word, col)
        parse = self.dialect.parsers.get(word)
        if parse is not None:
            self.i += 1
            self.word = word
            return parse(self, ln, col)
        if self.reserved(word):
            raise self.error(f"{word} is not a command here", col)
        return self.assignment(ln, col)

    def assignment(self, ln: int, col: int) -> s.Stmt:
        """``name = e``, ``name(i) = e`` (an array element, MC4), ``name.n = e`` (a bit, MC4)."""
        word = variable(self.take()[1])
        target: s.Local | s.Element | s.Bit = s.Local(word)
        if self.at("(") and self.dialect.arrays:
            target = s.Element(word, self.call_args())
            if ((self.end_of_statement() or self.at("ELSE"))
                    and "FUNCTION" in self.dialect.parsers):
                return s.CallStmt(ln, col, target)  # f(a, b): a library function's call
        bit = self.bit_suffix(target)
        if isinstance(bit, s.Bit):
            target = bit
        if not self.at("="):
            raise self.error(f"unknown command {word!r}", col)
        self.i += 1
        return s.Assign(ln, col, target, self.expr())

    def not_simulated(self, word: str, col: int) -> NotSimulated:
        return NotSimulated(
            f"{word} is a Trio BASIC command that is not simulated",
            line=self.line_no, column=col, text=self.text, keyword=word,
        )

    def axis_modifier(self) -> s.Expr | None:
        if self.accept("AXIS"):
            self.expect("(")
            e = self.expr()
            self.expect(")")
            return e
        return None

    def args(self) -> tuple[s.Expr, ...]:
        self.expect("(")
        out = [self.expr()]
        toks = self.toks
        while toks[self.i][1] == ",":
            self.i += 1
            out.append(self.expr())
        self.expect(")")
        return tuple(out)

    def st_move(self, ln: int, col: int) -> s.Stmt:
        return self.move(self.word, ln, col)

    def st_setup(self, ln: int, col: int) -> s.Stmt:
        return self.setup_command(self.word, ln, col)

    def st_bus(self, ln: int, col: int) -> s.Stmt:
        return s.BusCall(ln, col, self.word, self.bus_args(self.word))

    def bus_args(self, name: str) -> tuple[s.Expr, ...]:
        """The arguments of a system / fieldbus function, counted against its row."""
        fn = BUS_FUNCTIONS[name]
        c = self.col()
        if not self.at("("):
            raise self.error(f"{name} needs its arguments in brackets, {name}(...)")
        args = self.args()
        if not fn.low <= len(args) <= fn.high:
            want = str(fn.low) if fn.low == fn.high else f"{fn.low} to {fn.high}"
            raise self.error(f"{name} takes {want} arguments, got {len(args)}", c)
        return args

    def st_QUERY(self, ln: int, col: int) -> s.Stmt:
        """``? items``: PRINT's short form, to the process' OUTDEVICE (no ``#n``)."""
        return s.Print(ln, col, *self.print_items())

    def move(self, kind: str, ln: int, col: int) -> s.Stmt:
        lo, hi = MOVE_ARGS[kind]
        args: tuple[s.Expr, ...] = ()
        if hi:
            args_col = self.col()
            args = self.args()
            if not lo <= len(args) <= hi:
                want = str(lo) if lo == hi else f"{lo} to {hi}"
                raise self.error(f"{kind} takes {want} arguments, got {len(args)}", args_col)
        return s.MoveCmd(ln, col, kind, args, self.axis_modifier())

    def setup_command(self, name: str, ln: int, col: int) -> s.Stmt:
        """A set-up command: its arguments (counts from the command table), ``AXIS(n)``."""
        cmd = SETUP_COMMANDS[name]
        args: tuple[s.Expr, ...] = ()
        c = self.col()
        if cmd.high and (cmd.low or self.at("(")):
            args = self.args()
        if not cmd.low <= len(args) <= cmd.high:
            want = str(cmd.low) if cmd.low == cmd.high else f"{cmd.low} to {cmd.high}"
            raise self.error(f"{name} takes {want} arguments, got {len(args)}", c)
        axis = self.axis_modifier() if cmd.axis_command else None
        return s.SetupCmd(ln, col, name, args, axis)

    def st_PRINT(self, ln: int, col: int) -> s.Stmt:
        channel = None
        if self.accept("#"):
            channel = self.expr()
            self.expect(",")
        return s.Print(ln, col, *self.print_items(), channel=channel)

    def st_SCOPE(self, ln: int, col: int) -> s.Stmt:
        """``SCOPE(OFF)``, ``SCOPE(ON, period)``, ``SCOPE(ON, period, start, stop, p0..p7)``."""
        c = self.col()
        args = self.args()
        if len(args) not in (1, 2) and not 5 <= len(args) <= 12:
            raise self.error(f"SCOPE takes 1, 2 or 5 to 12 arguments, got {len(args)}", c)
        return s.ScopeCmd(ln, col, args)

    def st_DEFPOS(self, ln: int, col: int) -> s.Stmt:
        values = self.args()
        return s.DefPos(ln, col, values, self.axis_modifier())

    def st_OP(self, ln: int, col: int) -> s.Stmt:
        c = self.col()
        args = self.args()
        if len(args) > 2:
            raise self.error(f"OP takes 1 or 2 arguments, got {len(args)}", c)
        return s.OpWrite(ln, col, args)

    def io_read(self, word: str, col: int) -> s.IoRead:
        lo, hi = IO_ARGS[word]
        args: tuple[s.Expr, ...] = ()
        if self.at("("):
            c = self.col()
            args = self.args()
            if not lo <= len(args) <= hi:
                want = str(lo) if lo == hi else f"{lo} to {hi}"
                raise self.error(f"{word} takes {want} arguments, got {len(args)}", c)
        elif lo:
            raise self.error(f"{word} needs ({'n' if hi == 1 else 'a, b'})")
        return s.IoRead(word, args)

    def st_HALT(self, ln: int, col: int) -> s.Stmt:
        return s.Halt(ln, col)

    def st_PROCESS(self, ln: int, col: int) -> s.Stmt:
        return s.ProcessList(ln, col)

    def print_format(self) -> tuple[int, int] | None:
        """``[d]`` (decimals) or ``[w,d]`` (width, decimals) after a PRINT item."""
        if not self.accept("["):
            return None
        nums = []
        while True:
            tok = self.peek()
            if tok[0] != "number" or not tok[1].isdigit():
                raise self.error("expected a whole number in a PRINT format [w,d]")
            nums.append(int(self.take()[1]))
            if not self.accept(","):
                break
        self.expect("]")
        if len(nums) > 2:
            raise self.error("a PRINT format is [decimals] or [width,decimals]")
        return (0, nums[0]) if len(nums) == 1 else (nums[0], nums[1])

    def print_items(
        self,
    ) -> tuple[tuple[tuple[s.Expr, str], ...], tuple[tuple[int, int] | None, ...]]:
        items: list[tuple[s.Expr, str]] = []
        formats: list[tuple[int, int] | None] = []
        while not self.end_of_statement() and not self.at("ELSE"):
            e: s.Expr | s.Hex
            if self.peek()[0] == "string" and not self.dialect.strings:
                e = s.Str(self.take()[1][1:-1])
            elif self.accept("HEX"):
                (value,) = self.args_exact(1, "HEX")
                e = s.Hex(value)
            else:
                self.in_print = True  # PRINT("text"): a bracketed string item (spec §11.8)
                try:
                    e = self.expr()
                finally:
                    self.in_print = False
            formats.append(self.print_format() if not isinstance(e, (s.Str, s.Hex)) else None)
            sep = ""
            if self.at(";") or self.at(","):
                sep = self.take()[1]
            items.append((e, sep))
            if not sep:
                break
        return tuple(items), tuple(formats)

    def st_FOR(self, ln: int, col: int) -> s.Stmt:
        var = self.variable_name("loop variable")
        self.expect("=")
        start = self.expr()
        self.expect("TO")
        end = self.expr()
        step = self.expr() if self.accept("STEP") else None
        return s.For(ln, col, var, start, end, step)

    def st_NEXT(self, ln: int, col: int) -> s.Stmt:
        var = None if self.end_of_statement() else variable(self.name())
        return s.Next(ln, col, var)

    def st_IF(self, ln: int, col: int) -> s.Stmt:
        cond = self.expr()
        self.expect("THEN")
        if self.peek()[0] == "eol":
            return s.IfBlock(ln, col, cond)
        then = self.statements(stop=("ELSE",))
        orelse: list[s.Stmt] = []
        if self.accept("ELSE"):
            orelse = self.statements(stop=())
        if not then:
            raise self.error("expected a statement after THEN")
        return s.If(ln, col, cond, tuple(then), tuple(orelse))

    def st_ELSEIF(self, ln: int, col: int) -> s.Stmt:
        cond = self.expr()
        self.expect("THEN")
        return s.ElseIf(ln, col, cond)

    def st_ELSE(self, ln: int, col: int) -> s.Stmt:
        return s.Else(ln, col)

    def st_ENDIF(self, ln: int, col: int) -> s.Stmt:
        return s.EndIf(ln, col)

    def st_WHILE(self, ln: int, col: int) -> s.Stmt:
        return s.While(ln, col, self.expr())

    def st_WEND(self, ln: int, col: int) -> s.Stmt:
        return s.Wend(ln, col)

    def st_REPEAT(self, ln: int, col: int) -> s.Stmt:
        return s.Repeat(ln, col)

    def st_UNTIL(self, ln: int, col: int) -> s.Stmt:
        return s.Until(ln, col, self.expr())

    def st_WAIT(self, ln: int, col: int) -> s.Stmt:
        if self.accept("IDLE"):
            return s.WaitIdle(ln, col, self.axis_modifier())
        if self.accept("LOADED"):
            return s.WaitLoaded(ln, col, self.axis_modifier())
        if self.accept("UNTIL"):
            return s.WaitUntil(ln, col, self.expr())
        raise self.error("expected IDLE, LOADED or UNTIL after WAIT")

    def st_WA(self, ln: int, col: int) -> s.Stmt:
        self.expect("(")
        ms = self.expr()
        self.expect(")")
        return s.Wa(ln, col, ms)

    def st_GOTO(self, ln: int, col: int) -> s.Stmt:
        return s.Goto(ln, col, self.label_name())

    def st_GOSUB(self, ln: int, col: int) -> s.Stmt:
        return s.Gosub(ln, col, self.label_name())

    def st_RETURN(self, ln: int, col: int) -> s.Stmt:
        """``RETURN``; in the MC4 language also ``RETURN value`` (a FUNCTION's result)."""
        if (self.end_of_statement() or self.at("ELSE")
                or "FUNCTION" not in self.dialect.parsers):
            return s.Return(ln, col)
        return s.Return(ln, col, self.expr())

    def st_STOP(self, ln: int, col: int) -> s.Stmt:
        return s.Stop(ln, col, None if self.end_of_statement() else self.string())

    def st_RUN(self, ln: int, col: int) -> s.Stmt:
        bracket = self.at("(")
        name = self.string()
        proc = self.expr() if self.accept(",") else None
        if bracket and proc is not None:
            self.expect(")")  # RUN("prog", n)
        return s.Run(ln, col, name, proc)

    def st_BASE(self, ln: int, col: int) -> s.Stmt:
        return s.Base(ln, col, self.args())

    def st_CANCEL(self, ln: int, col: int) -> s.Stmt:
        mode = None
        if self.at("("):
            (mode,) = self.args_exact(1, "CANCEL")
        return s.Cancel(ln, col, mode, self.axis_modifier())

    def st_RAPIDSTOP(self, ln: int, col: int) -> s.Stmt:
        mode = None
        if self.at("("):
            (mode,) = self.args_exact(1, "RAPIDSTOP")
        return s.RapidStop(ln, col, mode)

    def args_exact(self, n: int, what: str) -> tuple[s.Expr, ...]:
        c = self.col()
        args = self.args()
        if len(args) != n:
            raise self.error(f"{what} takes {n} argument(s), got {len(args)}", c)
        return args

    def st_VR(self, ln: int, col: int) -> s.Stmt:
        (index,) = self.args_exact(1, "VR")
        target: s.VrRef | s.Bit = s.VrRef(index)
        bit = self.bit_suffix(target)
        if isinstance(bit, s.Bit):
            target = bit
        self.expect("=")
        return s.Assign(ln, col, target, self.expr())

    def st_TABLE(self, ln: int, col: int) -> s.Stmt:
        args = self.args()
        if len(args) > 1:
            return s.TableWrite(ln, col, args[0], args[1:])
        self.expect("=")
        return s.Assign(ln, col, s.TableRef(args[0]), self.expr())

    # -- expressions -------------------------------------------------------------------

    def expr(self, min_prec: int = 1, sub: bool = True) -> s.Expr:
        """Binary operators by precedence climbing over :data:`_PRECEDENCE` (spec §9.2: equal
        precedence left to right). ``sub``: a sub-expression, one level deeper (not the right
        operand of an operator, whose level that operator counts)."""
        if sub:
            self.depth += 1
            if self.depth > MAX_NESTING:
                raise self.too_deep()
        base = self.depth if sub else self.depth + 1
        toks = self.toks
        text = toks[self.i][1]
        left = (self.unary() if text == "-" or text == "+" or text == "NOT"
                else self.primary())  # (unary's own test, saving a call)
        while True:
            op = toks[self.i][1]
            prec = _PRECEDENCE.get(op)
            if prec is None or prec < min_prec:
                self.depth = base - 1
                return left
            if op in SHIFTS and not self.dialect.shifts:
                raise self.error(f"the shift operator {op} is not Trio BASIC on the {self.model} "
                                 "model: it came with the MC4xx / MC6xx language (firmware 2.x)")
            self.i += 1
            self.nest()  # the tree of a run of operators is as deep as the run is long
            left = s.Binary(op, left, self.expr(prec + 1, sub=False))

    def unary(self) -> s.Expr:
        text = self.toks[self.i][1]
        if text != "-" and text != "+" and text != "NOT":
            return self.primary()
        if self.accept("-"):
            self.nest()
            operand = self.unary()
            self.depth -= 1
            if isinstance(operand, s.Num):
                return s.Num(-operand.value)
            return s.Unary("-", operand)
        if self.accept("+"):
            self.nest()
            operand = self.unary()
            self.depth -= 1
            return operand
        if self.accept("NOT"):
            self.nest()
            operand = self.unary()
            self.depth -= 1
            return s.Unary("NOT", operand)
        return self.primary()

    def primary(self) -> s.Expr:
        tok = self.toks[self.i]
        kind = tok[0]
        if kind == "name":
            word = tok[1]
            if word in self.special[1]:
                node = self.named_value(tok)
            else:  # named_value's first case, saving a call
                self.i += 1
                if self.dialect.arrays and self.toks[self.i][1] == "(":
                    node = s.Element(variable(word), self.call_args())
                else:
                    node = s.Local(variable(word))
            nxt = self.toks[self.i]
            if nxt[0] == "number" and nxt[1][0] == ".":
                return self.bit_suffix(node)
            return node
        if kind == "number":
            self.i += 1
            text = tok[1]
            value = float(int(text[1:], 16)) if text[0] == "$" else float(text)
            if not math.isfinite(value):
                raise self.error(f"number {text} is out of range", tok[2])
            return s.Num(value)
        if kind == "string":
            if not (self.dialect.strings or self.in_print):
                raise self.error("a string is only allowed in PRINT")
            self.i += 1
            return s.Str(tok[1][1:-1])
        if kind == "op" and tok[1] == "(":
            self.i += 1
            e = self.expr()
            self.expect(")")
            return self.bit_suffix(e)
        raise self.error(f"expected a value, found {tok[1] or 'end of line'!r}")

    def named_value(self, tok: Token) -> s.Expr:
        word = tok[1]
        self.i += 1
        if word not in self.special[1]:  # no rule below claims it: a variable (or element)
            if self.dialect.arrays and self.toks[self.i][1] == "(":
                return s.Element(variable(word), self.call_args())
            return s.Local(variable(word))
        return self.named_special(word, tok)

    def named_special(self, word: str, tok: Token) -> s.Expr:
        """A name in an expression that one of the language's sets holds (the word taken)."""
        if word == "VR":
            (index,) = self.args_exact(1, "VR")
            return s.VrRef(index)
        if word == "TABLE":
            (index,) = self.args_exact(1, "TABLE")
            return s.TableRef(index)
        if word in CONSTANTS:
            return s.Num(CONSTANTS[word])
        if word in FUNCTIONS:
            arity = FUNCTIONS[word][0]
            return s.Call(word, self.args_exact(arity, word))
        if word in BUS_FUNCTIONS:
            return s.Call(word, self.bus_args(word))
        if word in STRING_FUNCTIONS and self.dialect.strings:
            lo, hi = STRING_FUNCTIONS[word][:2]
            c = self.col()
            args = self.args()
            if not lo <= len(args) <= hi:
                want = str(lo) if lo == hi else f"{lo} or {hi}"
                raise self.error(f"{word} takes {want} arguments, got {len(args)}", c)
            return s.Call(word, args)
        if word in PARAMS:
            return self.param_ref(word, tok[2])
        if word in IO_ARGS:
            return self.io_read(word, tok[2])
        if word in NOT_SIMULATED:
            raise self.not_simulated(word, tok[2])
        if word == "HEX":
            raise self.error("HEX() is only allowed as a PRINT item", tok[2])
        if word in self.dialect.later_words and self.at("("):
            raise self.later_only(word, tok[2])
        if self.reserved(word):
            raise self.error(f"{word} is a Trio BASIC keyword, not a value", tok[2])
        if self.dialect.arrays and self.at("("):
            return s.Element(variable(word), self.call_args())
        return s.Local(variable(word))

    def param_ref(self, word: str, col: int) -> s.Param:
        axis = self.axis_modifier()
        proc = None
        if self.accept("PROC"):
            self.expect("(")
            proc = self.expr()
            self.expect(")")
        return s.Param(word, axis, proc)


# -- the statement table -------------------------------------------------------------------
# One row per statement (:mod:`motionsim.sim.trio.language.commands`): keyword(s), the parse
# handler above, the compile handler of each statement class it builds
# (:mod:`motionsim.sim.trio.language.compiler`). A new command is one row and its handlers.

_P, _C = _Line, _Compiler

#: The language of ``series2`` and ``mc2xx``: the statements every generation has.
BASE = Dialect("series2 / mc2xx", (
    Row((), None, {s.Assign: _C.st_Assign, s.Label: _C.st_Label}),  # name = e, VR(n) = e, label:
    Row(("?",), _P.st_QUERY, {}),
    Row(("PRINT",), _P.st_PRINT, {s.Print: _C.st_Print}),
    Row(("DEFPOS",), _P.st_DEFPOS, {s.DefPos: _C.st_DefPos}),
    Row(("OP",), _P.st_OP, {s.OpWrite: _C.st_OpWrite}),
    Row(("HALT",), _P.st_HALT, {s.Halt: _C.st_Halt}),
    Row(("PROCESS",), _P.st_PROCESS, {s.ProcessList: _C.st_ProcessList}),
    Row(("FOR",), _P.st_FOR, {s.For: _C.st_For}),
    Row(("NEXT",), _P.st_NEXT, {s.Next: _C.st_Next}),
    Row(("IF",), _P.st_IF, {s.If: _C.st_If, s.IfBlock: _C.st_IfBlock}),
    Row(("ELSEIF",), _P.st_ELSEIF, {s.ElseIf: _C.st_ElseIf}),
    Row(("ELSE",), _P.st_ELSE, {s.Else: _C.st_Else}),
    Row(("ENDIF",), _P.st_ENDIF, {s.EndIf: _C.st_EndIf}),
    Row(("WHILE",), _P.st_WHILE, {s.While: _C.st_While}),
    Row(("WEND",), _P.st_WEND, {s.Wend: _C.st_Wend}),
    Row(("REPEAT",), _P.st_REPEAT, {s.Repeat: _C.st_Repeat}),
    Row(("UNTIL",), _P.st_UNTIL, {s.Until: _C.st_Until}),
    Row(("WAIT",), _P.st_WAIT, {s.WaitIdle: _C.st_WaitIdle, s.WaitLoaded: _C.st_WaitLoaded,
                                s.WaitUntil: _C.st_WaitUntil}),
    Row(("WA",), _P.st_WA, {s.Wa: _C.st_Wa}),
    Row(("GOTO",), _P.st_GOTO, {s.Goto: _C.st_Goto}),
    Row(("GOSUB",), _P.st_GOSUB, {s.Gosub: _C.st_Gosub}),
    Row(("RETURN",), _P.st_RETURN, {s.Return: _C.st_Return}),
    Row(("STOP",), _P.st_STOP, {s.Stop: _C.st_Stop}),
    Row(("RUN",), _P.st_RUN, {s.Run: _C.st_Run}),
    Row(("BASE",), _P.st_BASE, {s.Base: _C.st_Base}),
    Row(("CANCEL",), _P.st_CANCEL, {s.Cancel: _C.st_Cancel}),
    Row(("RAPIDSTOP",), _P.st_RAPIDSTOP, {s.RapidStop: _C.st_RapidStop}),
    Row(("VR",), _P.st_VR, {}),  # VR(n) = e, VR(n).b = e: an Assign
    Row(("TABLE",), _P.st_TABLE, {s.TableWrite: _C.st_TableWrite}),  # TABLE(n) = e: an Assign
    Row(("ON",), _P.st_ON, {s.OnError: _C.st_OnError, s.OnBranch: _C.st_OnBranch}),
    Row(tuple(MOVE_ARGS), _P.st_move, {s.MoveCmd: _C.st_MoveCmd}),
    Row(tuple(SETUP_COMMANDS), _P.st_setup, {s.SetupCmd: _C.st_SetupCmd}),
    Row(("SCOPE",), _P.st_SCOPE, {s.ScopeCmd: _C.st_ScopeCmd}),  # TRIGGER: a set-up command
    Row(tuple(BUS_FUNCTIONS), _P.st_bus, {s.BusCall: _C.st_BusCall}),
), later_words=MC4_WORDS)

#: The MC4xx / MC6xx language (firmware 2.x, spec §11): the base table, its declarations,
#: its words reserved, string values, bit access and arrays.
MC4 = BASE.extend("mc4xx", (
    Row(("INCLUDE",), _P.st_INCLUDE, {s.Include: _C.st_Include}),
    Row(("DIM",), _P.st_DIM, {s.Dim: _C.st_Dim, s.DimList: _C.st_DimList}),
    Row(("GLOBAL",), _P.st_GLOBAL, {s.Global: _C.st_Global}),
    Row(("CONSTANT",), _P.st_CONSTANT, {s.Constant: _C.st_Constant}),
    Row(("SELECT_CASE",), _P.st_SELECT_CASE, {s.SelectCase: _C.st_SelectCase}),
    Row(("CASE",), _P.st_CASE, {s.Case: _C.st_Case}),
    Row(("END_CASE",), _P.st_END_CASE, {s.EndCase: _C.st_EndCase}),
    Row(("EXIT_LOOP",), _P.st_EXIT_LOOP, {s.ExitLoop: _C.st_ExitLoop}),
    Row(("FUNCTION",), _P.st_FUNCTION, {s.Function: _C.st_Function}),
    Row(("ENDFUNC",), _P.st_ENDFUNC, {s.EndFunc: _C.st_EndFunc}),
    Row((), None, {s.CallStmt: _C.st_CallStmt}),  # f(a, b): a library function called
), keywords=MC4_WORDS, later_words=frozenset(), strings=True, bit_access=True, arrays=True,
   shifts=True)


def dialect_of(model: str) -> Dialect:
    """The language of a model (config ``model``; :data:`MC4_MODELS` speak the MC4 one)."""
    return MC4 if model in MC4_MODELS else BASE


def parse_line(text: str, line_no: int = 1, model: str = DEFAULT_MODEL,
               dialect: Dialect | None = None) -> list[s.Stmt]:
    """The statements of one line of Trio BASIC (a command-line entry or a program line), in
    the language of ``model`` (or of ``dialect``, a statement table of one's own)."""
    return _Line(text, line_no, model, dialect).parse()


def parse_program(text: str, model: str = DEFAULT_MODEL,
                  dialect: Dialect | None = None,
                  errors: list[ParseError | NotSimulated] | None = None) -> s.Program:
    """Parse a whole program text in the language of ``model`` (series2 / mc2xx / mc4xx /
    mc6xx) or of ``dialect``; raises :class:`ParseError` at the first bad line — or, given
    ``errors`` (a list), appends each bad line's error there and leaves that line out."""
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    language = dialect or dialect_of(model)
    out: list[s.Stmt] = []
    p = _Line("", 0, model, language)
    for i, line in enumerate(lines, start=1):
        try:
            p.start(line, i)
            out.extend(p.parse())
        except (ParseError, NotSimulated) as err:
            if errors is None:
                raise
            errors.append(err)
    return s.Program(tuple(out), tuple(lines), language)


__all__ = ["BASE", "MC4", "MOVE_ARGS", "dialect_of", "parse_line", "parse_program"]
