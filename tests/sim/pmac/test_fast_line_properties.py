"""The plain-line fast path compiles a rotary line exactly as the general parser does.

``compile_line`` tries :func:`motionsim.sim.pmac.language.fast_line.fast_compile` first; these
properties
pin that, for any line (plain words, whole-line assignments, anything else), the result
(statements' expressions, operations, word count, planner short cuts) or the ``ParseError``
(message, column, text, ERR003) is the one the general path ``parse_program_line`` +
``compile_statements`` gives.
"""

from __future__ import annotations

from hypothesis import example, given, settings
from hypothesis import strategies as st
from motionsim.sim.errors import NotSimulated, ParseError
from motionsim.sim.pmac.buffers.program import compile_line, compile_statements, rotary_check
from motionsim.sim.pmac.language.fast_line import fast_compile
from motionsim.sim.pmac.language.parser import parse_program_line

_WORDS = [
    "X", "Y", "Z", "A", "B", "C", "U", "V", "W", "I", "J", "K", "R", "F", "TA", "TS", "TM",
    "DWELL", "DWE", "DELAY", "DLY", "x", "ta", "Dwell",
]  # fmt: skip
_BARE = ["LINEAR", "LIN", "RAPID", "RPD", "INC", "ABS", "CIRCLE", "CIR", "linear", "inc"]
_NUMBERS = st.one_of(
    st.integers(0, 99999).map(str),
    st.floats(0, 1e4, allow_nan=False).map(lambda v: f"{v:.4f}"),
    st.sampled_from(["0", ".5", "5.", "007", "1.", "2", "12", "$1F", "1..3", "1.2.3", "-0"]),
)
_GAP = st.sampled_from(["", "", " ", "  ", "\t"])
_ODD = st.sampled_from([
    "(", ")", ",", ":", "=", "==", ";c", "P1=", "M2==", "-", "E", "N", "INT(", "TAN(",
    "(X,Y)", "+", "..", "*", "LINE", "DLYX", "ATAN2(", '"s"', "\x01", "Q", "O",
])  # fmt: skip


def _word() -> st.SearchStrategy[str]:
    valued = st.tuples(st.sampled_from(_WORDS), _GAP, st.sampled_from(["", "", "-", "- "]),
                       _NUMBERS).map("".join)
    return st.one_of(valued, st.sampled_from(_BARE), st.sampled_from(["1", "2", "3", ""]).map(
        lambda n: "CIRCLE" + n), _ODD)


_PLAIN_LINES = st.lists(st.tuples(_GAP, _word()).map("".join), max_size=8).map("".join)
_INDEX = st.sampled_from(["1", "0", "12", "8191", "8192", "007", "2.", "1.5", "(1)", ""])
_OPERAND = st.one_of(
    _NUMBERS, st.tuples(st.sampled_from(["P", "Q", "M", "I", "p", "X", "SIN("]), _GAP, _INDEX)
    .map("".join),
)
_ASSIGNMENTS = st.tuples(
    _GAP, st.sampled_from(["P", "Q", "M", "I", "m", "q"]), _GAP, _INDEX, _GAP,
    st.sampled_from(["=", "==", "&=", "->", "=*"]), _GAP, st.sampled_from(["", "", "-", "+"]),
    _OPERAND, _GAP, st.sampled_from(["", "", "+", "-", "*", "/", "%", "&"]), _GAP,
    st.one_of(_OPERAND, st.just("")), _GAP, st.sampled_from(["", "", "", " X1", "+1", ";c"]),
).map("".join)


def _general(text: str):
    line = compile_statements(text, parse_program_line(text))
    rotary_check(line)  # a rotary line: control flow is refused as not simulated
    return line


def _outcome(fn, text: str):
    try:
        return ("line", fn(text))
    except (ParseError, NotSimulated) as e:
        return ("error", str(e), e.details, type(e))


def _check_same(text: str) -> None:
    fast = fast_compile(text)
    if fast is not None:
        general = _general(text)  # the fast path only takes lines the general path accepts
        assert fast == general
        for a, b in zip(fast.ops, general.ops, strict=True):
            assert repr(a) == repr(b)  # the same expression texts and constants, op by op
    assert _outcome(compile_line, text) == _outcome(_general, text)


@settings(max_examples=1500, deadline=None)
@given(_PLAIN_LINES)
@example("X10 Y-2.5 F5 DWELL10 X1")
@example("INC LINEAR TA10 TS0 TM50")
@example("CIRCLE1 X1 Y2 I-1 J.5 K0 R3")
@example("")
@example("  x 1 - 2 ")
@example("LIN X1 LINK2")  # the lexer reads LINK (LIST LINK's object word), not LIN K2
def test_plain_line_compiles_exactly_as_the_general_parser(text):
    _check_same(text)


@settings(max_examples=1000, deadline=None)
@given(_ASSIGNMENTS)
@example("P1=P2+1.5")
@example("M12==1")
@example("q3 = -p4 * 2")
@example("P1=4/0")
def test_assignment_line_compiles_exactly_as_the_general_parser(text):
    _check_same(text)


_AXIS_WORD = st.tuples(
    _GAP, st.sampled_from(["X", "Y", "Z", "A", "B", "C", "U", "V", "W", "x", "w", "I", "F"]),
    _GAP, st.sampled_from(["", "", "-", "- ", "+"]), _NUMBERS,
).map("".join)


@settings(max_examples=1000, deadline=None)
@given(st.lists(_AXIS_WORD, min_size=1, max_size=4), _GAP)
@example(["X1.5", " Y-2"], "")
@example(["x 1 ", "y-.5", "Z007"], " ")
@example(["X1", "Y2", "Z3", "A4"], "")
@example(["X1.2.3"], "")
@example(["X1.", "Y2"], "")
def test_axis_word_line_compiles_exactly_as_the_general_parser(words, tail):
    """Lines of nothing but axis words (the commonest streamed line, the planners' short
    cuts), with odd numbers, signs and spacing."""
    _check_same("".join(words) + tail)


@settings(max_examples=500, deadline=None)
@given(st.text(alphabet="XYZIJKRFTADWELINCBS-.0123456789 ():=;$", max_size=20))
def test_any_character_mix_compiles_or_fails_exactly_as_the_general_parser(text):
    _check_same(text)


def test_the_fast_path_takes_the_commonest_streamed_lines():
    for text in ("X1.5 Y-2", "INC LINEAR TA10 TS0 TM50", "DWELL20", "CIRCLE2 X1 Y1 I0 J1",
                 "F10 X2", "rapid z3"):
        assert fast_compile(text) is not None, text
    for text in ("P1=P2+1", "M1==1", "Q5=-2.5", "P9=M3*P2"):
        assert fast_compile(text) is not None, text
    for text in ("P1=P2+P3+1", "P1==1", "P8192=1", "P1=SIN(2)", "X(P1)", "X10:5", "INC(X)",
                 "X$10", "X10 ;c", "R"):
        assert fast_compile(text) is None, text
