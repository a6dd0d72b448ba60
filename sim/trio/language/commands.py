"""The Trio BASIC statement table: one row per statement, a dialect = a table of rows.

A :class:`Row` is one statement of the language: the keyword(s) that start it, the parse
function that reads the rest of it (called with the parser, the line and the column, the
keyword already taken) and, for each statement class that function can build, the compile
function that turns it into operations (called with the compiler and the statement). Both are
direct references to the handlers, so a reader follows a keyword to its code without a
``getattr`` name game. A row with no keyword holds statements that start otherwise (an
assignment, a label).

A :class:`Dialect` is a model generation's language: its rows, the words it reserves beyond
the common keywords, and the expression features it has (string values, bit access ``v.n``,
array elements). The MC4xx / MC6xx language (firmware 2.x, spec §11) is the base table
:meth:`extended <Dialect.extend>` by the rows and features it adds, as one dialect of a SQL
parser extends another; the base dialect names the words a later generation made keywords, so
it can answer "this came with MC4xx" instead of a bare syntax error. The rows themselves are
written beside their handlers, at the foot of :mod:`motionsim.sim.trio.language.parser`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any

from . import statements as s

#: ``(parser, line, column) -> statement``: the keyword is taken (``parser.word`` holds it).
ParseFn = Callable[[Any, int, int], s.Stmt]
#: ``(compiler, statement) -> None``: emits the statement's operations.
CompileFn = Callable[[Any, Any], None]


@dataclass(frozen=True)
class Row:
    """One statement: ``words`` -> ``parse`` -> ``compiles[type(statement)]``."""

    words: tuple[str, ...]
    parse: ParseFn | None
    compiles: Mapping[type[s.Stmt], CompileFn]


@dataclass(frozen=True)
class Dialect:
    """A generation's Trio BASIC: its statement rows and expression features."""

    name: str
    rows: tuple[Row, ...]
    #: Words this dialect reserves beyond the common keywords (never a variable name).
    keywords: frozenset[str] = frozenset()
    #: Words a later generation made keywords: here ordinary names, and as a statement the
    #: syntax error that names the generation they came with.
    later_words: frozenset[str] = frozenset()
    #: String values outside PRINT, and the string functions (LEN, MID ...; spec §11.7).
    strings: bool = False
    #: ``value.n``, bit n of a value (spec §11.8).
    bit_access: bool = False
    #: ``name(i)``, an element of a DIM array (spec §11.2).
    arrays: bool = False
    #: The shift operators ``<<`` and ``>>`` (issue 32).
    shifts: bool = False
    parsers: dict[str, ParseFn] = field(init=False, repr=False, compare=False)
    compilers: dict[type[s.Stmt], CompileFn] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        parsers: dict[str, ParseFn] = {}
        compilers: dict[type[s.Stmt], CompileFn] = {}
        for row in self.rows:
            for word in row.words:
                if word in parsers:
                    raise ValueError(f"{self.name}: {word} has two rows")
                if row.parse is not None:
                    parsers[word] = row.parse
            for cls, fn in row.compiles.items():
                if cls in compilers:
                    raise ValueError(f"{self.name}: {cls.__name__} is compiled by two rows")
                compilers[cls] = fn
        object.__setattr__(self, "parsers", parsers)
        object.__setattr__(self, "compilers", compilers)

    def extend(self, name: str, rows: Iterable[Row], **features: Any) -> Dialect:
        """This dialect plus ``rows`` (a word or statement class already here is an error:
        an extension adds, it does not redefine) and the ``features`` it changes."""
        return replace(self, name=name, rows=self.rows + tuple(rows), **features)


__all__ = ["CompileFn", "Dialect", "ParseFn", "Row"]
