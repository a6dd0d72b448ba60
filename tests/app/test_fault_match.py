"""A fault's ``match`` runs in time linear in the command line (app/fault_match.py).

The classic catastrophic patterns of a backtracking engine — nested quantifiers and
overlapping alternations, which Python's ``re`` needs seconds to minutes for on a few dozen
characters — are searched by RE2 in microseconds; patterns RE2 cannot run in linear time
(back-references, look-around) are refused when the fault is added, naming ``match``.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest
from motionsim.app.fault_match import CommandPattern
from motionsim.app.faults import FAULT_SPEC
from pydantic import ValidationError

#: Nested quantifiers and overlapping alternatives: exponential for a backtracking engine.
CATASTROPHIC = ["(a+)+$", "(a|aa)+$", "(a|a)+$", "(.*a){4}$", "(a*)*b", "(\\w+\\s?)+$",
                "^(([a-z])+.)+[A-Z]([a-z])+$", "(x+x+)+y"]


def test_catastrophic_patterns_are_searched_in_linear_time():
    """Each pattern against 10 000 characters that almost match: the child would run for
    days with a backtracking engine; it is given 60 s and killed if it has not finished."""
    script = textwrap.dedent(f"""
        from motionsim.app.faults import FAULT_SPEC, FaultTable
        class Log:
            def emit(self, *a, **k): pass
        class Ctl:
            kind = "pmac"; log = Log()
        table = FaultTable(Ctl())
        for p in {CATASTROPHIC!r}:
            table.add(FAULT_SPEC.validate_python({{"kind": "error_reply", "match": p,
                                                  "error": "ERR003"}}))
        for subject in ("a" * 10000 + "!", "x" * 10000, "ab " * 3000 + "!"):
            table.forced_error(subject)
        print("ok")
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok"


@pytest.mark.parametrize("pattern", CATASTROPHIC)
def test_a_catastrophic_pattern_still_finds_its_match(pattern):
    subject = {"(a*)*b": "aaab", "(x+x+)+y": "xxxxy",
               "^(([a-z])+.)+[A-Z]([a-z])+$": "ab.Cd"}.get(pattern, "AAAA")
    assert CommandPattern(pattern).search(subject)


def test_matching_ignores_case_and_searches_anywhere_in_the_line():
    assert CommandPattern("^pr").search("PR")
    assert CommandPattern("p7=").search("#1J/ P7=2")
    assert not CommandPattern("^p7").search("#1J/ P7=2")


@pytest.mark.parametrize("pattern,what", [("(a)\\1", "\\1"), ("I(?=1)", "(?="),
                                          ("(?<!x)P", "(?<"), ("a{1001}", "{1001}")])
def test_a_pattern_needing_backtracking_is_refused_naming_match(pattern, what):
    with pytest.raises(ValidationError) as info:
        FAULT_SPEC.validate_python({"kind": "reply_drop", "match": pattern})
    (error,) = info.value.errors()
    assert error["loc"][-1] == "match"
    assert "linear-time" in error["msg"] and what in error["msg"]
