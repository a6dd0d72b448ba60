"""Write ``docker/pip/`` so that pip inside ``docker build`` reaches the index as this machine's
pip does: the CA bundle pip trusts here (a TLS-intercepting package proxy signs with a CA of its
own) and the index settings that make sense inside a container.

The Dockerfile's dependency stage copies ``docker/pip/`` and runs pip with
``PIP_CONFIG_FILE=/tmp/pip/pip.conf``; that stage is not part of the final image, so the bundle
never ships in it. Without this step the folder holds only its README and pip uses PyPI with
the image's own CA bundle — what a machine with direct access needs.

What is carried over from ``pip config list`` (files and ``PIP_*`` variables; a variable wins
over ``[install]``, which wins over ``[global]``):

- ``cert`` (else ``REQUESTS_CA_BUNDLE`` / ``SSL_CERT_FILE``, else Debian's bundle): copied as
  ``docker/pip/ca-certificates.crt``;
- ``index-url``, ``extra-index-url``, ``find-links``: only their ``http(s)://`` entries —
  a ``file://`` URL or a local folder is this machine's disk, not reachable from a build;
- ``trusted-host``, ``timeout``/``default-timeout``, ``retries``, ``proxy``.

Run: ``.venv/bin/python tools/docker_pip_context.py`` (``make docker-test`` does).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docker" / "pip"
#: Where the Dockerfile's dependency stage puts ``docker/pip/``.
IN_BUILD = "/tmp/pip"
BUNDLE = "ca-certificates.crt"
URL_OPTIONS = ("index-url", "extra-index-url", "find-links")
PLAIN_OPTIONS = ("trusted-host", "timeout", "retries", "proxy")
ALIASES = {"default-timeout": "timeout"}
SYSTEM_BUNDLE = Path("/etc/ssl/certs/ca-certificates.crt")


def pip_config(listing: str) -> dict[str, str]:
    """``pip config list`` output as option -> value, with pip's precedence applied."""
    rank = {"global": 0, "install": 1, ":env:": 2}
    best: dict[str, tuple[int, str]] = {}
    for line in listing.splitlines():
        m = re.match(r"^([^.=]*)\.([\w-]+)='(.*)'$", line.strip())
        if not m or m[1] not in rank:
            continue
        option = ALIASES.get(m[2], m[2])
        if option not in best or rank[m[1]] >= best[option][0]:
            best[option] = (rank[m[1]], m[3])
    return {option: value for option, (_, value) in best.items()}


def build_config(config: dict[str, str], environ: dict[str, str]) -> tuple[str, Path | None]:
    """The build's ``pip.conf`` text and the CA bundle to copy beside it (None: none found)."""
    bundle = next((Path(p) for p in (config.get("cert"), environ.get("REQUESTS_CA_BUNDLE"),
                                     environ.get("SSL_CERT_FILE"), str(SYSTEM_BUNDLE))
                   if p and Path(p).is_file()), None)
    lines = ["[global]"]
    if bundle is not None:
        lines.append(f"cert = {IN_BUILD}/{BUNDLE}")
    for option in URL_OPTIONS:
        urls = [u for u in config.get(option, "").split()
                if u.startswith(("http://", "https://"))]
        if urls:
            lines.append(f"{option} = {' '.join(urls)}")
    for option in PLAIN_OPTIONS:
        if config.get(option):
            lines.append(f"{option} = {config[option]}")
    return "\n".join(lines) + "\n", bundle


def main() -> int:
    listing = subprocess.run([sys.executable, "-m", "pip", "config", "list"],
                             capture_output=True, text=True, check=True).stdout
    text, bundle = build_config(pip_config(listing), dict(os.environ))
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "pip.conf").write_text(text)
    if bundle is not None:
        shutil.copyfile(bundle, OUT / BUNDLE)
    else:
        (OUT / BUNDLE).unlink(missing_ok=True)
    settings = ", ".join(line.split(" =")[0] for line in text.splitlines()[1:]) or "defaults"
    print(f"docker/pip: pip inside the build uses {settings}"
          + (f" (CA bundle from {bundle})" if bundle else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
