"""The bare SimPy reference loop the PMAC and Trio stream benches compare against.

What a rotary-buffer stream costs with nothing but SimPy: a deque of pre-made lines, an
executor process that takes one line and yields one timeout per 1 ms move, a refill process
that tops the deque up when it runs low (woken by a plain ``env.event()``), and a dict
appended to a list per event (line loaded, move started). No parsing, no planning, no BREQ.

``reference_rate(n_lines)`` returns simulated lines per wall second.

Run: ``.venv/bin/python bench/reference_loop.py [n_lines]``.
"""

from __future__ import annotations

import sys
import time
from collections import deque

import simpy

_LOW, _HIGH = 5, 10


def _run(n_lines: int) -> int:
    env = simpy.Environment()
    lines = [f"X{i % 1000}" for i in range(1000)]
    buf: deque[str] = deque()
    events: list[dict] = []
    state = {"sent": 0, "wake": env.event(), "need": env.event()}

    def refill():
        sent = 0
        while sent < n_lines:
            while len(buf) < _HIGH and sent < n_lines:
                buf.append(lines[sent % 1000])
                sent += 1
                events.append({"t": env.now, "type": "line_loaded", "n": sent})
                if len(events) > 100_000:
                    events.clear()
            if not state["wake"].triggered:
                state["wake"].succeed()
            state["need"] = env.event()
            yield state["need"]

    def execute():
        done = 0
        while done < n_lines:
            if not buf:
                state["wake"] = env.event()
                yield state["wake"]
                continue
            buf.popleft()
            done += 1
            events.append({"t": env.now, "type": "move_start", "n": done})
            if len(buf) < _LOW and not state["need"].triggered:
                state["need"].succeed()
            yield env.timeout(0.001)
        state["sent"] = done

    env.process(refill())
    env.process(execute())
    env.run()
    return state["sent"]


def reference_rate(n_lines: int = 200_000) -> float:
    """Lines per wall second of the bare SimPy reference loop."""
    t0 = time.perf_counter()
    done = _run(n_lines)
    wall = time.perf_counter() - t0
    assert done == n_lines
    return n_lines / wall


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000
    print(f"reference loop: {reference_rate(n):,.0f} lines/s ({n:,} lines)")
