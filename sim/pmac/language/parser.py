"""Text -> statements for the Turbo PMAC command language.

One compiled regular expression tokenises a line (case-insensitive); a small recursive-descent
parser turns the tokens into :mod:`motionsim.sim.pmac.language.statements`. Several commands may
share a line
(``&1 B0 R``, ``&1B0R``); they are returned left to right, each with its character span so the
terminal can store the exact text of a program line.

Whether a word is an on-line command or a program statement depends on whether this port has a
buffer open (seed 000, TSRM p295, p328): with a buffer open ``B0`` is a B-axis move and ``I100``
the I component of a circle vector; with buffers closed they point the CS at its rotary
program and query I100. ``parse_line(text, open_=...)`` follows ``OPEN ROT`` / ``CLOSE`` inside
the line itself.

Abbreviations accepted: ``DEF``/``DEFINE``, ``DEL``/``DELETE``, ``ROT``/``ROTARY``,
``GAT``/``GATHER``, ``LIN``/``LINEAR``, ``RPD``/``RAPID``, ``CIR1``/``CIRCLE1``, ``DWE``/
``DWELL``, ``DLY``/``DELAY``, ``VER``/``VERSION``. A ``;`` starts a comment.

Errors are :class:`motionsim.sim.errors.ParseError` with the 1-based ``column`` of the offending
character and ``pmac_error="ERR003"`` (data error or unrecognised command); nothing executes
when any part of a line fails to parse.
"""

from __future__ import annotations

import re
from typing import Any

from ...errors import ParseError
from ..card import card_commands, macro_station, memory_commands, mvar_defs
from . import axis_definitions, flow_words, keywords, ranges
from . import expressions as ex
from . import motor_statements as motor_st
from . import plc_statements as plc_st
from . import statements as st
from .conditions import (
    _NOT_COMPARATORS,
    COMPARATORS,
    Cond,
    any_of_all,
)
from .cs_enable import EnableCS

#: Words the lexer reads whole: the keyword table's spellings and objects, and the functions.
_WORDS = keywords.lexer_words(tuple(ex.FUNCTIONS))

_TOKEN = re.compile(
    r"\s*(?:"
    r"(?P<num>\$[0-9A-Fa-f]+|\d*\.\d+|\d+(?:\.(?!\.)\d*)?)"
    r'|(?P<str>"[^"]*")'
    r"|(?P<comment>;.*)"
    r"|(?P<word>" + keywords.lexer_pattern(_WORDS) + r"|[A-Za-z])"
    r"|(?P<op>\?\?\?|\?\?|\?|->|\.\.|==|&=|\|=|\^=|##|\$\$\$(?:\*\*\*)?|\$\*|\$"
    r"|![=<>~]|<>|>=|<=|[=&#|^+\-*/%(),:<>~\\])"
    r")",
    re.IGNORECASE | re.ASCII,
)

_FUNCS = frozenset(ex.FUNCTIONS)
_PC_PE = re.compile(r"([CE])(?![A-Za-z0-9(])", re.IGNORECASE)
_CLEAR_ALL_PLCS = re.compile(r"\s*ALL\s*PLCS(?![A-Za-z])", re.IGNORECASE)
_CLEAR_ALL = re.compile(r"\s*ALL(?![A-Za-z])", re.IGNORECASE)
#: Variable letters; ``L``: the L-variables of compiled PLCs (card/variables.py).
_VARS = frozenset("IPQML")
#: ``G{n}``, ``T{n}``, ``D{n}`` (and ``M{n}`` not followed by ``=`` / ``->`` / ``..``) in a
#: buffer: calls of PROG 10n0, 10n2, 10n3, 10n1 (TSRM p425; TUM p328; flow_statements.Call).
_CODE_CALLS = frozenset("GTD")
_ASSIGN_OPS = frozenset(["=", "==", "&=", "|=", "^="])
_NOT_M_CODE = _ASSIGN_OPS | {"->", ".."}

_ERR = "ERR003"

