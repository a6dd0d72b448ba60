"""``python -m motionsim.app.healthcheck``: exit 0 when the local service answers ``/health``.

The container image's ``HEALTHCHECK`` (and docker-compose's) runs it, so it follows the port the
service was configured with: ``MOTIONSIM_PORT`` (default 8000), the same variable
``motionsim serve`` reads, and ``MOTIONSIM_HOST`` unless that is a wildcard address.
"""

from __future__ import annotations

import os
import sys
import urllib.error
import urllib.request

WILDCARDS = {"", "0.0.0.0", "::", "[::]"}


def health_url(env: dict[str, str] | None = None) -> str:
    """The ``/health`` URL of the service configured by ``env`` (default: ``os.environ``)."""
    env = dict(os.environ) if env is None else env
    host = env.get("MOTIONSIM_HOST", "127.0.0.1")
    host = "127.0.0.1" if host in WILDCARDS else host
    if ":" in host and not host.startswith("["):
        host = f"[{host}]"
    port = int(env.get("MOTIONSIM_PORT", "8000"))
    return f"http://{host}:{port}/health"


def main() -> int:
    url = health_url()
    try:
        with urllib.request.urlopen(url, timeout=2) as response:  # noqa: S310 - local URL
            ok = response.status == 200
    except (urllib.error.URLError, OSError) as exc:
        print(f"{url}: {exc}", file=sys.stderr)
        return 1
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
