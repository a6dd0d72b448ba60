"""``make mutate``'s own machinery (tools/mutation_lines.py, tools/mutation_fork.py): which
mutants are inert, which tests a mutant needs, and that a forked child serving a mutant from
memory kills a bad one, lets a no-op live and stops one that never ends."""

from __future__ import annotations

import json
import textwrap

import pytest

from tools import mutation_fork
from tools.mutation_lines import IMPORT_CONTEXT, StatementIndex, inert_reason, inert_spans, select

SOURCE = textwrap.dedent('''\
    """Module docstring."""
    from __future__ import annotations

    LIMIT = 3


    def clamp(value: int | None, top: int = LIMIT) -> int:
        """Clamp docstring."""
        if value is not None and (
                value > top):
            return top
        total = (value or 0) + \\
            1
        return total - 1
    ''')


def test_annotations_and_docstrings_are_inert_code_is_not():
    spans = inert_spans(SOURCE)
    assert inert_reason(spans, (7, 20)) == "annotation"  # the `|` of `int | None`
    assert inert_reason(spans, (7, 50)) == "annotation"  # the return annotation
    assert inert_reason(spans, (1, 3)) == "docstring"
    assert inert_reason(spans, (8, 6)) == "docstring"
    assert inert_reason(spans, (7, 40)) is None  # the default value LIMIT is evaluated
    assert inert_reason(spans, (9, 13)) is None


def test_annotations_are_code_without_the_future_import():
    source = SOURCE.replace("from __future__ import annotations\n", "\n")
    assert inert_reason(inert_spans(source), (7, 20)) is None


def test_a_mutant_needs_the_header_of_its_innermost_statement():
    index = StatementIndex(SOURCE)
    assert list(index.lines((9, 13))) == [9, 10]  # `if` condition over two lines, not the body
    assert list(index.lines((10, 22))) == [9, 10]
    assert list(index.lines((11, 15))) == [11]  # the body's return
    assert list(index.lines((12, 24))) == [12, 13]  # a statement continued by a backslash
    assert list(index.lines((7, 40))) == [7]  # a default value: the `def` line (import time)
    assert list(index.lines((4, 8))) == [4]


def test_selection_by_coverage_contexts():
    by_line = {4: [IMPORT_CONTEXT], 9: ["t::a", "t::b"], 10: ["t::b"], 11: ["t::c"]}
    assert select(by_line, [9, 10]) == {"t::a", "t::b"}
    assert select(by_line, [11]) == {"t::c"}
    assert select(by_line, [4]) is None  # run at import: the whole subset
    assert select(by_line, [12, 13]) == set()  # no test executes it: survives unrun


@pytest.fixture
def demo(tmp_path, monkeypatch):
    """A module ``mt_demo`` served from memory and a test file for it."""
    (tmp_path / "pytest.ini").write_text("[pytest]\n")
    (tmp_path / "test_demo.py").write_text(textwrap.dedent('''\
        import mt_demo

        def test_low():
            assert mt_demo.clamp(1) == 1

        def test_high():
            assert mt_demo.clamp(9) == 3

        def test_unrelated():
            assert mt_demo.LIMIT == 3
        '''))
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _run(demo, source, order=None, limit_s=60.0):
    return mutation_fork.run_mutant([str(demo / "test_demo.py")], order, "mt_demo",
                                    demo / "mt_demo.py", source, limit_s)


def test_a_known_bad_mutant_is_killed_and_a_no_op_is_not(demo):
    assert _run(demo, SOURCE).code == 0
    assert _run(demo, SOURCE.replace("value > top", "value >= top")).code == 0  # no-op here
    assert _run(demo, SOURCE.replace("return top", "return value")).code == 1


def test_only_the_chosen_tests_run(demo):
    bad = SOURCE.replace("return top", "return value")
    assert _run(demo, bad, order=["test_demo.py::test_low"]).code == 0
    assert _run(demo, bad, order=["test_demo.py::test_low", "test_demo.py::test_high"]).code == 1


def test_a_mutant_that_never_ends_is_stopped_at_its_limit(demo):
    verdict = _run(demo, SOURCE.replace("return total - 1", "while True:\n        pass"),
                   limit_s=3.0)
    assert verdict.timed_out and verdict.seconds < 10


