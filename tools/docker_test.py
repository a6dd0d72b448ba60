"""``make docker-test``: the image and ``docker-compose.yml`` run for real on a Docker engine.

1. the base image the Dockerfile names, made if missing (``tools/docker_base_image.sh``);
2. pip's settings for the build (``tools/docker_pip_context.py``);
3. ``docker build -t motionsim:latest .``, then the image's own ``HEALTHCHECK`` command run in
   a container of it (from its working directory, as Docker runs it) against its own server;
4. the README's command, ``docker compose up --build --exit-code-from client`` (Compose v2) or
   ``docker-compose up ...`` (v1), on free host ports under a project name of its own: its exit
   status must be 0 and the client's JSON summary must show every line streamed, BREQ obeyed,
   the program run to its end and ``starved`` 0;
5. ``down -v`` whatever happened.

``--image-only`` (``make docker-image``) stops after step 3: ``.ci/run`` runs it while the
suite runs, so the ``make docker-test`` after the suite finds the images built. Every step is
bounded in time (``--timeout-s``, default 1500 s in all). Exit 0: passed; 1: a
step failed (its output says which); 3: no Docker engine answers (``.ci/run`` tells that
apart from a failure).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
IMAGE = "motionsim:latest"
PROJECT = "motionsim-docker-test"
NO_ENGINE = 3


class Failed(Exception):
    """A step failed; the message says which and why."""


def compose_command() -> list[str]:
    """Compose v2 (``docker compose``) when the plugin answers, else v1 (``docker-compose``)."""
    if os.environ.get("MOTIONSIM_COMPOSE"):
        return os.environ["MOTIONSIM_COMPOSE"].split()
    v2 = subprocess.run(["docker", "compose", "version"], capture_output=True, timeout=60)
    if v2.returncode == 0:
        return ["docker", "compose"]
    if shutil.which("docker-compose"):
        return ["docker-compose"]
    raise Failed("neither `docker compose` (v2) nor `docker-compose` (v1) is installed "
                 "(Debian: apt-get install docker-compose)")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Budget:
    """What is left of the whole run's time."""

    def __init__(self, seconds: float) -> None:
        self.end = time.monotonic() + seconds

    def left(self, step: str) -> float:
        left = self.end - time.monotonic()
        if left <= 0:
            raise Failed(f"{step}: out of time")
        return left


def _kill_group(pid: int) -> None:
    with contextlib.suppress(ProcessLookupError):
        os.killpg(pid, signal.SIGKILL)


def run(argv: list[str], budget: Budget, step: str, *, echo: bool = True,
        env: dict[str, str] | None = None) -> str:
    """Run ``argv`` (its output shown as it comes when ``echo``); its output; Failed unless 0."""
    print(f"== {step}: {' '.join(argv)}", flush=True)
    limit = budget.left(step)
    start = time.monotonic()
    proc = subprocess.Popen(argv, cwd=ROOT, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, errors="replace",
                            start_new_session=True)
    out: list[str] = []
    # at the limit the whole process group goes (debootstrap under the script too), so a
    # silent hang ends as well
    timer = threading.Timer(limit, _kill_group, (proc.pid,))
    timer.start()
    try:
        assert proc.stdout is not None
        for line in proc.stdout:
            out.append(line)
            if echo:
                print(line, end="", flush=True)
        proc.wait()
    finally:
        timer.cancel()
    if time.monotonic() - start >= limit:
        raise Failed(f"{step}: out of time ({limit:.0f} s)")
    took = time.monotonic() - start
    if proc.returncode != 0:
        tail = "" if echo else "".join(out[-30:])
        raise Failed(f"{tail}{step}: exit status {proc.returncode} after {took:.0f} s")
    print(f"== {step}: ok in {took:.0f} s", flush=True)
    return "".join(out)


def check_image_health(budget: Budget) -> None:
    """The image's HEALTHCHECK command, run as Docker runs it: in a container of the image
    (its working directory, its user), against the server that container serves."""
    config = json.loads(run(["docker", "image", "inspect", IMAGE], budget, "inspect",
                            echo=False))[0]["Config"]
    test = config["Healthcheck"]["Test"]
    assert test[0] == "CMD", test
    name = f"{PROJECT}-health"
    subprocess.run(["docker", "rm", "-f", name], capture_output=True, timeout=60)
    run(["docker", "run", "-d", "--name", name, IMAGE], budget, "serve", echo=False)
    try:
        end = time.monotonic() + min(60.0, budget.left("health check"))
        while True:
            probe = subprocess.run(["docker", "exec", name, *test[1:]], capture_output=True,
                                   text=True, timeout=30)
            if probe.returncode == 0:
                print(f"== health check {test[1:]}: ok", flush=True)
                break
            if "No module named" in probe.stderr or time.monotonic() > end:
                logs = subprocess.run(["docker", "logs", "--tail", "20", name],
                                      capture_output=True, text=True, timeout=60)
                raise Failed(f"{logs.stdout}{logs.stderr}{probe.stderr}the image's "
                             f"HEALTHCHECK {test[1:]} fails in its working directory")
            time.sleep(1)
    finally:
        subprocess.run(["docker", "rm", "-f", name], capture_output=True, timeout=60)


