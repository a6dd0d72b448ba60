// Plain SVG time charts: step traces, level lines, shaded intervals, marks and lanes. Each
// chart is redrawn whole from the model's bounded series; what it draws is bounded by its
// width in pixels (a few vertices, one rect or mark a column), however many events fell in
// the window.

const NS = "http://www.w3.org/2000/svg";

export function svg(tag, attrs = {}, text = null) {
  const el = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attrs)) el.setAttribute(k, v);
  if (text !== null) el.textContent = text;
  return el;
}

/** Maps simulated time [t0, t1] onto pixels [x0, x1]. */
export class TimeAxis {
  constructor(t0, t1, x0, x1) {
    Object.assign(this, { t0, t1, x0, x1 });
    this.k = (x1 - x0) / Math.max(t1 - t0, 1e-9);
  }

  x(t) {
    return this.x0 + (t - this.t0) * this.k;
  }
}

/**
 * SVG path `d` of a step series over the axis window, value -> y by `y(v)`. The changes that
 * fall in one half-pixel column are drawn as one vertical stroke over the values they pass
 * through (at most three vertices: low, high, last), so a trace has at most about six
 * vertices a pixel however many points the window holds.
 */
export function stepPath(series, ax, y) {
  let v = series.valueBefore(ax.t0);
  let d = `M${ax.x0.toFixed(1)} ${y(v).toFixed(1)}`;
  let at = v;                         // the value the path has reached
  let col = null, lo = v, hi = v;     // the column gathering changes and the values they span
  const flush = () => {
    if (col === null) return;
    d += `H${col}`;
    const through = v === hi ? [lo, hi] : v === lo ? [hi, lo] : [lo, hi, v];
    for (const w of through) {
      if (w !== at) { d += `V${y(w).toFixed(1)}`; at = w; }
    }
    col = null;
  };
  const n = series.t.length;
  for (let i = series.indexAt(ax.t0); i < n; i++) {
    const t = series.t[i];
    if (t > ax.t1) break;
    const nv = series.v[i];
    if (nv === v) continue;
    const px = Math.round(ax.x(t) * 2) / 2;
    if (px !== col) {
      flush();
      col = px;
      lo = hi = v;
    }
    v = nv;
    if (v < lo) lo = v;
    if (v > hi) hi = v;
  }
  flush();
  d += `H${ax.x1.toFixed(1)}`;
  return d;
}

/** Time ticks: about `count` round values between t0 and t1, labelled in seconds. */
export function timeTicks(ax, count = 6) {
  const span = ax.t1 - ax.t0;
  const raw = span / count;
  const mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw) || raw;
  const digits = Math.max(0, -Math.floor(Math.log10(step)));
  const out = [];
  for (let t = Math.ceil(ax.t0 / step) * step; t <= ax.t1 + 1e-12; t += step) {
    out.push([ax.x(t), t.toFixed(digits)]);
  }
  return out;
}

/** The time grid; with `labels`, the ticks' values and the axis' unit ("t (s)", simulated
 *  seconds) left of the first tick, in the margin. */
export function drawTimeGrid(g, ax, top, bottom, labels = true) {
  for (const [x, label] of timeTicks(ax)) {
    g.appendChild(svg("line", { x1: x, x2: x, y1: top, y2: bottom, class: "grid" }));
    const anchor = x > ax.x1 - 12 ? "end" : x < ax.x0 + 12 ? "start" : "mid";
    if (labels) g.appendChild(svg("text", { x, y: bottom + 12, class: `tick ${anchor}` }, label));
  }
  if (labels) {
    g.appendChild(svg("text", { x: ax.x0 - 6, y: bottom + 12, class: "axis-unit end",
                                "data-role": "time-unit" }, "t (s)"));
  }
}

/** Round value ticks from 0 to at least `max`: a step of 1, 2 or 5 × 10^k giving about
 *  `count` intervals; the last tick is the axis' top. */
export function valueTicks(max, count = 4) {
  const raw = Math.max(max, 1e-9) / count;
  const mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= raw - 1e-12);
  const top = Math.ceil(max / step - 1e-9) * step;
  const out = [];
  for (let i = 0; i * step <= top + 1e-9; i++) out.push(Number((i * step).toPrecision(12)));
  return out;
}

/** Shaded intervals; one that starts inside the last one drawn (a pixel wide at least)
 *  widens it instead of adding a rect, so there are never more rects than pixel columns. */
export function shade(g, intervals, ax, top, bottom, cls) {
  let last = null, drawnTo = -Infinity;
  for (const [a, b] of intervals.items) {
    const end = b === null ? ax.t1 : b;
    if (end < ax.t0 || a > ax.t1) continue;
    const xa = Math.max(ax.x(a), ax.x0), xb = Math.min(ax.x(end), ax.x1);
    if (last && xa <= drawnTo) {
      drawnTo = Math.max(drawnTo, xb);
      last.setAttribute("width", drawnTo - Number(last.getAttribute("x")));
      last.setAttribute("data-t1", b === null ? "" : b);
      continue;
    }
    last = svg("rect", { x: xa, y: top, width: Math.max(xb - xa, 1), height: bottom - top,
                         class: cls, "data-t0": a, "data-t1": b === null ? "" : b });
    drawnTo = xa + Math.max(xb - xa, 1);
    g.appendChild(last);
  }
}

/** A lane of coloured blocks, one per run of a non-zero code, named by `name(code)`. */
export function lane(g, series, ax, top, h, name, cls) {
  let v = series.valueBefore(ax.t0);
  let start = ax.t0;
  let drawnTo = -Infinity;            // runs thinner than a pixel inside a drawn one: skipped
  const n = series.t.length;
  const flush = (end) => {
    if (!v) return;
    const xa = ax.x(start), xb = ax.x(end);
    if (xb < drawnTo) return;
    const w = Math.max(xb - xa, 1);
    drawnTo = xa + w;
    g.appendChild(svg("rect", { x: xa, y: top, width: w, height: h,
                                class: `${cls} code-${v}`, "data-code": v }));
    if (w > 34) g.appendChild(svg("text", { x: xa + 3, y: top + h - 4, class: "lane-text" },
                                  name(v)));
  };
  for (let i = series.indexAt(ax.t0); i < n && series.t[i] <= ax.t1; i++) {
    if (series.v[i] === v) continue;
    flush(series.t[i]);
    v = series.v[i];
    start = series.t[i];
  }
  flush(ax.t1);
}
