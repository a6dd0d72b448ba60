// PMAC: one card per coordinate system that has a rotary buffer or a program state.
//
// The chart is the rotary buffer seen by a streaming host: lines ahead of move planning (what
// `PR` reports) against I17 (at or above it BREQ stays low: "buffer full") and I16 (below it
// a calculated line raises BREQ again), BREQ as a step trace beneath (a line loaded below I17
// is a low→high pulse), the program's `waiting` (ran out of lines) shaded, and the
// synchronous M-variable writes as marks on the same time axis (TSRM p46, p286; TUM p337).

import { drawTimeGrid, shade, stepPath, svg, TimeAxis, valueTicks } from "./chart.js";
import { fill, fmt, h, widthOf } from "./dom.js";

const LEFT = 40, RIGHT = 10, TOP = 14, PLOT_H = 130, GAP = 12, BREQ_H = 22, WRITE_H = 7;
const LINES_SHOWN = 14;

export class PmacView {
  constructor(root, ctl) {
    this.ctl = ctl;
    this.root = root;
    this.cards = new Map();
    this.empty = h("p", { class: "hint" },
                   "No coordinate system has a rotary buffer yet: `&1 DEFINE ROT 600` at the " +
                   "terminal, or PUT /controllers/{id}/coord/1/rotary.");
    this.alerts = h("div", { class: "alerts" });
    root.append(this.alerts, this.empty);
  }

  csNumbers() {
    const seen = new Set(this.ctl.model.coords.keys());
    for (const n of Object.keys(this.ctl.snap.coordStates || {})) seen.add(Number(n));
    return [...seen].sort((a, b) => a - b);
  }

  card(n) {
    let c = this.cards.get(n);
    if (c) return c;
    const head = h("header", { class: "cs-head" });
    const chart = h("div", { class: "chart-box" });
    const key = (cls, text) => h("span", { class: `key ${cls}` }, h("i"), text);
    const legend = h("div", { class: "legend" }, key("ahead", "lines ahead (PR)"),
                     key("i16", "I16: BREQ on below"), key("i17", "I17: BREQ off at"),
                     key("breq", "BREQ"), key("starved", "starved (program waiting for lines)"),
                     key("write", "host write"), key("sync", "sync M write"));
    const lines = h("table", { class: "lines" });
    const el = h("section", { class: "card cs", "data-cs": n, id: `cs-${n}` },
                 head, h("div", { class: "cs-body" }, h("div", {}, chart, legend), h("div", { class: "lines-box" }, lines)));
    c = { el, head, chart, lines };
    this.cards.set(n, c);
    const after = [...this.cards.keys()].filter((k) => k < n).sort((a, b) => b - a)[0];
    if (after === undefined) this.root.insertBefore(el, this.empty.nextSibling);
    else this.cards.get(after).el.after(el);
    return c;
  }

  render(win) {
    const { model } = this.ctl;
    fill(this.alerts, model.alerts.slice(-3).map((a) =>
      h("div", { class: "alert" }, `t = ${fmt(a.t)} s: ${a.text}`)));
    const numbers = this.csNumbers();
    this.empty.hidden = numbers.length > 0;
    for (const n of numbers) this.renderCs(n, this.card(n), win);
    for (const [n, c] of this.cards) {
      if (!numbers.includes(n)) { c.el.remove(); this.cards.delete(n); }
    }
  }

  renderCs(n, card, win) {
    const starvedS = this.ctl.model.cs(n).starvedTotal(win.t1);
    const { model, snap } = this.ctl;
    const c = model.cs(n);
    const rest = (snap.coords || {})[n] || {};
    const rot = rest.rotary;
    const prog = c.program;
    const feed = rest.program?.feed_override;
    const kv = (label, value, role, cls = "") =>
      h("span", { class: `kv ${cls}` }, label, " ", h("b", { "data-role": role }, value));
    fill(card.head,
      h("h3", {}, `&${n}`),
      h("span", { class: `state state-${prog.state}`, "data-role": "program-state" }, prog.state),
      c.executing !== null ? kv("executing", `line ${c.executing}`, "executing") : null,
      kv("lines ahead (PR)", String(c.linesAhead), "lines-ahead"),
      kv("BREQ", c.breq ? "high" : "low", "breq", c.breq ? "on" : "off"),
      kv("I16", fmt(snap.i16), "i16"), kv("I17", fmt(snap.i17), "i17"),
      feed !== undefined ? kv("feed", `${fmt(feed, 1)} %`, "feed") : null,
      h("span", { class: `kv starved-tally${c.starvations ? " hot" : ""}`,
                  title: "times the program ran out of rotary lines, and for how long in all" },
        "starved ", h("b", { "data-role": "starved-count" }, `${c.starvations}×`), " ",
        h("b", { "data-role": "starved-total" }, `${starvedS.toFixed(3)} s`)),
      rot ? kv("rotary", `${rot.used_words}/${rot.size_words} words${rot.open ? ", open" : ""}`,
               "rotary") : h("span", { class: "kv muted" }, "no rotary buffer"),
      prog.error ? h("span", { class: "error", "data-role": "error" }, `run-time error: ${prog.error}`)
                 : null);
    this.chart(card.chart, c, win);
    this.lineTable(card.lines, c);
  }

