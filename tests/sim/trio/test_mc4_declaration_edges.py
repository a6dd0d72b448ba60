"""Re-declaring shared names and indexing what is no array (spec trio.md §11.4, DIM and
CONSTANT ``[BK]``): the same CONSTANT twice is allowed, another value is refused naming both,
a DIM name cannot become a CONSTANT, and ``name(i) =`` of an undeclared name says it is no
array."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError

from tests.sim.trio.test_mc4_declarations import mc4, refused


def test_the_same_constant_twice_is_one_constant():
    c = mc4()
    c.store_program("P", "CONSTANT lim, 5\nCONSTANT lim, 5\nVR(0)=lim\n")
    assert c.program_names() == ["P"]


@pytest.mark.parametrize(("text", "message"), [
    ("CONSTANT lim, 5\nCONSTANT lim, 6\n",
     "LIM is already CONSTANT 5; a shared name cannot be declared again as CONSTANT 6"),
    ("DIM lim AS INTEGER\nCONSTANT lim, 6\n", "LIM is already a local (DIM) of this program"),
])
def test_a_shared_name_redeclared_otherwise_is_refused_at_its_line(text, message):
    err = refused(text)
    assert (err.details["line"], err.details["column"]) == (2, 1)
    assert message in err.message


def test_an_element_of_an_undeclared_name_is_no_array():
    err = refused("nothing(1) = 2\n")
    assert isinstance(err, ParseError)
    assert "NOTHING is not an array (DIM NOTHING(n) AS ... declares one)" in err.message


def test_a_for_loop_whose_start_is_past_its_end_runs_no_pass():
    """FOR v = start TO end [STEP inc]: with a positive step and start > end, or a negative
    step and start < end, the body does not run (the loop ends before its first pass
    ``[INF]``); a negative step counting down runs each pass."""
    from tests.sim.trio.conftest import make, run_to

    c = make()
    c.store_program("F", "VR(1)=0\nFOR i = 5 TO 1\nVR(1)=VR(1)+1\nNEXT i\n"
                         "FOR j = 1 TO 5 STEP -1\nVR(1)=VR(1)+10\nNEXT j\n"
                         "FOR k = 3 TO 1 STEP -1\nVR(2)=VR(2)+1\nNEXT k\n")
    c.run_program("F", 1)
    run_to(c, 0.2)
    assert c.vr[1:3] == [0.0, 3.0]
