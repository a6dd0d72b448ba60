"""README's install section: three ways into another project (a path, a git URL, a wheel),
examples reachable from an installed motionsim, and no extra implied to come from an index
motionsim is not on."""

from __future__ import annotations

import re

from tests.app.test_cli import ROOT

README = (ROOT / "README.md").read_text()


def _section(title: str) -> str:
    start = README.index(title)
    end = README.find("\n## ", start + 1)
    return README[start:end]


def test_the_install_section_shows_a_path_a_git_url_and_a_wheel():
    text = _section("### Installing motionsim into your project")
    block = re.search(r"```sh\n(.*?)```", text, re.S)[1]
    commands = [line.split("#")[0].strip() for line in block.splitlines() if line.strip()]
    assert "pip install /path/to/motionsim" in commands
    assert any(c.startswith("pip install 'motionsim @ git+https://") for c in commands)
    assert "pip wheel --no-deps -w dist /path/to/motionsim" in commands  # as test_packaging builds
    assert "pip install dist/motionsim-0.1.0-py3-none-any.whl" in commands
    assert "motionsim examples DIR" in text
    assert "not published on PyPI" in text


def test_no_command_installs_motionsim_by_name_from_an_index():
    # ``pip install motionsim`` / ``'motionsim[cluster]'``: by name; ``motionsim @ URL`` is not
    bare = re.findall(r"pip install ['\"]?motionsim(?:\[[\w,]+\])?['\"]?(?=\s|$|`)(?!\s*@)",
                      README)
    assert bare == []
    assert "pip install 'motionsim[cluster]'" not in README


def test_the_first_screen_is_still_the_two_set_up_commands():
    first = re.search(r"## Set-up: two commands\n\n```sh\n(.*?)```", README, re.S)[1]
    assert [line.split("#")[0].strip() for line in first.splitlines()] == ["make run",
                                                                          "make test"]
    assert README.index("## Set-up: two commands") < README.index("## A first session")