def test_the_baseline_maps_lines_to_the_tests_that_run_them(demo):
    (demo / "mt_demo.py").write_text(SOURCE)
    out = demo / "cov.json"
    verdict = mutation_fork.baseline([str(demo / "test_demo.py")], demo / "mt_demo.py", out,
                                     60.0, demo / "baseline.log")
    assert verdict.code == 0, (demo / "baseline.log").read_text()
    measured = json.loads(out.read_text())
    lines = {int(k): set(v) for k, v in measured["lines"].items()}
    assert lines[4] == {IMPORT_CONTEXT}
    assert lines[11] == {"test_demo.py::test_high"}
    assert lines[12] == {"test_demo.py::test_low"}
    assert set(measured["durations"]) == {f"test_demo.py::test_{n}"
                                          for n in ("low", "high", "unrelated")}


PATCHABLE = textwrap.dedent('''\
    LIMIT = 3


    def clamp(value, top=LIMIT):
        def inner(v):
            return min(v, top)
        return inner(value)


    class Box:
        size = 2

        def grow(self, by):
            return self.size + by

        @property
        def double(self):
            return self.size * 2
    ''')


@pytest.mark.parametrize(("old", "new", "names"), [
    ("return self.size + by", "return self.size - by", ["Box.grow"]),
    ("return min(v, top)", "return max(v, top)", ["clamp"]),  # a nested function: its outer
    ("return self.size * 2", "return self.size * 3", ["Box.double"]),
    ("top=LIMIT", "top=LIMIT + 1", None),  # a default: evaluated at import
    ("size = 2", "size = 3", None),  # a class attribute
    ("LIMIT = 3", "LIMIT = 4", None),  # module level
])
def test_only_mutants_of_function_bodies_are_patched_in(old, new, names):
    from tools.mutation_patch import changed_functions

    assert changed_functions(PATCHABLE, PATCHABLE.replace(old, new), "m.py") == names


def test_patching_swaps_the_code_of_the_live_functions():
    import types

    from tools.mutation_patch import apply

    module = types.ModuleType("mt_patch")
    module.__file__ = "mt_patch.py"
    exec(compile(PATCHABLE, "mt_patch.py", "exec"), module.__dict__)
    box = module.Box()
    mutated = PATCHABLE.replace("self.size + by", "self.size - by").replace(
        "self.size * 2", "self.size * 3")
    assert apply(module, mutated, ["Box.double", "Box.grow"])
    assert box.grow(1) == 1 and box.double == 6
    assert not apply(module, mutated, ["Box.missing"])


def test_a_zygote_tests_patched_mutants_without_a_fresh_import(demo):
    (demo / "mt_demo.py").write_text(SOURCE)
    zygote = mutation_fork.Zygote([str(demo / "test_demo.py")], "mt_demo", demo / "z.log")
    try:
        order = ["test_demo.py::test_low", "test_demo.py::test_high"]
        assert zygote.run(SOURCE, [], order, 60.0).code == 0
        bad = SOURCE.replace("return top", "return value")
        assert zygote.run(bad, ["clamp"], order, 60.0).code == 1
        assert zygote.run(bad, ["clamp"], order[:1], 60.0).code == 0  # only test_low runs
        assert zygote.run(bad, ["nothing"], order, 60.0).code == mutation_fork.PATCH_FAILED
        forever = SOURCE.replace("return total - 1", "while True:\n        pass")
        assert zygote.run(forever, ["clamp"], order, 3.0).timed_out
        assert zygote.run(SOURCE, [], order, 60.0).code == 0  # each mutant in a fresh fork
    finally:
        zygote.close()


def test_equivalent_entries_match_by_operator_line_and_optionally_mutant_and_number():
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))
    from tools.mutate import _equivalents, _listed

    config = {"equivalent": [
        {"module": "m.py", "operator": "core/N", "code": "x = max(0, y)",
         "mutant": "x = max( -1, y)", "reason": "clamped later"},
        {"module": "m.py", "operator": "core/N", "code": "pc += 1", "line": 7, "reason": "dead"},
        {"module": "other.py", "operator": "core/N", "code": "pc += 1", "reason": "elsewhere"},
    ]}
    eq = _equivalents(config, "m.py")
    assert _listed(eq, "core/N", "    x = max(0, y)", "x = max(-1, y)", 3) == "clamped later"
    assert _listed(eq, "core/N", "x = max(0, y)", "x = max(1, y)", 3) is None
    assert _listed(eq, "core/N", "pc += 1", "pc += 2", 7) == "dead"
    assert _listed(eq, "core/N", "pc += 1", "pc += 2", 8) is None
    assert _listed(eq, "core/M", "pc += 1", "pc += 2", 7) is None