  chart(box, c, win) {
    const { model, snap } = this.ctl;
    const width = widthOf(box);
    const bottom = TOP + PLOT_H;
    const breqTop = bottom + GAP, breqBottom = breqTop + BREQ_H;
    const height = breqBottom + 18;
    const ax = new TimeAxis(win.t0, win.t1, LEFT, width - RIGHT);
    let ymax = Math.max(4, (snap.i17 ?? 0) + 2, c.linesAhead + 1);
    const s = c.aheadSeries;
    for (let i = s.indexAt(win.t0); i < s.t.length; i++) ymax = Math.max(ymax, s.v[i] + 1);
    const ticks = valueTicks(ymax, 4);
    ymax = ticks[ticks.length - 1];
    const plotBottom = bottom - WRITE_H;             // host writes are marked beneath the plot
    const y = (v) => plotBottom - (v / ymax) * (PLOT_H - WRITE_H);
    const g = svg("svg", { width, height, class: "chart", "data-role": "rotary-chart" });
    drawTimeGrid(g, ax, TOP, breqBottom);
    shade(g, c.starved, ax, TOP, breqBottom, "starved");
    for (const v of ticks) {
      g.appendChild(svg("line", { x1: LEFT, x2: width - RIGHT, y1: y(v), y2: y(v), class: "grid" }));
      g.appendChild(svg("text", { x: LEFT - 5, y: y(v) + 4, class: "tick end", "data-tick": v },
                        String(v)));
    }
    const levels = [];
    for (const [name, level] of [["i16", snap.i16], ["i17", snap.i17]]) {
      if (level === undefined || level === null) continue;
      g.appendChild(svg("line", { x1: LEFT, x2: width - RIGHT, y1: y(level), y2: y(level),
                                  class: `level ${name}`, "data-level": level }));
      levels.push([name, level]);
    }
    g.appendChild(svg("path", { d: stepPath(s, ax, y), class: "trace ahead",
                                "data-role": "lines-ahead-trace" }));
    this.writeMarks(g, c, ax, plotBottom, bottom);
    // labels last, on a white halo: no trace is drawn over them
    g.appendChild(svg("text", { x: 4, y: TOP - 4, class: "axis-label" }, "lines ahead"));
    for (const [name, level] of levels) {
      g.appendChild(svg("text", { x: width - RIGHT - 4, y: y(level) - 3,
                                  class: `level-text end ${name}` },
                        `${name.toUpperCase()} = ${level}`));
    }
    let markedAt = -Infinity;            // one mark a pixel column: the first write in it
    for (const [t, label, cs] of model.syncM.items) {
      if (t < win.t0 || t > win.t1 || (cs !== undefined && cs !== c.cs)) continue;
      const x = ax.x(t);
      if (x - markedAt < 1) continue;
      markedAt = x;
      const mark = svg("line", { x1: x, x2: x, y1: TOP, y2: TOP + 8, class: "sync-m" });
      mark.appendChild(svg("title", {}, `t = ${fmt(t)} s: ${label}`));
      g.appendChild(mark);
    }
    const by = (v) => breqBottom - v * (BREQ_H - 4) - 2;
    g.appendChild(svg("rect", { x: LEFT, y: breqTop, width: ax.x1 - LEFT, height: BREQ_H,
                                class: "lane-bg" }));
    g.appendChild(svg("text", { x: 4, y: breqBottom - 6, class: "axis-label" }, "BREQ"));
    g.appendChild(svg("path", { d: stepPath(c.breqSeries, ax, by), class: "trace breq",
                                "data-role": "breq-trace" }));
    box.replaceChildren(g);
  }

  /** One mark a pixel column for the host's writes (lines loaded at one instant), in the
   *  strip beneath the plot; its title says when and how many lines. */
  writeMarks(g, c, ax, top, bottom) {
    let markedAt = -Infinity;
    for (const [t, lines] of c.writes.items) {
      if (t < ax.t0 || t > ax.t1) continue;
      const x = ax.x(t);
      if (x - markedAt < 1) continue;
      markedAt = x;
      const mark = svg("line", { x1: x, x2: x, y1: top + 1, y2: bottom, class: "host-write",
                                 "data-t": t });
      mark.appendChild(svg("title", {}, `t = ${fmt(t)} s: host wrote ${lines} line(s)`));
      g.appendChild(mark);
    }
  }

  lineTable(table, c) {
    let lines = [...c.lines.values()];
    const at = lines.findIndex((l) => l.n === c.executing);
    lines = at >= 0 ? lines.slice(Math.max(0, at - 3), Math.max(0, at - 3) + LINES_SHOWN)
                    : lines.slice(-LINES_SHOWN);
    const rows = lines.map((l) =>
      h("tr", { class: `line-${l.state}${l.n === c.executing ? " executing" : ""}`,
                "data-n": l.n },
        h("td", { class: "n" }, String(l.n)), h("td", { class: "lstate" }, l.state),
        h("td", { class: "text" }, l.text)));
    fill(table, h("tr", {}, h("th", {}, "n"), h("th", {}, "state"), h("th", {}, "line")), rows);
  }
}
