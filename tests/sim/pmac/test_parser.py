"""Text -> statements (spec §3, §10; TUM p248; TSRM p486-489)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as hs
from motionsim.sim.errors import ParseError
from motionsim.sim.pmac.buffers.program import compile_line
from motionsim.sim.pmac.card.variables import Variables
from motionsim.sim.pmac.language import statements as st
from motionsim.sim.pmac.language.parser import parse_line


def kinds(text, open_=False):
    return [type(s).__name__ for s, _, _ in parse_line(text, open_)]


def test_several_commands_on_one_line():
    assert kinds("&1 B0 R") == ["AddressCS", "ProgramPointer", "Run"]
    assert kinds("&1B0R") == ["AddressCS", "ProgramPointer", "Run"]


def test_case_insensitive_and_abbreviations():
    assert kinds("def rot 600") == kinds("DEFINE ROTARY 600") == ["DefineRotary"]
    assert kinds("DEL GAT") == ["DeleteGather"]
    assert kinds("open rot") == ["OpenRotary"]


def test_open_changes_the_meaning_of_i_and_b_words():
    """Seed 000 / TSRM p295, p328."""
    assert kinds("I100 B0") == ["VarQuery", "ProgramPointer"]
    assert kinds("I100 B0", open_=True) == ["VectorWord", "AxisWord"]
    assert kinds("OPEN ROT I100 CLOSE I100") == ["OpenRotary", "VectorWord", "Close", "VarQuery"]
    assert kinds("I100=5", open_=True) == ["Assign"]


def test_variable_forms():
    (q, _, _), = parse_line("I16..17")
    assert q == st.VarQuery("I", 16, last=17)
    (d, _, _), = parse_line("I16=*")
    assert d == st.VarDefault(16, 16)
    (a, _, _), = parse_line("M1==P2+1")
    assert a.op == "==" and a.target.kind == "M"
    assert kinds("M1&=1 M1|=2 M1^=3") == ["Assign"] * 3


def test_synchronous_assignment_is_for_m_variables_only():
    with pytest.raises(ParseError) as e:
        parse_line("P1==1")
    assert e.value.column == 3


def test_bare_constant_is_p0():
    """TUM p244: a bare constant ``342`` is ``P0=342``."""
    (a, _, _), = parse_line("342")
    assert a.target.kind == "P" and a.value.const == 342.0


def test_program_line_spans_and_motor_definition():
    spans = [(type(s).__name__, a, b) for s, a, b in parse_line("#1->X  &2", False)]
    assert spans == [("AxisDefinition", 0, 5), ("AddressCS", 7, 9)]


def test_parse_error_column():
    with pytest.raises(ParseError) as e:
        parse_line("X10 Y20 @")
    assert (e.value.column, e.value.pmac_error) == (9, "ERR003")
    with pytest.raises(ParseError) as e:
        parse_line("DEFINE FOO")
    assert e.value.column == 8


def evaluate(text: str, **p: float) -> float:
    v = Variables(lambda *a: None)
    for k, val in p.items():
        v.write("P", int(k[1:]), val)
    line = compile_line(f"P100={text}")
    _, _, idx, _, expr = line.ops[0]
    return expr(v, 1)


@pytest.mark.parametrize(
    "text, value",
    [
        ("1+2*3", 7),
        ("(1+2)*3", 9),
        ("10*2/3", pytest.approx(6.666666667)),
        ("2+6&3", 4),  # & is a high-priority operator: 2 + (6&3)
        ("11%-4", 3),
        ("-11%-4", -3),
        ("3%-2.5", -2),
        ("-3%-2.5", 2),
        ("7%0", 0),
        ("2^1", 3),
        ("2^2", 0),
        ("5^7", 2),
        ("$AA^$55", 0xFF),
        ("3^-3", -2),
        ("0.5^0.875", 0.375),
        ("1/0", 2.0**47),
        ("SIN(30)", pytest.approx(0.5)),
        ("INT(-2.5)", -3),
        ("P(1+1)*2", 6),
    ],
)
def test_arithmetic_as_the_manual_defines_it(text, value):
    """Spec §10 / TSRM p486-489 worked examples."""
    assert evaluate(text, P2=3) == value


def test_unary_plus_is_rejected():
    """TSRM p486: ``P1=+P2`` is an error."""
    with pytest.raises(ParseError):
        parse_line("P1=+P2")


def test_integer_m_variable_target_rounds(rig):
    """TSRM p487: ``M1=10*2/3`` gives 7."""
    rig.ok("M1=10*2/3")
    assert rig.c.get_variable("M1") == 7


_ALPHABET = "XYZABIJKRPQMTSFDLNOCEHUVW0123456789.$-+*/%&|^=()?#,;\" ><@!_"


@settings(max_examples=400, deadline=None)
@given(hs.text(alphabet=_ALPHABET, max_size=30), hs.booleans())
def test_any_text_parses_or_raises_a_positioned_parse_error(text, open_):
    """hpack-style property: any input parses or raises our positioned error, nothing else."""
    try:
        out = parse_line(text, open_)
    except ParseError as e:
        assert e.pmac_error == "ERR003"
        assert e.column is not None and 1 <= e.column <= len(text) + 1
        return
    for _stmt, a, b in out:
        assert 0 <= a < b <= len(text)
