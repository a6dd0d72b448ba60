"""``mypy --strict`` over ``sim/`` may only get cleaner (issue 31).

The recorded counts (``tests/app/mypy_strict_baseline.json``) are a ratchet: a change that adds
a type error to ``sim/`` fails here; one that removes some lowers the figure in that file.
``sim/pmac/lookahead/`` (the coordinate system) is at zero and stays there. How mypy is run,
and why on a shadow package: ``tools/mypy_strict.py``.
"""

from __future__ import annotations

import pytest

from tools import mypy_strict


@pytest.fixture(scope="module")
def errors() -> list[str]:
    return mypy_strict.run()


def test_the_package_imports_resolve(errors):
    # Were motionsim.sim... not found, every imported name would be Any and the count a
    # count of nothing.
    missing = [e for e in errors if "import-not-found" in e and "motionsim" in e]
    assert not missing, missing[:5]


def test_no_count_rises_above_the_recorded_one(errors):
    now, recorded = mypy_strict.counts(errors), mypy_strict.baseline()
    assert set(now) == set(recorded), "tools/mypy_strict.py PARTS and the baseline differ"
    risen = {key: (recorded[key], n) for key, n in now.items() if n > recorded[key]}
    new = [e for e in errors if any(e.startswith(k + "/") or k == "sim" for k in risen)]
    assert not risen, f"mypy --strict errors rose (recorded, now): {risen}\n" + "\n".join(
        new[:40]
    )


def test_the_coordinate_system_has_no_errors(errors):
    assert [e for e in errors if e.startswith("sim/pmac/lookahead/")] == []


def test_counts_are_per_part_and_whole():
    lines = [
        "sim/pmac/lookahead/planning.py:3: error: x  [misc]",
        "sim/trio/axis.py:9: error: y  [misc]",
        "sim/pmac/lookahead_other.py:1: error: z  [misc]",
    ]
    assert mypy_strict.counts(lines) == {"sim": 3, "sim/pmac/lookahead": 1}
