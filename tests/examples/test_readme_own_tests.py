"""The README's "In your own tests" example is a real test: run it with the installed
``motionsim`` fixture, as written (it passes) and with the host slowed beyond the time its
I16 lines cover (the README's own assertion fails)."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


def readme_example() -> str:
    text = README.read_text()
    section = text[text.index("## In your own tests"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_readme_example_passes_for_a_host_that_keeps_up(pytester):
    pytester.makepyfile(test_readme=readme_example())
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)


def test_the_readme_example_fails_for_a_host_slower_than_its_i16_lines_cover(pytester):
    code = readme_example()
    slow = code.replace("        ahead = ", "        host.sleep(1.0)\n        ahead = ", 1)
    assert slow != code
    pytester.makepyfile(test_readme=slow)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(failed=1)
    out = " ".join(result.stdout.str().split())
    # the README's sample output is what this run prints (host-paced: the same every run)
    text = README.read_text()
    sample = re.search(r"fails the\s+assertion.*?```\n(.*?)```", text, re.S).group(1)
    header, *rest = sample.splitlines()
    first = " ".join(" ".join(x for x in rest if not x.strip().startswith("…")).split())
    assert header in out
    assert first in out
