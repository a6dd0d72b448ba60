"""``tools/mutation.toml`` (``make mutate``) names real modules and test files, and covers the
decision modules issue 25 found left out: the ``first_seq`` rules, the Trio terminal's lock and
queue, the PMAC's ERRnnn answers and the PMAC Ethernet framing."""

from __future__ import annotations

import tomllib

import pytest

from tests.app.test_cli import ROOT

CONFIG = tomllib.loads((ROOT / "tools" / "mutation.toml").read_text())["modules"]


def test_every_module_and_test_file_listed_exists():
    missing = [(module, test) for module, entry in CONFIG.items()
               for test in [module, *entry["tests"]] if not (ROOT / test).is_file()]
    assert missing == []


@pytest.mark.parametrize("module, pinned_by", [
    ("sim/pmac/buffers/line_numbers.py", "tests/api/test_first_seq.py"),
    ("sim/trio/terminal.py", "tests/sim/trio/test_terminal.py"),
    ("sim/pmac/host/terminal.py", "tests/sim/pmac/test_reports_and_errors.py"),
    ("sim/pmac/card/error_codes.py", "tests/api/test_terminal.py"),
    ("api/pmac_ethernet/protocol.py", "tests/api/pmac_ethernet/test_pmac_codec.py"),
])
def test_the_decision_modules_left_out_before_are_mutated_with_their_tests(module, pinned_by):
    assert pinned_by in CONFIG[module]["tests"]


@pytest.mark.parametrize("module", ["sim/pmac/lookahead/planning.py",
                                    "sim/pmac/lookahead/execution.py",
                                    "sim/pmac/lookahead/coord.py"])
def test_the_quit_and_blend_pins_test_the_lookahead_modules(module):
    assert "tests/sim/pmac/test_quit_blend_pins.py" in CONFIG[module]["tests"]
