// Trio: per axis, the three places a move can be — MTYPE (executing), NTYPE (next) and the
// process buffer of the process that loaded it — as lanes over time named by move type, with
// DPOS; per process its state, the line it is blocked on and what that line waits for.
//
// TN20-16: one process buffer serves every axis of a process, so while it holds axis 1's long
// move, the process is blocked on axis 0's next move line and axis 0 runs dry (MTYPE = NTYPE
// = 0). That stall is marked on the axis and in the process table.

import { drawTimeGrid, lane, shade, svg, TimeAxis } from "./chart.js";
import { fill, fmt, h, widthOf } from "./dom.js";
import { mtypeName, stalledAxes, waitsFor } from "./model.js";

const LEFT = 190, RIGHT = 10, LANE_H = 16, ROW_GAP = 10;  // LEFT: name, DPOS, stalls, lane
const LANES = [["mtype", "MTYPE"], ["ntype", "NTYPE"], ["pb", "process buf"]];

export class TrioView {
  constructor(root, ctl) {
    this.ctl = ctl;
    this.lanesBox = h("div", { class: "chart-box" });
    this.procTable = h("table", { class: "procs" });
    this.stall = h("div", { class: "stall-box", "data-role": "stall" });
    const key = (cls, text) => h("span", { class: `key ${cls}` }, h("i"), text);
    const legend = h("div", { class: "legend" }, key("mtype", "MTYPE: the move executing"),
                     key("ntype", "NTYPE: the next move"),
                     key("pb", "process buffer: loaded by a process, for this axis"),
                     key("stalled", "axis stalled"), key("blocked", "process blocked on a move line"));
    root.append(
      h("section", { class: "card" }, h("h3", {}, "Axes: MTYPE / NTYPE / process buffer"),
        this.stall, this.lanesBox, legend),
      h("section", { class: "card" }, h("h3", {}, "Processes"), this.procTable));
  }

  axisNumbers() {
    const seen = new Set([0, ...this.ctl.model.axes.keys()]);
    for (const n of Object.keys(this.ctl.snap.axes || {})) seen.add(Number(n));
    return [...seen].sort((a, b) => a - b);
  }

  render(win) {
    const { model } = this.ctl;
    const stalled = stalledAxes(model);
    fill(this.stall, [...stalled.values()].map((s) =>
      h("div", { class: "stall", "data-axis": s.axis, "data-process": s.process },
        `axis ${s.axis} stalled: idle (MTYPE = NTYPE = 0) while process ${s.process} waits to ` +
        `load its move — ${s.text}`)));
    this.lanes(win, stalled);
    this.processes();
  }

  lanes(win, stalled) {
    const { model, snap } = this.ctl;
    const axes = this.axisNumbers();
    const procs = [...model.processes.values()].filter((p) => p.blocked.items.length);
    const width = widthOf(this.lanesBox);
    const rowH = LANES.length * LANE_H + ROW_GAP;
    const top = 4;
    const bottom = top + axes.length * rowH + procs.length * (LANE_H + ROW_GAP);
    const g = svg("svg", { width, height: bottom + 18, class: "chart", "data-role": "axis-lanes" });
    const ax = new TimeAxis(win.t0, win.t1, LEFT, width - RIGHT);
    drawTimeGrid(g, ax, top, bottom);
    let y = top;
    for (const n of axes) {
      const a = model.axis(n);
      const dpos = snap.axes?.[n]?.dpos;
      const stall = stalled.get(n);
      const row = svg("g", { class: `axis-row${stall ? " stalled" : ""}`, "data-axis": n });
      row.appendChild(svg("text", { x: 4, y: y + 12, class: "axis-name" }, `axis ${n}`));
      row.appendChild(svg("text", { x: 4, y: y + 28, class: "axis-sub", "data-role": "dpos" },
                          `DPOS ${fmt(dpos, 3)}`));
      row.appendChild(svg("text", { x: 4, y: y + 42, class: `axis-sub${a.stalls ? " hot" : ""}`,
                                    "data-role": "stalled" },
                          `stalled ${a.stalls}× ${a.stalledTotal(win.t1).toFixed(3)} s`));
      for (const [key, label] of LANES) {
        row.appendChild(svg("rect", { x: LEFT, y, width: ax.x1 - LEFT, height: LANE_H - 2,
                                      class: "lane-bg" }));
        row.appendChild(svg("text", { x: LEFT - 4, y: y + LANE_H - 5, class: "lane-label end" },
                            label));
        lane(row, a.lanes[key], ax, y, LANE_H - 2, mtypeName, `block ${key}`);
        y += LANE_H;
      }
      shade(row, a.stalled, ax, y - LANES.length * LANE_H - 2, y, "stall-bg");
      y += ROW_GAP;
      g.appendChild(row);
    }
    for (const p of procs) {
      g.appendChild(svg("text", { x: 4, y: y + 12, class: "axis-name" }, `process ${p.process}`));
      g.appendChild(svg("rect", { x: LEFT, y, width: ax.x1 - LEFT, height: LANE_H - 2,
                                  class: "lane-bg" }));
      g.appendChild(svg("text", { x: LEFT - 4, y: y + LANE_H - 5, class: "lane-label end" },
                          "blocked"));
      shade(g, p.blocked, ax, y, y + LANE_H - 2, "blocked");
      y += LANE_H + ROW_GAP;
    }
    this.lanesBox.replaceChildren(g);
  }

  processes() {
    const { model, snap } = this.ctl;
    const rows = [...model.processes.values()].sort((a, b) => a.process - b.process).map((p) => {
      const w = waitsFor(model, p);
      const program = snap.programs?.[p.process] ?? (p.process === 0 ? "(terminal)" : "");
      return h("tr", { class: `proc-${p.state}`, "data-process": p.process },
        h("td", {}, String(p.process)), h("td", {}, program),
        h("td", { "data-role": "state" }, p.state), h("td", {}, p.line ?? ""),
        h("td", { class: "code" }, p.blockedOn ?? ""),
        h("td", { "data-role": "waits-for" }, w ? w.text : ""),
        h("td", {}, p.buffer ? `${mtypeName(p.buffer.mtype)} → axis ${p.buffer.axis}` : "empty"));
    });
    fill(this.procTable,
      h("tr", {}, ...["process", "program", "state", "line", "blocked on", "waits for",
                      "process buffer"].map((t) => h("th", {}, t))),
      rows.length ? rows : h("tr", {}, h("td", { colspan: 7, class: "muted" }, "no process ran yet")));
  }
}
