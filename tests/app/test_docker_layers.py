"""The Dockerfile's layers and compose's published ports, read as Docker would (no engine here).

- Dependencies are installed in a layer that only ``pyproject.toml`` feeds, so a source edit
  re-installs motionsim alone (the package itself with ``--no-deps``, no build isolation).
- Compose publishes the ports on the host's loopback unless ``MOTIONSIM_PUBLISH_HOST`` says
  otherwise, as the README's security section promises (the TCP protocols have no
  authentication).
"""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
import tomllib

import yaml

from tests.app.test_cli import ROOT
from tests.app.test_image_entrypoint import DOCKERFILE

SOURCE_DIRS = {"motionsim", "sim", "app", "api", "examples"}


def _steps() -> list[tuple[str, str]]:
    """(instruction, arguments) in order, continuation lines joined the way Docker joins them."""
    text = re.sub(r"\\\n", "", DOCKERFILE)
    return [(m.group(1), m.group(2).strip())
            for m in re.finditer(r"^([A-Z]+)\s+(.*)$", text, re.M)]


def _requirements_command() -> str:
    """The ``python -c`` of the dependency layer, with its output redirection cut off."""
    run = next(args for op, args in _steps() if op == "RUN" and "requirements.txt" in args)
    return run.split(">", 1)[0].strip()


def test_dependencies_are_installed_in_a_layer_before_any_source_is_copied():
    steps = _steps()
    deps = next(i for i, (op, args) in enumerate(steps)
                if op == "RUN" and "pip install -r" in args)
    copied_before = [args.split()[0] for op, args in steps[:deps] if op == "COPY"]
    assert copied_before == ["pyproject.toml"]
    sources_after = {args.split()[0] for op, args in steps[deps:] if op == "COPY"}
    assert sources_after >= SOURCE_DIRS
    package = next(args for op, args in steps[deps + 1:] if op == "RUN" and "pip install" in args)
    assert "--no-deps" in package.split() and "--no-build-isolation" in package.split()


def test_the_dependency_layer_lists_exactly_pyprojects_requirements(tmp_path):
    """The layer's own command, run here on the repository's pyproject.toml: the build
    requirements (the package is built without isolation later) and every dependency."""
    (tmp_path / "pyproject.toml").write_bytes((ROOT / "pyproject.toml").read_bytes())
    argv = shlex.split(_requirements_command())
    assert argv[:2] == ["python", "-c"]
    out = subprocess.run([sys.executable, *argv[1:]], cwd=tmp_path, capture_output=True,
                         text=True, timeout=30, check=True).stdout.split()
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert out == project["build-system"]["requires"] + project["project"]["dependencies"]


def _published(env: dict[str, str]) -> list[str]:
    """The motionsim service's ``ports`` with compose's ``${VAR:-default}`` interpolation."""
    ports = yaml.safe_load((ROOT / "docker-compose.yml").read_text())["services"]["motionsim"]
    return [re.sub(r"\$\{(\w+):-([^}]*)\}", lambda m: env.get(m[1]) or m[2], p)
            for p in ports["ports"]]


def test_compose_publishes_every_port_on_loopback_by_default():
    published = _published({})
    assert published == ["127.0.0.1:8000:8000", "127.0.0.1:1025:1025", "127.0.0.1:2323:2323"]


def test_compose_publishes_on_all_interfaces_only_when_the_user_opts_in():
    assert {p.split(":")[0] for p in _published({"MOTIONSIM_PUBLISH_HOST": "0.0.0.0"})} == {
        "0.0.0.0"}
    text = (ROOT / "docker-compose.yml").read_text() + (ROOT / "README.md").read_text()
    assert "MOTIONSIM_PUBLISH_HOST=0.0.0.0 docker compose up" in text