def client_summary(output: str) -> dict[str, object]:
    """The client's last JSON line in compose's prefixed output (``client_1  | {...}``)."""
    for line in reversed(re.sub(r"\x1b\[[0-9;]*m", "", output).splitlines()):
        m = re.match(r"^client[-_]\d+\s+\|\s+(\{.*\})\s*$", line)
        if m:
            summary: dict[str, object] = json.loads(m[1])
            return summary
    raise Failed("the client printed no JSON summary")


def check_summary(summary: dict[str, object], lines: int) -> None:
    program = summary.get("program")
    problems = [what for what, bad in (
        (f"lines_sent {summary.get('lines_sent')} < the {lines} lines of the compose command",
         not isinstance(summary.get("lines_sent"), int) or summary["lines_sent"] < lines),
        ("no BREQ wait: the buffer never filled", not summary.get("breq_waits")),
        (f"program state {program} (not waiting: it did not run to its end)",
         not isinstance(program, dict) or program.get("state") != "waiting"),
        (f"starved {summary.get('starved')} (the program ran out of lines early)",
         summary.get("starved") != 0),
    ) if bad]
    if problems:
        raise Failed("the client's summary: " + "; ".join(problems))


def compose_client_lines(text: str) -> int:
    """The ``--lines`` of the client's command in ``docker-compose.yml`` (read without a YAML
    library: this tool needs nothing but the standard library and Docker)."""
    m = re.search(r'"--lines",\s*"(\d+)"', text)
    if not m:
        raise Failed('docker-compose.yml: the client command has no "--lines", "N"')
    return int(m[1])


def compose_up(compose: list[str], budget: Budget) -> None:
    lines = compose_client_lines((ROOT / "docker-compose.yml").read_text())
    env = dict(os.environ, MOTIONSIM_HTTP_HOST_PORT=str(free_port()),
               MOTIONSIM_PMAC_HOST_PORT=str(free_port()),
               MOTIONSIM_TRIO_HOST_PORT=str(free_port()))
    base = [*compose, "-p", PROJECT]
    try:
        out = run([*base, "up", "--build", "--no-color", "--exit-code-from", "client"], budget,
                  "compose up", env=env)
        summary = client_summary(out)
        check_summary(summary, lines)
        print(f"== client: {summary['lines_sent']} lines streamed, "
              f"{summary['breq_waits']} BREQ waits, starved {summary['starved']}", flush=True)
    finally:
        subprocess.run([*base, "down", "-v", "--remove-orphans"], cwd=ROOT, env=env,
                       timeout=300, check=False)


def engine_answers() -> bool:
    try:
        return subprocess.run(["docker", "info"], capture_output=True,
                              timeout=60).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--timeout-s", type=float, default=1500.0,
                    help="the whole run's time limit (base image, build, compose)")
    ap.add_argument("--image-only", action="store_true",
                    help="steps 1-3 only: the base image, pip's settings and the build "
                         "(`make docker-image`; .ci/run does it while the suite runs)")
    args = ap.parse_args(argv)
    what = "make docker-image" if args.image_only else "make docker-test"
    if not engine_answers():
        print(f"{what}: no Docker engine answers (`docker info` fails): start dockerd",
              file=sys.stderr)
        return NO_ENGINE
    budget = Budget(args.timeout_s)
    start = time.monotonic()
    try:
        compose = [] if args.image_only else compose_command()
        run(["bash", "tools/docker_base_image.sh"], budget, "base image")
        run([sys.executable, "tools/docker_pip_context.py"], budget, "pip settings")
        run(["docker", "build", "-t", IMAGE, "."], budget, "build")
        if not args.image_only:
            check_image_health(budget)
            compose_up(compose, budget)
    except Failed as exc:
        print(f"{what}: FAILED: {exc}", file=sys.stderr)
        return 1
    print(f"{what}: passed in {time.monotonic() - start:.0f} s"
          + (f" ({' '.join(compose)})" if compose else ""), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
