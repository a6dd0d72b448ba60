"""Example host program: stream a motion program into a Turbo PMAC rotary buffer over REST.

This is the ``client`` service of ``docker-compose.yml``; it runs the same against a local
``motionsim serve`` (any clock)::

    python examples/compose_client.py --url http://127.0.0.1:8000 --lines 2000

What a host does with a real controller, through motionsim's REST resources:

1. ``&1 DEFINE ROT 600`` (``PUT /controllers/pmac/coord/1/rotary``), after deleting any old one;
2. post the program in batches (``POST .../rotary/lines`` with ``first_seq``, so a retried
   batch is never stored twice); a batch that does not fit answers 409 ``buffer_full`` and
   nothing of it is stored;
3. then wait for BREQ — the controller's "send me more" (lines ahead dropped below I16) —
   with ``POST .../clock/run-until {"event": {"type": "breq", "cs": 1, "level": true}}``
   (a virtual clock runs to it, a realtime clock waits for it) and send again;
4. start the program after the first batch (``POST .../coord/1/run`` = ``B0 R``);
5. at the end, wait until the program has run out of lines (``program`` state ``waiting``).

It prints one JSON summary line and exits 0 on success.
"""

from __future__ import annotations

import argparse
import json
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


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--url", default="http://127.0.0.1:8000")
    ap.add_argument("--controller", default="pmac")
    ap.add_argument("--cs", type=int, default=1)
    ap.add_argument("--words", type=int, default=600, help="rotary buffer size (DEFINE ROT)")
    ap.add_argument("--lines", type=int, default=2000, help="program lines to stream")
    ap.add_argument("--batch", type=int, default=20, help="lines per POST")
    ap.add_argument("--move-ms", type=int, default=20, help="TM of each move (TA10 TS0)")
    args = ap.parse_args(argv)

    base = f"/controllers/{args.controller}/coord/{args.cs}"
    clock_path = f"/controllers/{args.controller}/clock/run-until"
    with httpx.Client(base_url=args.url, timeout=60, trust_env=False) as http:
        wait_healthy(http, 60)
        r = http.delete(f"{base}/rotary")
        if r.status_code not in (204, 404, 409):
            r.raise_for_status()
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
            if r.status_code >= 400:
                print(f"error: {r.status_code} {r.text}", file=sys.stderr)
                return 1
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
        events = http.get(f"/controllers/{args.controller}/events",
                          params={"type": "program", "limit": 100_000}).json()["events"]
        waits_for_lines = [e["t"] for e in events
                           if e.get("cs") == args.cs and e["state"] == "waiting"]
        print(json.dumps({"lines_sent": sent, "breq_waits": waits,
                          "starved": len(waits_for_lines) - 1 + int(starved),
                          "ran_out_at": waits_for_lines[-1] if waits_for_lines else None,
                          "program": coord["program"]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
