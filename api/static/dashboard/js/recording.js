// A controller's own recording drawn: the PMAC's data gathering (GET .../gather) or the
// Trio's SCOPE capture (GET .../scope), one trace per source against simulated time, each
// on its own lane and scale, zoomed to a span the user types (or the whole recording).
//
// The recording is fetched when the user asks (it is not an event stream), page by page as
// the API pages it. A trace draws at most two vertices a pixel column (the lowest and the
// highest sample in it, in time order), however many samples fall in the span.

import { drawTimeGrid, svg, TimeAxis } from "./chart.js";
import { fill, fmt, h, widthOf } from "./dom.js";

const LEFT = 40, RIGHT = 10, TOP = 8, LANE_H = 70, GAP = 10;
const PAGE = 100000;

/** The page's columns as traces: `{name, t, v}` per source (t in simulated seconds). */
export function traces(page) {
  const t = page.columns.t;
  return page.sources.map((s) => ({ name: s.name, t, v: page.columns[s.name] }));
}

/** Index of the first sample at or after `t0` and one past the last at or before `t1`. */
export function spanIndices(t, t0, t1) {
  let lo = 0, hi = t.length;
  while (lo < hi) { const m = (lo + hi) >> 1; if (t[m] < t0) lo = m + 1; else hi = m; }
  const a = lo;
  hi = t.length;
  while (lo < hi) { const m = (lo + hi) >> 1; if (t[m] <= t1) lo = m + 1; else hi = m; }
  return [a, lo];
}

/** Lowest and highest value of `v[a..b)` ([0, 1] when empty or flat around it). */
export function valueRange(v, a, b) {
  let lo = Infinity, hi = -Infinity;
  for (let i = a; i < b; i++) { if (v[i] < lo) lo = v[i]; if (v[i] > hi) hi = v[i]; }
  if (lo === Infinity) return [0, 1];
  if (lo === hi) return [lo - 1, hi + 1];
  return [lo, hi];
}

/**
 * SVG path `d` of samples `a..b` of a trace: a straight line from sample to sample, the
 * samples of one pixel column reduced to their lowest and highest (in the order they came).
 * Returns `{d, vertices}`.
 */
export function linePath(tr, a, b, ax, y) {
  let d = "", vertices = 0;
  let col = null, lo = 0, hi = 0, iLo = 0, iHi = 0;
  const flush = () => {
    if (col === null) return;
    const pts = iLo <= iHi ? [lo, hi] : [hi, lo];
    for (const [k, w] of pts.entries()) {
      if (k === 1 && lo === hi) break;
      d += `${d ? "L" : "M"}${col.toFixed(1)} ${y(w).toFixed(1)}`;
      vertices++;
    }
  };
  for (let i = a; i < b; i++) {
    const px = Math.round(ax.x(tr.t[i]));
    const w = tr.v[i];
    if (px !== col) {
      flush();
      col = px; lo = hi = w; iLo = iHi = i;
    } else {
      if (w < lo) { lo = w; iLo = i; }
      if (w > hi) { hi = w; iHi = i; }
    }
  }
  flush();
  return { d, vertices };
}

export class RecordingPanel {
  constructor(ctl, api) {
    this.ctl = ctl;
    this.api = api;
    this.resource = ctl.kind === "pmac" ? "gather" : "scope";
    this.page = null;
    this.span = null;                 // [t0, t1] zoomed to, or null: the whole recording
    this.msg = h("span", { class: "muted", "data-role": "recording-msg" },
                 ctl.kind === "pmac" ? "DEFINE GATHER, GATHER … then load"
                                     : "SCOPE(ON, …), TRIGGER … then load");
    this.from = h("input", { size: 8, "aria-label": "zoom from (s)", "data-role": "zoom-from",
                             placeholder: "from s" });
    this.to = h("input", { size: 8, "aria-label": "zoom to (s)", "data-role": "zoom-to",
                           placeholder: "to s" });
    this.box = h("div", { class: "chart-box" });
    const button = (text, role, fn) => h("button", { type: "button", "data-role": role,
                                                     onclick: fn }, text);
    this.el = h("section", { class: "card recording", "data-role": "recording" },
      h("header", { class: "cs-head" }, h("h3", {}, `recording (${this.resource})`),
        button("load", "recording-load", () => this.load()),
        this.from, this.to, button("zoom", "zoom", () => this.zoom()),
        button("all", "zoom-all", () => { this.span = null; this.draw(); }), this.msg),
      this.box);
  }

  async load() {
    const base = `/controllers/${encodeURIComponent(this.ctl.id)}/${this.resource}`;
    try {
      let page = await this.api("GET", `${base}?limit=${PAGE}`);
      while (page.next < page.total) {  // more than a page held: the rest, page by page
        const more = await this.api("GET", `${base}?since=${page.next}&limit=${PAGE}`);
        if (more.next === page.next) break;
        for (const [k, col] of Object.entries(more.columns)) page.columns[k].push(...col);
        page.next = more.next;
      }
      this.page = page;
      const n = page.columns.t.length;
      fill(this.msg, `${n} samples of ${page.sources.length} sources, every ` +
                     `${page.period_cycles} servo cycle(s)${page.running ? ", still recording" : ""}`);
      this.draw();
    } catch (e) {
      fill(this.msg, h("span", { class: "error" }, e.message));
    }
  }

  zoom() {
    const t0 = Number(this.from.value), t1 = Number(this.to.value);
    if (!(this.from.value && this.to.value && t1 > t0)) {
      fill(this.msg, h("span", { class: "error" }, "zoom: from < to, in seconds"));
      return;
    }
    this.span = [t0, t1];
    this.draw();
  }

  draw() {
    const page = this.page;
    if (!page) return;
    const t = page.columns.t;
    if (!t.length) { this.box.replaceChildren(h("p", { class: "hint" }, "no samples")); return; }
    const [t0, t1] = this.span ?? [t[0], t[t.length - 1] > t[0] ? t[t.length - 1] : t[0] + 1e-3];
    const [a, b] = spanIndices(t, t0, t1);
    const trs = traces(page);
    const width = widthOf(this.box);
    const height = TOP + trs.length * (LANE_H + GAP) + 18;
    const ax = new TimeAxis(t0, t1, LEFT, width - RIGHT);
    const g = svg("svg", { width, height, class: "chart", "data-role": "recording-chart",
                           "data-t0": t0, "data-t1": t1, "data-samples": b - a });
    drawTimeGrid(g, ax, TOP, height - 18);
    trs.forEach((tr, i) => {
      const top = TOP + i * (LANE_H + GAP), bottom = top + LANE_H;
      const [lo, hi] = valueRange(tr.v, a, b);
      const y = (w) => bottom - ((w - lo) / (hi - lo)) * LANE_H;
      const { d, vertices } = linePath(tr, a, b, ax, y);
      g.appendChild(svg("rect", { x: LEFT, y: top, width: ax.x1 - LEFT, height: LANE_H,
                                  class: "lane-bg" }));
      g.appendChild(svg("path", { d, class: `trace rec rec-${i % 6}`, "data-source": tr.name,
                                  "data-vertices": vertices }));
      g.appendChild(svg("text", { x: LEFT + 4, y: top + 12, class: "axis-label" }, tr.name));
      g.appendChild(svg("text", { x: LEFT - 5, y: top + 10, class: "tick end" }, fmt(hi, 1)));
      g.appendChild(svg("text", { x: LEFT - 5, y: bottom, class: "tick end" }, fmt(lo, 1)));
    });
    this.box.replaceChildren(g);
  }
}