Token = tuple[str, str, int, int]  # (kind, text upper-cased, start, end)


def tokenize(text: str) -> list[Token]:
    """Tokens of one line; raises ParseError at the first character no token matches."""
    out: list[Token] = []
    pos, n = 0, len(text)
    match = _TOKEN.match
    while pos < n:
        m = match(text, pos)
        if m is None or m.end() == pos:
            if text[pos:].strip() == "":
                break
            col = pos + 1 + (len(text[pos:]) - len(text[pos:].lstrip()))
            raise ParseError(
                f"unexpected character {text[col - 1]!r}", column=col, text=text, pmac_error=_ERR
            )
        kind = m.lastgroup
        if kind is None:  # only whitespace left
            break
        if kind != "comment":
            out.append((kind, m.group(kind).upper(), m.start(kind), m.end(kind)))
        pos = m.end()
    return out


def _number(tok: str) -> float:
    if tok.startswith("$"):
        return float(int(tok[1:], 16))
    return float(tok)


class _Parser:
    def __init__(self, text: str, open_: bool) -> None:
        self.text = text
        deep = ex.too_deep(text)  # before tokenising a line that can only be refused
        if deep is not None:
            raise ParseError(f"expression nested deeper than {ex.MAX_NESTING} levels (the "
                             "limit)", column=deep, text=text, pmac_error=_ERR)
        self.toks = tokenize(text)
        self.i = 0
        self.open = open_
        #: Nesting level of the expression being parsed (``ex.MAX_NESTING`` at most).
        self.depth = 0
        #: A SPLINE1 / SPLINE2 word came earlier on this line (no PVT-style velocities).
        self.spline_line = False
        #: The keyword row whose builder runs now (its ``objects`` for ``OPEN`` / ``LIST``...).
        self.row: keywords.Keyword | None = None

    # -- token helpers --------------------------------------------------------------------

    def peek(self, k: int = 0) -> Token | None:
        j = self.i + k
        return self.toks[j] if j < len(self.toks) else None

    def error(self, message: str, tok: Token | None = None) -> ParseError:
        if tok is None:
            tok = self.peek()
        col = tok[2] + 1 if tok is not None else len(self.text.rstrip()) + 1
        return ParseError(message, column=col, text=self.text, pmac_error=_ERR)

    def take(self) -> Token:
        tok = self.peek()
        if tok is None:
            raise self.error("unexpected end of line")
        self.i += 1
        return tok

    def at(self, kind: str, text: str | None = None) -> bool:
        tok = self.peek()
        return tok is not None and tok[0] == kind and (text is None or tok[1] == text)

    def at_op(self, k: int, text: str) -> bool:
        """Is the token ``k`` ahead the operator ``text``?"""
        tok = self.peek(k)
        return tok is not None and tok[0] == "op" and tok[1] == text

    def skip_to(self, end: int) -> None:
        """Take every token that starts before character ``end`` (a family module parsed the
        text itself)."""
        while self.i < len(self.toks) and self.toks[self.i][2] < end:
            self.i += 1

    def match_text(self, pattern: re.Pattern[str]) -> re.Match[str] | None:
        """Match ``pattern`` on the text right after the last token taken; on a match, the
        tokens it covers are taken (for words the tokenizer splits into letters:
        ``RHX:`` is ``R`` ``H`` ``X`` ``:``)."""
        m = pattern.match(self.text, self.toks[self.i - 1][3])
        if m is not None:
            while self.i < len(self.toks) and self.toks[self.i][2] < m.end():
                self.i += 1
        return m

    def expect_op(self, text: str) -> Token:
        if not self.at("op", text):
            raise self.error(f"expected {text!r}")
        return self.take()

    def integer(self) -> int:
        tok = self.peek()
        if tok is None or tok[0] != "num":
            raise self.error("expected a number")
        self.i += 1
        v = _number(tok[1])
        if v != int(v) or v < 0:
            raise self.error("expected a whole number", tok)
        return int(v)

    # -- expressions ----------------------------------------------------------------------

    def expression(self) -> ex.Expr:
        first = self.term()
        rest: list[tuple[str, ex.Expr]] = []
        while self.at("op") and self.peek()[1] in ex.LOW:  # type: ignore[index]
            op = self.take()[1]
            rest.append((op, self.term()))
        return ex.chain(first, rest) if rest else first

    def term(self) -> ex.Expr:
        first = self.unary()
        rest: list[tuple[str, ex.Expr]] = []
        while self.at("op") and self.peek()[1] in ex.HIGH:  # type: ignore[index]
            op = self.take()[1]
            rest.append((op, self.unary()))
        return ex.chain(first, rest) if rest else first

    def nest(self, tok: Token | None) -> None:
        """One more level of nesting (``(``, a unary ``-``); ERR003 past ``MAX_NESTING``."""
        self.depth += 1
        if self.depth > ex.MAX_NESTING:
            raise self.error(
                f"expression nested deeper than {ex.MAX_NESTING} levels (the limit)", tok)

    def unary(self) -> ex.Expr:
        tok = self.peek()
        if tok is not None and tok[0] == "op" and tok[1] == "-":
            self.i += 1
            self.nest(tok)
            inner = self.unary()
            self.depth -= 1
            return ex.negate(inner)
        if tok is not None and tok[0] == "op" and tok[1] == "+":
            raise self.error("unary plus is not allowed", tok)
        return self.primary()

    def primary(self) -> ex.Expr:
        tok = self.peek()
        if tok is None:
            raise self.error("expected a value")
        kind, word = tok[0], tok[1]
        if kind == "num":
            self.i += 1
            return ex.constant(_number(word), word)
        if kind == "op" and word == "(":
            return self.parenthesised()
        if kind == "word" and word in _VARS:
            self.i += 1
            return ex.variable(word, self.index())
        if kind == "word" and word in _FUNCS:
            self.i += 1
            if not self.at("op", "("):
                raise self.error(f"{word} needs (argument)")
            return ex.function(word, self.parenthesised())
        raise self.error("expected a value", tok)

    def parenthesised(self) -> ex.Expr:
        self.nest(self.peek())
        self.expect_op("(")
        inner = self.expression()
        self.expect_op(")")
        self.depth -= 1
        return ex.paren(inner)

    def index(self) -> ex.Expr:
        """A variable number: a constant or ``(expression)``."""
        tok = self.peek()
        if tok is not None and tok[0] == "num":
            self.i += 1
            v = _number(tok[1])
            if v != int(v) or not 0 <= v <= 8191:
                raise self.error("variable number must be 0..8191", tok)
            return ex.constant(v, tok[1])
        if tok is not None and tok[0] == "op" and tok[1] == "(":
            return self.parenthesised()
        raise self.error("expected a variable number", tok)

    def value(self) -> ex.Expr:
        """A word's value: a (signed) constant or a parenthesised expression."""
        tok = self.peek()
        if tok is not None and tok[0] == "op" and tok[1] == "-":
            self.i += 1
            self.nest(tok)
            inner = self.value()
            self.depth -= 1
            return ex.negate(inner)
        if tok is not None and tok[0] == "num":
            self.i += 1
            return ex.constant(_number(tok[1]), tok[1])
        if tok is not None and tok[0] == "op" and tok[1] == "(":
            return self.parenthesised()
        raise self.error("expected a value", tok)

    def has_value(self) -> bool:
        tok = self.peek()
        if tok is None:
            return False
        if tok[0] == "num":
            return True
        if tok[0] == "op" and tok[1] == "(":
            return True
        if tok[0] == "op" and tok[1] == "-":
            nxt = self.peek(1)
            return nxt is not None and (nxt[0] == "num" or (nxt[0] == "op" and nxt[1] == "("))
        return False

    # -- conditions (TUM p252; PUM p162) --------------------------------------------------

    def condition(self) -> Cond:
        """``{simple} [AND|OR {simple}]...`` inside an IF / WHILE's parentheses, read from the
        tokens like any expression: so ``P174!=0ANDP176!=0`` (the card's own LIST form, no
        blanks) is two simple conditions. AND binds tighter than OR."""
        groups = [[self.simple_condition()]]
        while self.at("word") and self.peek()[1] in ("AND", "OR"):  # type: ignore[index]
            if self.take()[1] == "OR":
                groups.append([])
            groups[-1].append(self.simple_condition())
        return any_of_all(groups)

    def simple_condition(self) -> Cond:
        """``{expression} {comparator} {expression}``."""
        start = self.i
        try:
            left = self.expression()
        except ParseError:
            self._parenthesised_condition(start)
            raise
        tok = self.peek()
        if tok is None or tok[0] != "op" or tok[1] not in COMPARATORS:
            if tok is not None and tok[0] == "op" and tok[1] in _NOT_COMPARATORS:
                raise self.error(f"comparator {tok[1]!r} is not PMAC syntax", tok)
            raise self.error("expected a comparison (= != > !> < !< ~ !~)", tok)
        self.i += 1
        right = self.expression()
        f = COMPARATORS[tok[1]]
        return lambda v, c: f(left(v, c), right(v, c))

    def _parenthesised_condition(self, start: int) -> None:
        """TUM p252: parentheses around the simple conditions of a condition are illegal
        (``IF((P1>-20) AND (P1<20))``); inside expressions they are fine. Raise that error when
        the tokens from ``start`` open a parenthesis holding a comparator."""
        toks = self.toks
        if start >= len(toks) or toks[start][:2] != ("op", "("):
            return
        depth = 0
        for tok in toks[start:]:
            if tok[0] != "op":
                continue
            if tok[1] == "(":
                depth += 1
            elif tok[1] == ")":
                depth -= 1
                if depth == 0:
                    return
            elif depth == 1 and tok[1] in COMPARATORS:
                raise self.error("no parentheses around a simple condition: write "
                                 "(P1>-20 AND P1<20), not ((P1>-20) AND (P1<20))", toks[start])

    # -- statements -----------------------------------------------------------------------

    def statements(self, until_close: bool = False) -> list[tuple[Any, int, int]]:
        out: list[tuple[Any, int, int]] = []
        while self.peek() is not None:
            start = self.peek()[2]  # type: ignore[index]
            try:
                stmt = self.statement()
            except ParseError as e:
                # where the failing statement began (0-based), for not_simulated.which
                e.statement_start = start  # type: ignore[attr-defined]
                raise
            end = self.toks[self.i - 1][3]
            if isinstance(stmt, (st.OpenRotary, st.OpenProgram)) or getattr(
                stmt, "opens_buffer", False
            ):
                self.open = True
            elif isinstance(stmt, st.Close):
                self.open = False
                if until_close:
                    out.append((stmt, start, end))
                    return out
            out.append((stmt, start, end))
        return out

    def statement(self) -> Any:
        tok = self.take()
        kind, word = tok[0], tok[1]
        if kind == "num":
            # A bare constant is P0 = constant (TUM p244).
            return st.Assign(st.VarRef("P", ex.constant(0.0, "0")), "=", ex.constant(_number(word)))
        if kind == "str":
            raise self.error("unexpected text string", tok)
        if kind == "op":
            return self.op_statement(tok)
        return self.word_statement(tok)

    def op_statement(self, tok: Token) -> Any:
        word = tok[1]
        if word == "&":
            return st.AddressCS(self.integer() if self.at("num") else None)
        if word == "#":
            if not self.at("num"):
                return st.AddressMotor(None)
            motor = self.integer()
            if self.at("op", "->"):
                return self.axis_definition(motor, self.take())
            return st.AddressMotor(motor)
        if word in ("?", "??", "???"):
            return st.Query(word)
        if word == "##":
            return motor_st.MotorGroup(self.integer() if self.at("num") else None)
        if word in ("$$$", "$$$***"):
            return card_commands.Reset(factory=word == "$$$***")
        if word in ("$", "$*"):
            return motor_st.Enable(absolute=word == "$*")
        if word == "/":
            return st.StopAtEnd()
        if word == "\\":
            return st.QuickStop()
        if word == "%":
            if self.at("num"):
                return st.FeedOverride(_number(self.take()[1]))
            return st.Query("%")
        raise self.error(f"unexpected {word!r}", tok)

    def axis_definition(self, motor: int, arrow: Token) -> Any:
        """After ``#{n}->``: a definition or the query (:mod:`.axis_definitions`)."""
        try:
            definition, end = axis_definitions.parse(self.text, arrow[3])
        except ParseError as e:
            e.statement_start = arrow[2]  # type: ignore[attr-defined]
            raise
        while self.i < len(self.toks) and self.toks[self.i][2] < end:
            self.i += 1
        return axis_definitions.AxisDefinition(motor, definition)

    def word_statement(self, tok: Token) -> Any:
        """A command word: dispatched through the keyword table (:mod:`.keywords`); a single
        letter or an unknown word goes to :meth:`letter_statement`."""
        word = tok[1]
        row = keywords.BY_SPELLING.get(word) or keywords.lookup(word)
        if row is not None:
            if not row.simulated or row.builds is None:
                raise self.not_simulated(row.name, tok)
            self.row = row
            return row.builds(self, tok)
        if word in _FUNCS:
            raise self.error(f"{word} is a function, not a command", tok)
        return self.letter_statement(tok)

    def not_simulated(self, name: str, tok: Token) -> ParseError:
        """The error for a valid command motionsim does not simulate: ERR003 on the wire,
        ``not_simulated`` naming it on the REST terminal."""
        e = self.error(f"{name} is valid Turbo PMAC but not simulated", tok)
        e.details["not_simulated"] = name
        return e

    def clear(self) -> Any:
        """``CLEAR`` (the open buffer) or ``CLEAR ALL PLCS``; ``CLEAR ALL`` is not simulated."""
        if self.match_text(_CLEAR_ALL_PLCS) is not None:
            return plc_st.ClearAllPlcs()
        if _CLEAR_ALL.match(self.text, self.toks[self.i - 1][3]):
            raise self.not_simulated("CLEAR ALL", self.toks[self.i - 1])
        return plc_st.Clear()

    def plc_number(self) -> int:
        tok = self.peek()
        n = self.integer()
        if n >= plc_st.N_PLCS:
            raise self.error(f"no PLC {n} (0..{plc_st.N_PLCS - 1})", tok)
        return n

    def number_list(self, lo: int, hi: int, what: str) -> tuple[int, ...]:
        """``{n}[,{n}...]`` or ``{n}..{m}``, each in ``lo..hi`` (motor lists: ``HOMEZ1,2,3``)."""
        def one() -> int:
            tok = self.peek()
            n = self.integer()
            if not lo <= n <= hi:
                raise self.error(f"no {what} {n} ({lo}..{hi})", tok)
            return n

        out = [one()]
        if self.at("op", ".."):
            self.take()
            tok = self.peek()
            last = one()
            if last < out[0]:
                raise self.error(f"bad {what} range", tok)
            return tuple(range(out[0], last + 1))
        while self.at("op", ","):
            self.take()
            out.append(one())
        return tuple(out)

    def plc_list(self) -> tuple[int, ...]:
        """``PLC n[,n...]`` or ``PLC n..m`` after ENABLE / DISABLE."""
        what = self.take()
        if what[1] not in ("PLC", "PLCC"):
            raise self.error("expected PLC", what)
        first = self.plc_number()
        if self.at("op", ".."):
            self.take()
            tok = self.peek()
            last = self.plc_number()
            if last < first:
                raise self.error("bad PLC range", tok)
            return tuple(range(first, last + 1))
        out = [first]
        while self.at("op", ","):
            self.take()
            out.append(self.plc_number())
        return tuple(out)

    def axis_list(self, radius: bool = False) -> tuple[str, ...] | None:
        """``({axis}[,{axis}...])``; with ``radius`` ``R`` too (``INC(R)`` / ``ABS(R)``, the
        circle centre vectors, TSRM p442)."""
        if not self.at("op", "("):
            return None
        self.take()
        axes: list[str] = []
        while True:
            tok = self.take()
            if tok[0] != "word" or len(tok[1]) != 1 or not (
                    tok[1] in st.AXES or (radius and tok[1] == "R")):
                raise self.error("expected an axis letter" + (" or R" if radius else ""), tok)
            axes.append(tok[1])
            if self.at("op", ","):
                self.take()
                continue
            self.expect_op(")")
            return tuple(axes)

    def letter_statement(self, tok: Token) -> Any:
        word = tok[1]
        online = self.online_letter(word)
        if online is not None:
            return online
        if word == "J" and motor_st.is_jog(self):
            return motor_st.parse_jog(self)
        has_value = self.has_value()
        if word == "K" and not has_value:
            return motor_st.Kill()
        if word == "O" and has_value and not self.open:
            return motor_st.OpenLoop(self.value_const(tok))
        if word == "M" and self.open and self._m_code():
            return self.code_call(tok)
        if word in _VARS and has_value and not (word == "I" and self.open and self._i_vector()):
            return self.variable_statement(word)
        if not has_value:
            if word == "R":
                return st.Run()
            if word == "S":
                return st.Step()
            if word == "Q":
                return st.Quit()
            if word == "A":
                return st.Abort()
            if word == "H":
                return st.Hold()
            if word == "E":
                return EnableCS()
            if word in ("P", "V", "F"):
                return st.Query(word)
            raise self.error(f"{word} needs a value", tok)
        if word == "B" and not self.open:
            return st.ProgramPointer(self.value_const(tok))
        if word in st.AXES:
            value = self.value()
            if self.at("op", "^"):  # TSRM "{axis}{data}^{data}": RAPID move until trigger
                raise self.not_simulated("move until trigger ({axis}{data}^{data})", tok)
            if self.at("op", ":"):
                if self.spline_line:
                    raise self.error("SPLINE: an axis word takes no velocity")
                self.take()
                if not self.has_value():
                    raise self.error("PVT: expected the end velocity after ':'")
                return st.AxisWord(word, value, self.value())
            return st.AxisWord(word, value)
        if word in ("I", "J", "K", "R"):
            return st.VectorWord(word, self.value())
        if word == "F":
            return st.Modal("F", self.value())
        if word in ("N", "O"):
            return st.Label(word, self.integer())
        if word in _CODE_CALLS:  # a program statement: ERR005 with no buffer open
            return self.code_call(tok)
        raise self.error(f"unrecognised command {word!r}", tok)

    def _m_code(self) -> bool:
        """Is ``M`` here an M-code (``M03``), not an M-variable (``M1=``, ``M1->``)?"""
        num, after = self.peek(), self.peek(1)
        if num is None or num[0] != "num":
            return False
        return after is None or not (after[0] == "op" and after[1] in _NOT_M_CODE)

    def code_call(self, tok: Token) -> Any:
        """``G{data}`` / ``M{data}`` / ``T{data}`` / ``D{data}`` and the letters after it (its
        arguments): a subroutine call (:class:`~.flow_statements.Call` with ``code``)."""
        value = self.value()
        if value.const is not None and not 0 <= value.const < 1000:
            raise self.error(f"{tok[1]}-code 0..999.999", tok)
        return flow_words.code_call(self, tok, value)

    def online_letter(self, word: str) -> Any:
        """On-line commands whose word the tokenizer splits into letters: ``PC`` / ``PE``
        (:mod:`.program_counter`), ``R[H]{space}:`` and ``W{space}:``
        (:mod:`.memory_commands`); None when the letter starts none of them."""
        if word == "P":
            m = self.match_text(_PC_PE)
            if m is not None:
                return st.ProgramCounter(executing=m.group(1).upper() == "E")
        elif word == "R":
            m = self.match_text(memory_commands.READ_HEAD)
            if m is not None:
                return memory_commands.parse_read(self, m)
        elif word == "W":
            m = self.match_text(memory_commands.WRITE_HEAD)
            if m is not None:
                return memory_commands.parse_write(self, m)
        elif word == "M":
            m = self.match_text(macro_station.HEAD)
            if m is not None:
                return macro_station.parse(m, self.text)
        return None

    def pset_axes(self) -> tuple[tuple[str, ex.Expr], ...]:
        """``PSET``'s ``{axis}{data}`` pairs, at least one (TSRM p31)."""
        axes: list[tuple[str, ex.Expr]] = []
        while True:
            tok = self.peek()
            if tok is None or tok[0] != "word" or len(tok[1]) != 1 or tok[1] not in st.AXES:
                if axes:
                    return tuple(axes)
                raise self.error("PSET needs {axis}{data}, e.g. PSET X0", tok)
            self.i += 1
            if not self.has_value():
                raise self.error(f"PSET: expected a value after {tok[1]}")
            axes.append((tok[1], self.value()))

    def pvt_time(self) -> ex.Expr:
        """``PVT{t}``'s time; a constant must lie in the move-time register's range
        (0, 4095.9998] ms (TSRM p463, p58; ERR003 otherwise ``[INF]``)."""
        tok = self.peek()
        if not self.has_value():
            raise self.error("PVT needs the segment time in ms")
        t = self.value()
        if t.const is not None and not 0 < t.const <= 4095.9998:
            raise self.error("PVT segment time must be > 0 and at most 4095.9998 ms", tok)
        return t

    def _i_vector(self) -> bool:
        """With a buffer open, ``I100`` is a vector word unless it is an assignment."""
        tok = self.peek()
        k = 1
        if tok is not None and tok[0] == "op" and tok[1] == "(":  # I({expr})= (TUM p243)
            depth = 0
            for k in range(len(self.toks) - self.i):
                t = self.peek(k)
                depth += (t[1] == "(") - (t[1] == ")") if t[0] == "op" else 0  # type: ignore[index]
                if depth == 0:
                    break
            k += 1
        elif tok is None or tok[0] != "num":
            return True
        else:  # I{n}..{m}= and I{n},{count}[,{step}]= are range assignments (ranges.py)
            while (self.peek(k) is not None and self.peek(k)[1] in (",", "..")  # type: ignore[index]
                   and self.peek(k + 1) is not None and self.peek(k + 1)[0] == "num"):  # type: ignore[index]
                k += 2
        nxt = self.peek(k)
        return not (nxt is not None and nxt[0] == "op" and nxt[1] in _ASSIGN_OPS)

    def value_const(self, tok: Token) -> float:
        v = self.value()
        if v.const is None:
            raise self.error("expected a constant", tok)
        return v.const

    def variable_statement(self, kind: str) -> Any:
        index = self.index()
        op = self.peek()
        if op is not None and op[0] == "op" and op[1] in _ASSIGN_OPS:
            self.i += 1
            if op[1] == "=" and kind == "I" and self.at("op", "*"):
                self.take()
                n = self._const_index(index, op)
                return st.VarDefault(n, n)
            if op[1] != "=" and kind != "M":
                raise self.error("synchronous assignment is for M-variables only", op)
            return st.Assign(st.VarRef(kind, index), op[1], self.expression())
        if op is not None and op[0] == "op" and op[1] == "->" and kind in "ML":
            self.i += 1
            n = self._const_index(index, op)
            return self.m_definition(n, n, op, kind)
        if index.const is None and not self.open:
            return ranges.IndirectQuery(kind, index)  # P(P1+10)
        first = self._const_index(index, op)
        if op is not None and op[0] == "op" and op[1] == "..":
            self.i += 1
            last = self.integer()
            if last < first or last > 8191:
                raise self.error("bad variable range", self.toks[self.i - 1])
            if kind in "ML" and self.at("op", "->"):
                return self.m_definition(first, last, self.take(), kind)
            if self.at("op", "=") and (nxt := self.peek(1)) is not None and nxt[1] == "*":
                if kind != "I":
                    raise self.error("=* is for I-variables only")
                self.i += 2
                return st.VarDefault(first, last)
            return self.range_value(kind, first, last, None, 1)
        if op is not None and op[0] == "op" and op[1] == ",":
            self.i += 1
            count = self.integer()
            step = 1
            if self.at("op", ","):
                self.take()
                step = self.integer()
            if first + step * (count - 1) > 8191:
                raise self.error("variable range goes past 8191", self.toks[self.i - 1])
            return self.range_value(kind, first, None, count, step)
        return st.VarQuery(kind, first)

    def range_value(self, kind: str, first: int, last: int | None, count: int | None,
                    step: int) -> Any:
        """After a range ``{a}..{b}`` / ``{n},{count},{step}``: ``={expr}`` assigns them all
        (:mod:`.ranges`), else the query."""
        if self.at("op", "="):
            self.take()
            return ranges.RangeAssign(kind, ranges.numbers(first, last, count, step),
                                      self.expression())
        if last is not None:
            return st.VarQuery(kind, first, last=last)
        return st.VarQuery(kind, first, count=count, step=step)

    def m_definition(self, first: int, last: int, arrow: Token, kind: str = "M") -> Any:
        """After ``M{n}[..{m}]->`` (or ``L{n}->``): a definition written right after the
        arrow (:mod:`motionsim.sim.pmac.card.mvar_defs`), else the query ``M{n}->``."""
        m = mvar_defs.DEFINITION_TEXT.match(self.text, arrow[3])
        if m is None:
            return st.MDefinitionQuery(first, None if last == first else last, kind)
        try:
            definition = mvar_defs.parse(m.group())
        except mvar_defs.DefinitionError as e:
            raise ParseError(
                f"M-variable definition: {e}", column=arrow[3] + e.column, text=self.text,
                pmac_error=_ERR,
            ) from None
        while self.i < len(self.toks) and self.toks[self.i][2] < m.end():
            self.i += 1
        return mvar_defs.MDefine(first, last, definition, kind)

    def _const_index(self, index: ex.Expr, tok: Token | None) -> int:
        if index.const is None:
            raise self.error("a constant variable number is needed here", tok)
        return int(index.const)


