"""The dashboard at 1 000 events/s (issue 12 item 3): it stays responsive — draws at most
~30 frames a second, keeps a bounded window of history — and drops nothing from its model.

A virtual-clock PMAC streams 250-ms moves through REST in small steps, paced to 1 200 logged
events a wall second, so the page gets a WebSocket message every ~20 ms (more often than it
may draw). The page's point cap is lowered (``?points=600``) so the lines-ahead trace (two
points a line) crosses it within the drive; the 120-s window is checked after the host stops
feeding for 130 simulated seconds (all held before must have aged out). Frames are counted
twice — the dashboard's own counter and, from outside it, every change of the page's
``<main>`` — against the animation frames the browser offered meanwhile (about 60 a second),
so it is the cap that limits the drawing. Only bounds a loaded machine cannot break are
asserted (at most ~30 frames a second, bounded history, nothing dropped); the rates reached
are bench/bench_dashboard.py's figures. What a chart draws is bounded by its width in
pixels, not by the points its window holds (the second test).
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import pytest

from tests.browser.conftest import Browser, dashboard
from tests.browser.load import install_probe, start_fast, stream_fast
from tests.browser.page import caught_up, select, server_last_seq, shown

FAST = "fast"
ASKED_EV_S = 1200        # the drive's pace; the page must see at least 1 000 events/s
DRIVE_S = 5.0
POINTS = 600             # ?points=: held per series at most POINTS + POINTS / 4
MOVE_MS = 250

READ = """(cid) => {
  const D = window.motionsimDashboard, ctl = D.controllers.get(cid), m = ctl.model;
  const c = m.cs(1);
  const steps = (s) => ({ n: s.t.length, first: s.t.length ? s.t[0] : null });
  const spans = (s) => ({ n: s.items.length,
                          first: s.items.length ? (s.items[0][1] ?? s.items[0][0]) : null });
  const p = window.__probe;
  return {
    now: performance.now(), stats: { ...D.stats }, bounds: D.bounds, cost: { ...ctl.stream.cost },
    t: m.t, tFirst: m.tFirst, counts: { ...m.counts }, lines: c.lines.size,
    series: { ahead: steps(c.aheadSeries), breq: steps(c.breqSeries),
              starved: spans(c.starved), syncM: spans(m.syncM) },
    probe: p ? { redraws: p.redraws.slice(), rafs: p.rafs, longTasks: p.longTasks.length }
             : null,
  };
}"""


def read(page, cid: str) -> dict:
    return page.evaluate(READ, cid)


def most_in_one_second(times_ms: list[float]) -> int:
    """The most instants that fall in any one-second window."""
    best, lo = 0, 0
    for hi, t in enumerate(times_ms):
        while t - times_ms[lo] >= 1000.0:
            lo += 1
        best = max(best, hi - lo + 1)
    return best


@pytest.fixture(scope="module")
def fast_page(served: str) -> Iterator[Browser]:
    """The dashboard with its point cap lowered; its sockets not routed (see ``dashboard``)."""
    with dashboard(served, f"/dashboard?points={POINTS}", route_sockets=False) as b:
        yield b


def test_at_1000_events_per_s_it_draws_at_most_30_fps_bounded_and_drops_nothing(fast_page, ms):
    b = fast_page
    sent = start_fast(ms, FAST, move_ms=MOVE_MS)
    b.page.wait_for_selector(f'[data-tab="{FAST}"]')
    select(b, FAST)
    caught_up(b, ms, FAST)
    install_probe(b.page)
    before = read(b.page, FAST)
    assert before["bounds"] == {"fps": 30, "historyS": 120, "maxPoints": POINTS,
                                "maxHeld": POINTS + POINTS // 4}

    drive = stream_fast(ms, FAST, sent=sent, events_per_s=ASKED_EV_S, seconds=DRIVE_S,
                        move_ms=MOVE_MS)
    end = read(b.page, FAST)
    window_s = (end["now"] - before["now"]) / 1000
    seen = end["cost"]["events"] - before["cost"]["events"]
    # The pace reached (about ASKED_EV_S on a quiet machine) is bench_dashboard.py's figure:
    # a loaded machine slows the drive and the browser, so no lower bound on a rate is
    # asserted here, only bounds a stall cannot break.
    load = (drive.rate, seen / window_s, end["probe"]["rafs"] / window_s)
    assert seen > 0 and drive.events > 0, load

    # -- at most ~30 frames a second, however often events arrive ------------------------
    frames = end["stats"]["frames"] - before["stats"]["frames"]
    redraws = end["probe"]["redraws"]
    assert frames / window_s <= 31, (frames, load)
    assert len(redraws) / window_s <= 31, (len(redraws), load)
    assert most_in_one_second(redraws) <= 33, (redraws, load)
    assert frames >= 1                                     # and it did draw meanwhile

    # -- at most maxHeld points a series, however many were pushed -----------------------
    final = caught_up(b, ms, FAST)
    after = read(b.page, FAST)
    bounds, series = after["bounds"], after["series"]
    pushed = after["counts"]["line_loaded"] + after["counts"]["line_calculated"]
    assert pushed > 2 * bounds["maxHeld"]              # the lines-ahead trace got that many
    for name, s in series.items():
        assert s["n"] < bounds["maxHeld"], (name, s)
    assert series["ahead"]["n"] >= bounds["maxPoints"]    # capped, not emptied
    assert after["lines"] <= 40                           # the line list keeps the last 40

    # -- nothing dropped: every event the service logged applied once, in order ------------
    assert int(final["lastSeq"]) == server_last_seq(ms, FAST) == int(final["received"])
    assert (final["gaps"], final["duplicates"]) == ("0", "0")

    # -- lines ahead shown equals PR at paused instants right after the load ---------------
    sent, ahead = drive.lines, []
    for k in range(4):
        sent = stream_fast(ms, FAST, sent=sent, events_per_s=ASKED_EV_S, seconds=0.3,
                           move_ms=MOVE_MS).lines
        ms.advance(FAST, 0.3 * k)          # into the lines ahead, by 0 to 3.6 moves
        ms.set_clock(FAST, paused=True)
        caught_up(b, ms, FAST)
        pr = ms.coord(FAST, 1)["rotary"]["lines_ahead"]
        assert shown(b, FAST, "#cs-1 [data-role=lines-ahead]") == str(pr)
        ms.set_clock(FAST, paused=False)       # a paused PMAC answers PR only once running
        reply = ms.terminal(FAST, "&1 PR")
        assert reply.reply.strip() == str(pr), reply
        ahead.append(pr)
    assert len(set(ahead)) > 1, ahead   # several levels, not only an empty buffer

    # -- a window of 120 simulated s: the host stops feeding for 130 s, then feeds again ----
    held = read(b.page, FAST)["series"]
    ms.advance(FAST, 130.0)                 # runs out of lines: `waiting`
    stream_fast(ms, FAST, sent=sent, events_per_s=ASKED_EV_S, seconds=0.1, move_ms=MOVE_MS)
    final = caught_up(b, ms, FAST)
    late = read(b.page, FAST)
    tmin = late["t"] - late["bounds"]["historyS"]
    assert late["t"] - held["ahead"]["first"] > late["bounds"]["historyS"]  # all held aged
    for name, s in late["series"].items():
        assert s["first"] is None or s["first"] >= tmin, (name, s, tmin)
    assert 0 < late["series"]["ahead"]["n"] < held["ahead"]["n"] // 4, (held, late)
    assert late["series"]["starved"]["n"] >= 1         # the 130 s out of lines, still shown
    assert int(final["received"]) == int(final["lastSeq"]) == server_last_seq(ms, FAST)
    assert (final["gaps"], final["duplicates"]) == ("0", "0")
    assert b.errors == []


DRAW = """async () => {
  const { Steps, Intervals } = await import("/dashboard/static/js/series.js");
  const { stepPath, shade, svg, TimeAxis } = await import("/dashboard/static/js/chart.js");
  const ax = new TimeAxis(0, 10, 40, 1440);          // 1 400 px for 10 s
  const s = new Steps(0);
  let x = 12345;                                     // a fixed pseudo-random walk over 0..9
  for (let i = 0; i < 20000; i++) {
    x = (x * 1103515245 + 12345) % 2147483648;
    s.t.push(i * 0.0005);                            // bypass the point cap: 20 000 held
    s.v.push(x % 10);
  }
  const y = (v) => 100 - 10 * v;
  const d = stepPath(s, ax, y);
  // expected: per half-pixel column, the lowest and highest value the trace passes through
  const cols = new Map();
  let v = s.initial;
  for (let i = 0; i < s.t.length; i++) {
    if (s.v[i] === v) continue;
    const px = Math.round(ax.x(s.t[i]) * 2) / 2;
    const c = cols.get(px) ?? { lo: v, hi: v };
    v = s.v[i];
    c.lo = Math.min(c.lo, v); c.hi = Math.max(c.hi, v);
    cols.set(px, c);
  }
  const spans = new Intervals();
  for (let i = 0; i < 5000; i++) {
    spans.set(i * 0.002, true);
    spans.set(i * 0.002 + 0.001, false);
  }
  const g = svg("svg");
  shade(g, spans, ax, 0, 10, "starved");
  const rects = [...g.children].map((r) => [Number(r.getAttribute("x")),
                                            Number(r.getAttribute("width"))]);
  return { d, cols: [...cols.entries()].map(([px, c]) => [px, y(c.hi), y(c.lo)]),
           last: y(v), rects };
}"""


def test_a_trace_of_20000_points_draws_a_few_vertices_a_pixel_through_every_level(fast_page):
    """A chart's cost follows its width, not the points its window holds: a step trace
    passes through each half-pixel column's lowest and highest value in at most three
    vertices; 5 000 intervals in 1 400 px shade as rects that never overlap."""
    got = fast_page.page.evaluate(DRAW)
    d = got["d"]
    commands = re.findall(r"([MHV])(-?[\d.]+)", d)
    assert len(got["cols"]) <= 2 * 1400 + 1                # half-pixel columns
    assert len(commands) <= 2 + 4 * len(got["cols"]), len(commands)  # H + at most 3 V each
    # rebuild each column's vertical extent from the path
    extent: dict[float, list[float]] = {}
    start = re.match(r"M(-?[\d.]+) (-?[\d.]+)", d)
    x, yv = float(start[1]), float(start[2])
    for cmd, val in commands[1:]:
        if cmd == "H":
            x = float(val)
        else:
            ext = extent.setdefault(x, [yv, yv])
            ext[0], ext[1] = min(ext[0], float(val)), max(ext[1], float(val))
        yv = float(val) if cmd == "V" else yv
    want = {px: [top, bottom] for px, top, bottom in got["cols"]}
    assert extent == want                   # y values are exact tenths
    assert float(re.findall(r"V(-?[\d.]+)", d)[-1]) == got["last"]
    xs = got["rects"]
    assert len(xs) <= 1400
    assert all(x0 + w <= x1 + 1e-9 for (x0, w), (x1, _) in zip(xs, xs[1:], strict=False))
