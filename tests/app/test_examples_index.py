"""Every example is listed in ``examples/README.md`` (which ``motionsim examples DIR`` copies
with them), and every file it names exists; the examples ship as package data."""

from __future__ import annotations

import re

from motionsim.app.cli import cli
from typer.testing import CliRunner

from tests.app.test_cli import ROOT

EXAMPLES = ROOT / "examples"
INDEX = (EXAMPLES / "README.md").read_text()


def _example_files() -> set[str]:
    return {p.relative_to(EXAMPLES).as_posix() for p in EXAMPLES.rglob("*")
            if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".pyc"
            and p.name not in ("README.md", "__init__.py")}


def test_every_example_file_is_listed_in_the_index():
    unlisted = sorted(f for f in _example_files()
                      if f"`{f}`" not in INDEX and f"`{f.split('/')[-1]}`" not in INDEX)
    assert unlisted == []


def test_every_file_the_index_names_exists():
    named = set(re.findall(r"`((?:[\w-]+/)?[\w.-]+\.(?:py|yaml|bas|plc|png))`", INDEX))
    missing = sorted(n for n in named if not any(f == n or f.endswith("/" + n)
                                                for f in _example_files()))
    assert missing == []


def test_motionsim_examples_copies_them_and_refuses_a_folder_in_use(tmp_path):
    dest = tmp_path / "ex"
    result = CliRunner().invoke(cli, ["examples", str(dest)])
    assert result.exit_code == 0, result.output
    copied = {p.relative_to(dest).as_posix() for p in dest.rglob("*") if p.is_file()}
    assert copied == _example_files() | {"README.md", "pmac/README.md", "trio/README.md"}
    again = CliRunner().invoke(cli, ["examples", str(dest)])
    assert again.exit_code == 2 and "pass --force" in again.stderr
    assert CliRunner().invoke(cli, ["examples", str(dest), "--force"]).exit_code == 0


def test_a_copied_example_imports_nothing_of_this_repository(tmp_path):
    """Issue 36 item 4: the copy ``motionsim examples`` writes imported ``tests`` (the
    trajectory-scan host). An example imports the installed package, the standard library,
    its listed dependencies, or a file beside it — never the repository's ``tests``."""
    import ast

    bad = []
    for p in sorted(EXAMPLES.rglob("*.py")):
        for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            bad += [f"{p.relative_to(EXAMPLES)}:{node.lineno} {n}" for n in names
                    if n.split(".")[0] in ("tests", "bench", "tools")]
    assert bad == []


def test_example_programs_are_ascii_as_the_downloaders_send_them():
    """dls-pmaclib sizes its Ethernet packets by characters: a ``µ`` in a comment of the
    scan program broke the download (issue 36 item 4). Card programs we ship are ASCII."""
    bad = [p.relative_to(EXAMPLES).as_posix() for p in sorted(EXAMPLES.rglob("*"))
           if p.suffix.lower() in (".pmc", ".plc", ".bas", ".pmh") and not p.read_bytes().isascii()]
    assert bad == []
