"""The Dockerfile's layers and compose's published ports, read as Docker would (no engine here).

- Dependencies are installed in a layer that only ``pyproject.toml`` feeds, so a source edit
  re-installs motionsim alone (the package itself with ``--no-deps``, no build isolation).
- The build's pip settings (``docker/pip/``) stay in the dependency stage; the base image script
  names the Dockerfile's base and leaves an existing one alone (the image and compose run for
  real on an engine in ``make docker-test``, tools/docker_test.py).
- Compose publishes the ports on the host's loopback unless ``MOTIONSIM_PUBLISH_HOST`` says
  otherwise, as the README's security section promises (the TCP protocols have no
  authentication).
"""

from __future__ import annotations

import os
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
    assert copied_before == ["docker/pip/", "pyproject.toml"]  # pip's settings for the build
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


def test_compose_host_ports_follow_their_variables_so_a_taken_8000_can_be_avoided():
    """``make docker-test`` publishes on free host ports through these variables (a developer's
    ``make run`` may hold 8000); the container ports stay those the image serves on."""
    published = _published({"MOTIONSIM_HTTP_HOST_PORT": "18000",
                            "MOTIONSIM_PMAC_HOST_PORT": "11025",
                            "MOTIONSIM_TRIO_HOST_PORT": "12323"})
    assert published == ["127.0.0.1:18000:8000", "127.0.0.1:11025:1025", "127.0.0.1:12323:2323"]


def _stages() -> list[list[tuple[str, str]]]:
    stages: list[list[tuple[str, str]]] = []
    for op, args in _steps():
        if op == "FROM":
            stages.append([])
        stages[-1].append((op, args))
    return stages


def test_the_builds_pip_settings_never_reach_the_final_image():
    """``docker/pip/`` (this machine's CA bundle and index settings) is copied into the
    dependency stage only; the final stage takes nothing but the installed venv from it."""
    *earlier, final = _stages()
    assert any(op == "COPY" and args.startswith("docker/pip/") for stage in earlier
               for op, args in stage)
    assert not any("docker/pip" in args for _, args in final)
    assert [args for op, args in final if op == "COPY" and args.startswith("--from")] == [
        "--from=deps /opt/venv /opt/venv"]


def _pip_context():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import docker_pip_context
    finally:
        sys.path.pop(0)
    return docker_pip_context


def test_the_builds_pip_settings_keep_what_a_container_can_reach(tmp_path):
    """``pip config list`` as this kind of machine prints it: a variable wins over ``[install]``
    over ``[global]``; ``file://`` indexes and local find-links folders are the host's disk
    and are dropped; the CA bundle pip trusts goes along, at the path the build copies it to."""
    ctx = _pip_context()
    bundle = tmp_path / "ca.crt"
    bundle.write_text("-----BEGIN CERTIFICATE-----\n")
    listing = "\n".join([
        f":env:.cert='{bundle}'",
        ":env:.default-timeout='180'",
        ":env:.find-links='/opt/wheels'",
        "global.cert='/nowhere/else.crt'",
        "global.constraint='/etc/xdg/pip/constraints.txt'",
        "global.extra-index-url='file:///opt/pypi/simple https://mirror.example/simple'",
        "global.index-url='https://global.example/simple'",
        "install.index-url='https://install.example/simple'",
        "global.trusted-host='mirror.example'",
    ])
    config = ctx.pip_config(listing)
    assert config["cert"] == str(bundle) and config["timeout"] == "180"
    assert config["index-url"] == "https://install.example/simple"
    text, found = ctx.build_config(config, {})
    assert found == bundle
    assert text.splitlines() == [
        "[global]",
        "cert = /tmp/pip/ca-certificates.crt",
        "index-url = https://install.example/simple",
        "extra-index-url = https://mirror.example/simple",
        "trusted-host = mirror.example",
        "timeout = 180",
    ]


def test_without_a_bundle_or_index_the_build_uses_pypi_and_the_images_own_bundle(
        tmp_path, monkeypatch):
    ctx = _pip_context()
    monkeypatch.setattr(ctx, "SYSTEM_BUNDLE", tmp_path / "absent.crt")
    text, found = ctx.build_config(ctx.pip_config(""), {})
    assert (text, found) == ("[global]\n", None)


def _fake_docker(tmp_path, inspect_rc: int, pull_rc: int):
    """A ``docker`` on PATH that answers ``image inspect`` / ``pull`` and logs its calls."""
    log = tmp_path / "docker.log"
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    fake = bin_dir / "docker"
    fake.write_text(f"""#!/bin/sh
echo "$*" >> {log}
case "$1 $2" in
  "image inspect") exit {inspect_rc} ;;
  "pull "*) exit {pull_rc} ;;
esac
exit 99
""")
    fake.chmod(0o755)
    return bin_dir, log


def _base_image(bin_dir):
    return subprocess.run(["bash", str(ROOT / "tools" / "docker_base_image.sh")],
                          env={**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"},
                          capture_output=True, text=True, timeout=60)


def test_the_base_image_script_does_nothing_when_the_dockerfiles_base_exists(tmp_path):
    """It names the Dockerfile's own ``FROM`` and, that image present, touches nothing."""
    base = next(args.split()[0] for op, args in _steps() if op == "FROM")
    bin_dir, log = _fake_docker(tmp_path, inspect_rc=0, pull_rc=1)
    made = _base_image(bin_dir)
    assert made.returncode == 0, made.stderr
    assert made.stdout == f"base image {base}: present\n"
    assert log.read_text().splitlines() == [f"image inspect {base}"]


def test_the_base_image_script_pulls_when_a_registry_answers(tmp_path):
    base = next(args.split()[0] for op, args in _steps() if op == "FROM")
    bin_dir, log = _fake_docker(tmp_path, inspect_rc=1, pull_rc=0)
    made = _base_image(bin_dir)
    assert made.returncode == 0, made.stderr
    assert made.stdout == f"base image {base}: pulled\n"
    assert log.read_text().splitlines() == [f"image inspect {base}", f"pull -q {base}"]
