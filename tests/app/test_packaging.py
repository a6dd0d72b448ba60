"""The installed distribution is one import package, ``motionsim``, and lives beside a user's own
``app/``, ``api/`` and ``sim/`` packages (the most common FastAPI layout) without shadowing them.

The wheel is built from a copy of the source (nothing is written into the repository) and
installed with ``--no-deps`` into a fresh venv whose dependencies come from this one's
site-packages through a ``.pth`` path entry: a path entry, unlike ``site.addsitedir``, runs
no ``.pth`` file of that directory, so this checkout's editable install stays invisible and
``motionsim`` can only come from the wheel.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SETUPTOOLS_WARNING = re.compile(r"Setuptools\w*Warning|BuildBackendWarning|_DeprecatedConfig")
LAYERS = {"motionsim": "motionsim", "motionsim.sim": "sim", "motionsim.app": "app",
          "motionsim.api": "api", "motionsim.examples": "examples"}

USER_TEST = '''
from app.main import greet          # the user's own app/, not motionsim's
from api import routes              # the user's own api/
import sim                          # the user's own sim/

import motionsim


def test_the_users_packages_are_their_own():
    assert greet() == "user app"
    assert routes.NAME == "user api"
    assert sim.NAME == "user sim"


def test_motionsim_comes_from_the_wheel_and_its_fixture_serves(motionsim):
    import motionsim as pkg
    assert "site-packages" in pkg.__file__
    assert motionsim.health()
    ids = {c["id"] for c in motionsim.controllers()}
    assert {"pmac", "trio"} <= ids
'''


def _mapped_packages() -> set[str]:
    """Every folder under the layers that holds a file: code packages (``__init__.py``) and
    data-only folders (the dashboard's static files), which setuptools sees as namespace
    packages and wants listed too."""
    found = set()
    for name, folder in LAYERS.items():
        for path in (ROOT / folder).rglob("*"):
            if not path.is_file() or "__pycache__" in path.parts or path.suffix == ".pyc":
                continue
            rel = path.parent.relative_to(ROOT / folder).parts
            found.update(".".join([name, *rel[:i]]) for i in range(len(rel) + 1))
    return found


def test_pyproject_lists_every_package_under_motionsim():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert config["package-dir"] == LAYERS
    assert set(config["packages"]) == _mapped_packages()


def _build_wheel(tmp: Path) -> Path:
    src = tmp / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, src / name)
    for folder in LAYERS.values():
        shutil.copytree(ROOT / folder, src / folder,
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    out = tmp / "dist"
    built = subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w",
                            str(out), str(src)], check=True, timeout=300, capture_output=True,
                           text=True)
    # the build is clean: no setuptools deprecation or configuration warning
    assert not SETUPTOOLS_WARNING.search(built.stdout + built.stderr), built.stderr
    (wheel,) = out.glob("motionsim-*.whl")
    return wheel


def _user_project(tmp: Path) -> Path:
    project = tmp / "userproj"
    files = {
        "app/__init__.py": "",
        "app/main.py": "def greet():\n    return 'user app'\n",
        "api/__init__.py": "",
        "api/routes.py": "NAME = 'user api'\n",
        "sim/__init__.py": "NAME = 'user sim'\n",
        "tests/__init__.py": "",
        "tests/test_with_motionsim.py": USER_TEST,
    }
    for rel, text in files.items():
        path = project / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    (project / "pyproject.toml").write_text(
        '[tool.pytest.ini_options]\ntestpaths = ["tests"]\npythonpath = ["."]\n')
    return project


@pytest.mark.timeout(600)
def test_the_wheel_in_a_fresh_venv_beside_a_project_with_its_own_app_api_and_sim(tmp_path):
    wheel = _build_wheel(tmp_path)
    with zipfile.ZipFile(wheel) as archive:
        names = set(archive.namelist())
    tops = {n.split("/")[0] for n in names}
    assert {t for t in tops if not t.endswith(".dist-info")} == {"motionsim"}
    dashboard = ROOT / "api" / "static" / "dashboard"
    shipped = {f"motionsim/api/{p.relative_to(ROOT / 'api').as_posix()}"
               for p in dashboard.rglob("*") if p.is_file()}
    assert "motionsim/api/static/dashboard/index.html" in shipped
    assert shipped <= names, sorted(shipped - names)   # the dashboard is package data
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    vpy = venv / "bin" / "python"
    purelib = "import sysconfig; print(sysconfig.get_path('purelib'))"
    site = subprocess.run([str(vpy), "-c", purelib],
                          check=True, capture_output=True, text=True).stdout.strip()
    (Path(site) / "motionsim_test_deps.pth").write_text(sysconfig.get_path("purelib") + "\n")
    subprocess.run([sys.executable, "-m", "pip", "--python", str(vpy), "install", "-q",
                    "--no-deps", str(wheel)], check=True, timeout=300, capture_output=True)
    project = _user_project(tmp_path)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTEST", "COV_"))}
    run = subprocess.run([str(vpy), "-m", "pytest", "-q", "-p", "no:cacheprovider"],
                         cwd=project, env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "2 passed" in run.stdout
    module = subprocess.run([str(vpy), "-m", "motionsim", "--version"], cwd=project, env=env,
                            capture_output=True, text=True, timeout=60)
    assert module.returncode == 0, module.stderr
    assert module.stdout.strip().endswith("0.1.0")

    # the examples ship: copied out of the installed package, a scenario runs from the copy
    copied = tmp_path / "my-examples"
    out = subprocess.run([str(venv / "bin" / "motionsim"), "examples", str(copied)], cwd=project,
                         env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert (copied / "README.md").is_file() and not list(copied.rglob("__init__.py"))
    ran = subprocess.run([str(venv / "bin" / "motionsim"), "run",
                          str(copied / "scenarios" / "m1_sync.yaml"), "--no-plots", "--out",
                          str(tmp_path / "run")], cwd=project, env=env, capture_output=True,
                         text=True, timeout=120)
    assert ran.returncode == 0, ran.stderr
