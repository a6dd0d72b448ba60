"""A PMAC streamed fast enough to load the dashboard, and what the page did meanwhile.

* :func:`stream_fast`: a virtual-clock PMAC whose host streams a rotary program through REST
  in steps — load a batch of lines, advance the clock by the time they take to run — paced so
  that its event log grows at a chosen rate in wall time (each line logs ``line_loaded``,
  ``line_calculated``, ``move_start``, ``move_end``, and BREQ edges as lines ahead cross I16 /
  I17). Simulated time runs far faster than wall time (long moves), so the page's history
  window is crossed within seconds.
* :data:`PROBE`: installed in the page, it counts independently of the dashboard's own
  counters — every time the page's ``<main>`` changes (one redraw = one mutation callback,
  the rendering being one synchronous task), every animation frame the browser offers, and
  every long task (over 50 ms) on the main thread.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from motionsim.app.client import MotionSimClient

from tests.browser.page import server_last_seq

#: Settings of the fast PMAC: I16 / I17 as in the browser test's rotary stream.
CONFIG = {"i16": 5, "i17": 10}


@dataclass
class Drive:
    """What :func:`stream_fast` did: lines sent, events logged, wall seconds, steps."""

    lines: int
    first_seq: int
    last_seq: int
    wall_s: float
    steps: int

    @property
    def events(self) -> int:
        return self.last_seq - self.first_seq

    @property
    def rate(self) -> float:
        return self.events / self.wall_s


def _line(i: int, move_ms: int) -> str:
    return f"TM{move_ms} TA{max(1, move_ms // 10)} TS0 X{(i % 4) * 10}"


def start_fast(ms: MotionSimClient, cid: str, *, move_ms: int = 250, backlog: int = 8,
               rotary_words: int = 4000) -> int:
    """Create the fast PMAC ``cid``, load ``backlog`` lines into &1's rotary buffer, run it
    and advance into the middle of its first move (so later steps end mid-move, with lines
    still ahead); returns the lines sent."""
    ms.create_controller("pmac", id=cid, clock="virtual", config=CONFIG)
    ms.define_rotary(cid, 1, rotary_words)
    ms.load_lines(cid, 1, [_line(i, move_ms) for i in range(backlog)], first_seq=1)
    ms.run(cid, 1)
    ms.advance(cid, 0.37 * move_ms / 1000)
    return backlog


def stream_fast(ms: MotionSimClient, cid: str, *, sent: int, events_per_s: float,
                seconds: float, move_ms: int = 250, batch: int = 4,
                max_batch: int = 32) -> Drive:
    """Stream for ``seconds`` of wall time at about ``events_per_s`` logged events a second,
    ``batch`` lines a step numbered after ``sent``: it sleeps when ahead of that pace and,
    when behind (a loaded machine), sends more lines a step, up to ``max_batch``. The log's
    length is read every 4th step (events a line logs), estimated in between."""
    first_seq = server_last_seq(ms, cid)
    start = time.monotonic()
    steps, lines, n, per_line = 0, 0, batch, 5.0
    while time.monotonic() - start < seconds:
        ms.load_lines(cid, 1, [_line(sent + i, move_ms) for i in range(n)],
                      first_seq=sent + 1)
        sent += n
        lines += n
        ms.advance(cid, n * move_ms / 1000)
        steps += 1
        if steps % 4 == 0:
            per_line = (server_last_seq(ms, cid) - first_seq) / lines
        ahead = start + per_line * lines / events_per_s - time.monotonic()
        if ahead > 0:
            time.sleep(ahead)
            n = batch
        else:
            n = min(max_batch, n + batch)
    return Drive(lines=sent, first_seq=first_seq, last_seq=server_last_seq(ms, cid),
                 wall_s=time.monotonic() - start, steps=steps)


#: In-page counters; ``window.__probe`` after :func:`install_probe`.
PROBE = """(animationFrames) => {
  const probe = { redraws: [], rafs: 0, longTasks: [] };
  new MutationObserver(() => probe.redraws.push(performance.now()))
    .observe(document.getElementById("main"), { childList: true, subtree: true,
                                                characterData: true, attributes: true });
  if (animationFrames) {
    const tick = () => { probe.rafs++; requestAnimationFrame(tick); };
    requestAnimationFrame(tick);
  }
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) probe.longTasks.push([e.startTime, e.duration]);
  }).observe({ type: "longtask" });
  window.__probe = probe;
}"""


def install_probe(page: Any, animation_frames: bool = True) -> None:
    """Install :data:`PROBE`; ``animation_frames`` counts them too — a requestAnimationFrame
    loop, which keeps the browser producing frames at 60 Hz (a bench measuring the page's own
    cost goes without)."""
    page.evaluate(PROBE, animation_frames)
