"""``make plots`` regenerates every plot the README shows from the example scenarios, so the
pictures cannot drift from what the simulator does."""

from __future__ import annotations

import importlib.util
import re
import shutil
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
SCRIPT = ROOT / "examples" / "scenarios" / "readme_plots.py"


def _script():
    spec = importlib.util.spec_from_file_location("readme_plots", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_readme_image_of_the_examples_is_made_by_make_plots():
    shown = set(re.findall(r"\]\(examples/scenarios/([\w.-]+\.png)\)",
                           (ROOT / "README.md").read_text()))
    assert shown and shown == set(_script().PLOTS)
    out = subprocess.run([shutil.which("make"), "-n", "-B", "plots"], cwd=ROOT,
                         capture_output=True, text=True, check=True, timeout=30).stdout
    assert "examples/scenarios/readme_plots.py" in out


def test_the_script_writes_the_readme_image_from_its_example(tmp_path):
    module = _script()
    (path,) = module.regenerate(tmp_path, ["rotary_breq_slow.png"])
    assert path == tmp_path / "rotary_breq_slow.png"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 20_000