def parse_line(text: str, open_: bool = False,
               until_close: bool = False) -> list[tuple[Any, int, int]]:
    """Statements of one terminal line with their ``(start, end)`` character spans.

    Args:
        text: the line as typed.
        open_: whether this port holds a program buffer open at the start of the line.
        until_close: stop after a ``CLOSE`` (the rest of the line is on-line text for the
            terminal, not program text: a PLC's entry).

    Raises:
        ParseError: with ``column`` (1-based) and ``pmac_error="ERR003"``.
    """
    return _Parser(text, open_).statements(until_close)


def parse_expression(text: str) -> ex.Expr:
    """One whole expression (``P1+2*M3``); used for PLC conditions.

    Raises:
        ParseError: with ``column`` (1-based), ERR003; also when text follows the expression.
    """
    p = _Parser(text, False)
    expr = p.expression()
    if p.peek() is not None:
        raise p.error("unexpected text after the expression")
    return expr


def parse_program_line(text: str) -> list[Any]:
    """The program statements of one rotary-buffer line (as with the buffer open).

    Raises:
        ParseError: bad text, or an on-line command (``R``, ``&2``...) inside the line.
    """
    out: list[Any] = []
    for stmt, start, _end in parse_line(text, open_=True):
        if not isinstance(stmt, st.PROGRAM_TYPES):
            raise ParseError(
                f"{type(stmt).__name__} is an on-line command, not a program statement",
                column=start + 1,
                text=text,
                pmac_error=_ERR,
            )
        out.append(stmt)
    return out


__all__ = ["parse_expression", "parse_line", "parse_program_line", "tokenize"]
