"""Example host program: stream a motion program into a Turbo PMAC rotary buffer over REST.

This is the ``client`` service of ``docker-compose.yml``; it runs the same against a local
``motionsim serve`` (any clock)::

    python examples/compose_client.py --url http://127.0.0.1:8000 --lines 2000

What a host does with a real controller, through motionsim's REST resources:

0. create a PMAC of its own (``POST /controllers``, id ``compose-client-<random>``, deleted
   again at the end), so the client can run any number of times against a running server
   and never meets an earlier run's buffer or program; ``--controller ID`` streams into an
   existing controller instead (its CS program is aborted and its rotary buffer replaced);
1. ``&1 DEFINE ROT 600`` (``PUT /controllers/{id}/coord/1/rotary``);
2. post the program in batches (``POST .../rotary/lines`` with ``first_seq``, so a retried
   batch is never stored twice); a batch that does not fit answers 409 ``buffer_full`` and
   nothing of it is stored;
3. then wait for BREQ — the controller's "send me more" (lines ahead dropped below I16) —
   with ``POST .../clock/run-until {"event": {"type": "breq", "cs": 1, "level": true}}``
   (a virtual clock runs to it, a realtime clock waits for it) and send again;
4. start the program after the first batch (``POST .../coord/1/run`` = ``B0 R``);
5. at the end, wait until the program has run out of lines (``program`` state ``waiting``).

It prints one JSON summary line and exits 0 on success, 1 when the service refused something,
2 when the service never became healthy.
"""

from __future__ import annotations

import argparse
import json
import secrets
import sys
import time

import httpx


def wait_healthy(http: httpx.Client, timeout_s: float) -> None:
    end = time.monotonic() + timeout_s
    while True:
        try:
            if http.get("/health").status_code == 200:
                return
        except httpx.TransportError:
            pass
        if time.monotonic() > end:
            raise SystemExit(f"motionsim at {http.base_url} not healthy after {timeout_s} s")
        time.sleep(0.2)


def program_lines(n: int) -> list[str]:
    """A zig-zag of short incremental linear moves, 2 words each."""
    return [f"X{1 if i % 2 == 0 else -1} Y0.5" for i in range(n)]


def _fresh_controller(http: httpx.Client, clock: str) -> str:
    """Create a PMAC of this run's own; its id."""
    id = f"compose-client-{secrets.token_hex(4)}"
    http.post("/controllers", json={"id": id, "kind": "pmac",
                                    "clock": {"mode": clock}}).raise_for_status()
    return id


def _reuse_controller(http: httpx.Client, id: str, cs: int) -> None:
    """Stop what an earlier run left in ``id``'s CS and remove its rotary buffer."""
    base = f"/controllers/{id}/coord/{cs}"
    http.post(f"{base}/abort").raise_for_status()
    r = http.delete(f"{base}/rotary")
    if r.status_code not in (204, 404):
        r.raise_for_status()


def stream(http: httpx.Client, args: argparse.Namespace, controller: str) -> dict:
    """Steps 1-5 on ``controller``; the summary."""
    base = f"/controllers/{controller}/coord/{args.cs}"
    clock_path = f"/controllers/{controller}/clock/run-until"
    http.put(f"{base}/rotary", json={"size_words": args.words}).raise_for_status()
    header = ["INC", "LINEAR", "TA10", "TS0", f"TM{args.move_ms}"]
    lines = [*header, *program_lines(args.lines)]
    sent = 0
    waits = 0
    started = False
    while sent < len(lines):  # seq numbers: 1 = first header line
        batch = lines[sent:sent + args.batch]
        r = http.post(f"{base}/rotary/lines", json={"lines": batch, "first_seq": sent + 1})
        if r.status_code == 409 and r.json().get("code") == "buffer_full":
            waits += 1
            http.post(clock_path, json={"event": {"type": "breq", "cs": args.cs,
                                                  "level": True},
                                        "timeout_s": 5}).raise_for_status()
            continue
        r.raise_for_status()
        sent += len(batch)
        if not started:
            http.post(f"{base}/run").raise_for_status()
            started = True
    coord = http.get(base).json()
    starved = coord["program"]["state"] == "waiting" and coord["rotary"]["lines_ahead"] > 0
    if coord["program"]["state"] != "waiting" or coord["rotary"]["lines_ahead"] > 0:
        http.post(clock_path, json={"event": {"type": "program", "cs": args.cs,
                                              "state": "waiting"},
                                    "timeout_s": 60}).raise_for_status()
        coord = http.get(base).json()
    events = http.get(f"/controllers/{controller}/events",
                      params={"type": "program", "limit": 100_000}).json()["events"]
    waits_for_lines = [e["t"] for e in events
                       if e.get("cs") == args.cs and e["state"] == "waiting"]
    return {"controller": controller, "lines_sent": sent, "breq_waits": waits,
            "starved": len(waits_for_lines) - 1 + int(starved),
            "ran_out_at": waits_for_lines[-1] if waits_for_lines else None,
            "program": coord["program"]}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--url", default="http://127.0.0.1:8000")
    ap.add_argument("--controller", default=None,
                    help="stream into this existing controller (default: a fresh one)")
    ap.add_argument("--clock", choices=("realtime", "virtual"), default="realtime",
                    help="clock of the fresh controller")
    ap.add_argument("--keep", action="store_true", help="do not delete the fresh controller")
    ap.add_argument("--cs", type=int, default=1)
    ap.add_argument("--words", type=int, default=600, help="rotary buffer size (DEFINE ROT)")
    ap.add_argument("--lines", type=int, default=2000, help="program lines to stream")
    ap.add_argument("--batch", type=int, default=20, help="lines per POST")
    ap.add_argument("--move-ms", type=int, default=20, help="TM of each move (TA10 TS0)")
    ap.add_argument("--wait-healthy-s", type=float, default=60.0)
    args = ap.parse_args(argv)

    with httpx.Client(base_url=args.url, timeout=60, trust_env=False) as http:
        try:
            wait_healthy(http, args.wait_healthy_s)
        except SystemExit as exc:
            print(exc, file=sys.stderr)
            return 2
        fresh = args.controller is None
        try:
            if fresh:
                controller = _fresh_controller(http, args.clock)
            else:
                controller = args.controller
                _reuse_controller(http, controller, args.cs)
            try:
                summary = stream(http, args, controller)
            finally:
                if fresh and not args.keep:
                    http.delete(f"/controllers/{controller}")
        except httpx.HTTPStatusError as exc:
            print(f"error: {exc.response.status_code} {exc.response.text}", file=sys.stderr)
            return 1
        print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