def test_a_zygote_names_the_test_that_killed_a_mutant(demo, tmp_path):
    (demo / "mt_demo.py").write_text(SOURCE)
    zygote = mutation_fork.Zygote([str(demo / "test_demo.py")], "mt_demo", demo / "z.log")
    killer = tmp_path / "killer"
    try:
        order = ["test_demo.py::test_low", "test_demo.py::test_high"]
        bad = SOURCE.replace("return top", "return value")
        assert zygote.run(bad, ["clamp"], order, 60.0, killer).code == 1
        assert killer.read_text() == "test_demo.py::test_high"
        killer.unlink()
        assert zygote.run(SOURCE, [], order, 60.0, killer).code == 0
        assert not killer.exists()  # nothing failed: no killer named
    finally:
        zygote.close()


def test_the_latest_killers_run_first_newest_first():
    from tools.mutate import KILLERS, _killers_first, _promote

    killers: list[str] = []
    for test in ["a", "b", "a", "c"]:
        _promote(killers, test)
    assert killers == ["c", "a", "b"]
    assert _killers_first(["x", "a", "y", "c"], killers) == ["c", "a", "x", "y"]
    assert _killers_first(["x", "y"], killers) == ["x", "y"]
    for n in range(10):
        _promote(killers, f"t{n}")
    assert len(killers) == KILLERS and killers[0] == "t9"


def test_results_count_the_same_from_a_results_file_as_from_rows(tmp_path, monkeypatch):
    import tools.mutate as mutate

    monkeypatch.setattr(mutate, "ROOT", tmp_path)
    (tmp_path / "m.py").write_text("x = 1\ny = max(0, x)\n")
    rows = [
        {"operator": "core/N", "occurrence": 0, "line": 1, "worker": "normal",
         "test": "killed", "output": "pytest exit 1", "diff": None},
        {"operator": "core/N", "occurrence": 1, "line": 2, "worker": "normal",
         "test": "survived", "output": "3 tests passed",
         "diff": "--- a/m.py\n+++ b/m.py\n-y = max(0, x)\n+y = max( -1, x)"},
        {"operator": "core/N", "occurrence": 2, "line": 2, "worker": "normal",
         "test": "survived", "output": mutate.UNCOVERED,
         "diff": "--- a/m.py\n+++ b/m.py\n-y = max(0, x)\n+y = max(1, x)"},
        {"operator": "core/N", "occurrence": 3, "line": 1, "worker": "skipped",
         "test": None, "output": "equivalent: docstring", "diff": None},
    ]
    spent = {"seconds": 5.0, "ran": 3}
    config = {"equivalent": [{"module": "m.py", "operator": "core/N", "code": "y = max(0, x)",
                              "mutant": "y = max( -1, x)", "reason": "x >= 0"}]}
    t = mutate.tally_rows("m.py", rows, 6, False, spent, config)
    assert (t.killed, t.equivalent, t.untested) == (1, 2, 2)
    assert t.survived == [(2, "core/N", "+y = max(1, x)", True)]
    assert t.rate == 0.5
    t = mutate.tally_rows("m.py", rows, 4, True, spent)  # no entry: both survive
    assert (t.killed, len(t.survived), t.untested, t.stale) == (1, 2, 0, True)


def test_a_mutant_limit_never_falls_under_one_and_a_half_times_its_tests_baseline():
    from tools.mutate import _limit

    assert _limit({"a": 1.0}, ["a"], 0.0, 120.0) == 13.0  # 10 s start + 3x the tests
    assert _limit({"a": 50.0, "b": 9.0}, ["a"], 0.0, 120.0) == 120.0  # capped
    assert _limit({"a": 219.0}, ["a"], 2.0, 120.0) == 14.0 + 1.5 * 219.0  # cap < baseline


def test_the_wilson_interval_of_a_sampled_rate():
    from tools.mutate import wilson

    lo, hi = wilson(90, 100)
    assert round(lo, 3) == 0.826 and round(hi, 3) == 0.945  # the textbook 90/100 interval
    lo, hi = wilson(10, 10)
    assert hi == 1.0 and round(lo, 3) == 0.722


def test_a_function_anchor_is_the_same_only_while_the_function_code_is_unchanged():
    from tools.mutation_lines import FunctionAnchors

    old = "X = 1\n\n\nclass A:\n    def f(self):\n        return 1\n\n    def g(self):\n" \
          "        return 2\n"
    new = "X = 1\nY = 2\n\n\nclass A:\n    def f(self):\n        # a comment\n" \
          "        return 1\n\n    def g(self):\n        return 3\n"
    a, b = FunctionAnchors(old), FunctionAnchors(new)
    assert a.anchor(1) is None and a.anchor(4) is None  # module and class level
    assert a.anchor(6) == b.anchor(8) == ("A.f", a.anchor(6)[1])  # moved, commented: same code
    assert a.anchor(9)[0] == b.anchor(11)[0] == "A.g"
    assert a.anchor(9) != b.anchor(11)  # its code changed
