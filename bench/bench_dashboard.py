"""The dashboard at 1 000 events/s in headless Chromium (issue 12 item 3: "stays responsive at
1 000 events/s: it draws at most ~30 frames/s, keeps a bounded window of history, drops
nothing").

A served motionsim (``motionsim serve`` subprocess, virtual clock) and Debian's Chromium driven
by Playwright, the page at its default bounds (120 simulated s, 20 000 points a series). The
load: a PMAC whose host streams a rotary program through REST paced to 1 000 logged events a
wall second (:mod:`tests.browser.load`), in two phases —

* ``sparse``: 250-ms moves, simulated time ~50x wall time: the 120-s window binds within
  seconds, so the page holds a steady ~1 000 points a series;
* ``dense``: 5-ms moves, simulated time about wall time (what a factor-1 clock streaming a
  1 kHz-ish program gives): the window holds everything, the 20 000-point cap binds after a
  minute — the most a series ever holds, the costliest frame.

Per phase: events/s the page applied, frames/s drawn (the dashboard's counter), the event
handling cost per event (``performance.now()`` around parse + apply, the stream's own
counter), render time per frame, the main thread's busy fraction (Chromium's ``TaskDuration``
metric through the DevTools protocol, over wall time), long tasks (> 50 ms), and the JS heap
after a forced garbage collection, sampled through the phase (growth = a leak). The
reference, same run: the same page open with no events for a few seconds (its idle busy
fraction and heap). Targets (absolute, from the issue): frames/s <= 31 (~30) and every
logged event applied.

Run: ``.venv/bin/python bench/bench_dashboard.py [--sparse-s 20] [--dense-s 75]``; writes
``bench/results/dashboard.json``. Without a Chromium it says so and writes nothing.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from motionsim.app.client import MotionSimClient  # noqa: E402

from bench.results import write  # noqa: E402
from bench.served import motionsim  # noqa: E402
from tests.browser.load import install_probe, start_fast, stream_fast  # noqa: E402
from tests.browser.page import server_last_seq  # noqa: E402
from tests.browser.served import CHROMIUM_ARGS, chromium_path  # noqa: E402

RATE = 1000.0
PHASES = (("sparse", 250), ("dense", 5))     # (name, move ms)
SAMPLES = 5                                   # heap samples a phase

READ = """(cid) => {
  const D = window.motionsimDashboard, ctl = D.controllers.get(cid);
  const held = ctl ? [...ctl.model.coords.values()].flatMap(
    (c) => [c.aheadSeries.t.length, c.breqSeries.t.length]) : [];
  return { now: performance.now(), stats: { ...D.stats },
           cost: ctl ? { ...ctl.stream.cost } : { messages: 0, events: 0, ms: 0 },
           lastSeq: ctl ? ctl.model.lastSeq : 0, received: ctl ? ctl.model.received : 0,
           gaps: ctl ? ctl.model.gaps.length : 0, held: Math.max(0, ...held),
           longTasks: window.__probe ? window.__probe.longTasks.slice() : [] };
}"""


class Page:
    """The dashboard page and a DevTools session on it."""

    def __init__(self, page: Any) -> None:
        self.page = page
        self.cdp = page.context.new_cdp_session(page)
        self.cdp.send("Performance.enable")

    def metrics(self) -> dict[str, float]:
        got = self.cdp.send("Performance.getMetrics")["metrics"]
        return {m["name"]: m["value"] for m in got}

    def heap_mb(self) -> float:
        """JS heap in use after a full garbage collection (MB)."""
        self.cdp.send("HeapProfiler.collectGarbage")
        return self.cdp.send("Runtime.getHeapUsage")["usedSize"] / 1e6

    def read(self, cid: str) -> dict[str, Any]:
        return self.page.evaluate(READ, cid)


def window(p: Page, cid: str, run: Any) -> dict[str, Any]:
    """Run ``run()``; what the page did meanwhile (differences of its counters)."""
    m0, r0 = p.metrics(), p.read(cid)
    run()
    m1, r1 = p.metrics(), p.read(cid)
    return {
        "wall_s": (r1["now"] - r0["now"]) / 1000,
        "frames": r1["stats"]["frames"] - r0["stats"]["frames"],
        "render_ms": r1["stats"]["renderMs"] - r0["stats"]["renderMs"],
        "events": r1["cost"]["events"] - r0["cost"]["events"],
        "messages": r1["cost"]["messages"] - r0["cost"]["messages"],
        "handler_ms": r1["cost"]["ms"] - r0["cost"]["ms"],
        "task_s": m1["TaskDuration"] - m0["TaskDuration"],
        "script_s": m1["ScriptDuration"] - m0["ScriptDuration"],
        "layout_s": m1["LayoutDuration"] - m0["LayoutDuration"],
        "style_s": m1["RecalcStyleDuration"] - m0["RecalcStyleDuration"],
        "long_tasks_ms": [d for t, d in r1["longTasks"] if t >= r0["now"]],
        "held_points_max": r1["held"],
    }


def summary(windows: list[dict[str, Any]]) -> dict[str, Any]:
    """The figures over the windows together."""
    total = {k: sum(w[k] for w in windows) for k in
             ("wall_s", "frames", "render_ms", "events", "messages", "handler_ms", "task_s",
              "script_s", "layout_s", "style_s")}
    wall, long_tasks = total["wall_s"], [d for w in windows for d in w["long_tasks_ms"]]
    return {
        "wall_s": wall, "events": total["events"], "events_per_s": total["events"] / wall,
        "messages_per_s": total["messages"] / wall,
        "fps": total["frames"] / wall,
        "fps_max_window": max(w["frames"] / w["wall_s"] for w in windows),
        "handler_us_per_event": 1e3 * total["handler_ms"] / max(1, total["events"]),
        "handler_busy": total["handler_ms"] / 1e3 / wall,
        "render_ms_per_frame": total["render_ms"] / max(1, total["frames"]),
        "main_thread_busy": total["task_s"] / wall,
        "script_busy": total["script_s"] / wall,
        "layout_busy": total["layout_s"] / wall,
        "style_busy": total["style_s"] / wall,
        "long_tasks": len(long_tasks), "longest_task_ms": max(long_tasks, default=0.0),
        "held_points_max": windows[-1]["held_points_max"],
    }


def phase(p: Page, ms: MotionSimClient, cid: str, move_ms: int, seconds: float) -> dict:
    """Stream ``cid`` at RATE for ``seconds``, in SAMPLES windows with the heap sampled after
    each (outside them: a forced collection is not the page's work); its figures."""
    sent = start_fast(ms, cid, move_ms=move_ms)
    p.page.click(f'[data-tab="{cid}"] button.pick')
    p.page.wait_for_selector(f'main [data-controller="{cid}"]', state="attached")
    heap: list[float] = []
    drives, windows = [], []

    def drive() -> None:
        nonlocal sent
        d = stream_fast(ms, cid, sent=sent, events_per_s=RATE, seconds=seconds / SAMPLES,
                        move_ms=move_ms)
        sent = d.lines
        drives.append(d)

    for _ in range(SAMPLES):
        windows.append(window(p, cid, drive))
        heap.append(p.heap_mb())
    fig = summary(windows)
    seq = server_last_seq(ms, cid)
    p.page.wait_for_function("([cid, want]) => window.motionsimDashboard.controllers"
                             ".get(cid).model.lastSeq >= want", arg=[cid, seq], timeout=30_000)
    after = p.read(cid)
    fig.update({
        "driven_events_per_s": sum(d.events for d in drives) / sum(d.wall_s for d in drives),
        "heap_mb": heap, "heap_growth_mb": heap[-1] - heap[0],
        "logged": seq, "applied": after["received"], "gaps": after["gaps"],
        "delivered": after["received"] / seq,
        "simulated_s": ms.clock(cid).t, "lines": sent,
    })
    ms.delete_controller(cid)
    return fig


def idle(p: Page, seconds: float) -> dict[str, float]:
    fig = summary([window(p, "none", lambda: time.sleep(seconds))])
    return {"main_thread_busy": fig["main_thread_busy"], "fps": fig["fps"],
            "heap_mb": p.heap_mb()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sparse-s", type=float, default=20.0, help="wall s of the sparse phase")
    ap.add_argument("--dense-s", type=float, default=75.0, help="wall s of the dense phase")
    args = ap.parse_args()
    exe = chromium_path()
    if exe is None:
        print("no Chromium installed (apt-get install chromium): bench_dashboard not run")
        return
    from playwright.sync_api import sync_playwright

    seconds = {"sparse": args.sparse_s, "dense": args.dense_s}
    with motionsim() as url, MotionSimClient(url) as ms, sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=exe, headless=True, args=CHROMIUM_ARGS)
        page = browser.new_context(viewport={"width": 1500, "height": 1000}).new_page()
        page.goto(f"{url}/dashboard")
        page.wait_for_function("() => !!window.motionsimDashboard")
        install_probe(page, animation_frames=False)   # long tasks only
        p = Page(page)
        reference = idle(p, 5.0)
        figures = {name: phase(p, ms, name, move_ms, seconds[name]) for name, move_ms in PHASES}
        bounds = page.evaluate("() => window.motionsimDashboard.bounds")
        browser.close()
    print(f"idle page: main thread {reference['main_thread_busy']:.1%} busy, "
          f"heap {reference['heap_mb']:.1f} MB")
    print(f"{'phase':<7} {'ev/s':>6} {'msg/s':>6} {'fps':>5} {'us/ev':>6} {'render ms':>9} "
          f"{'busy':>6} {'long':>5} {'held':>6} {'heap MB first..last':>20} {'applied':>15}")
    for name, f in figures.items():
        print(f"{name:<7} {f['events_per_s']:6.0f} {f['messages_per_s']:6.1f} {f['fps']:5.1f} "
              f"{f['handler_us_per_event']:6.1f} {f['render_ms_per_frame']:9.2f} "
              f"{f['main_thread_busy']:6.1%} {f['long_tasks']:5d} {f['held_points_max']:6d} "
              f"{f['heap_mb'][0]:9.1f}..{f['heap_mb'][-1]:<9.1f} "
              f"{f['applied']:>7}/{f['logged']:<7}")
    ratios = {"fps_1000": max(f["fps_max_window"] for f in figures.values()),
              "delivered_1000": min(f["delivered"] for f in figures.values())}
    path = write("dashboard", figures=figures, references={"idle": reference},
                 ratios=ratios, bounds=bounds, rate_asked=RATE)
    print(f"frames/s at most {ratios['fps_1000']:.1f} (target <= 31), events applied / logged "
          f"{ratios['delivered_1000']:.3f} (target >= 1); wrote {path}")


if __name__ == "__main__":
    main()
