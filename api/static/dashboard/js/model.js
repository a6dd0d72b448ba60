// One controller's state, built from its event stream alone (docs/API.md "Events"). Every
// event is applied exactly once, in seq order; the counters (lines ahead, BREQ, MTYPE, ...)
// are exact, only the drawn history is bounded (series.js).

import { HISTORY_S, Intervals, Marks, Steps } from "./series.js";

export const LAST_LINES = 40;      // rotary lines listed per coordinate system

// Trio MTYPE / NTYPE codes (shared/spec/trio.md §10.1; 0-31 from two third-party enums
// consistent with TN20 and the Trajexia manual).
export const MTYPE_NAMES = {
  0: "IDLE", 1: "MOVE", 2: "MOVEABS", 3: "MHELICAL", 4: "MOVECIRC", 5: "MOVEMODIFY",
  6: "MOVESP", 7: "MOVEABSSP", 8: "MOVECIRCSP", 9: "MHELICALSP", 10: "FORWARD", 11: "REVERSE",
  12: "DATUM", 13: "CAM", 14: "FWD_JOG", 15: "REV_JOG", 20: "CAMBOX", 21: "CONNECT",
  22: "MOVELINK", 23: "CONNPATH", 24: "FLEXLINK", 30: "MOVETANG", 31: "MSPHERICAL",
};

export function mtypeName(code) {
  return MTYPE_NAMES[code] ?? `type ${code}`;
}

class CoordSystem {
  constructor(cs) {
    this.cs = cs;
    this.linesAhead = 0;                // lines stored, not yet calculated: what PR reports
    this.breq = false;
    this.program = { state: "idle", line: null, error: null };
    this.errors = [];                   // [{t, state, error}]
    this.lines = new Map();             // n -> {n, text, words, state}
    this.executing = null;
    this.loaded = 0;
    this.aheadSeries = new Steps(0);
    this.breqSeries = new Steps(0);
    this.starved = new Intervals();     // program state "waiting": ran out of rotary lines
    // every starvation since the log began (exact; the drawn intervals are bounded):
    this.starvations = 0;               // how many times the program ran out of lines
    this.starvedS = 0;                  // their total length, closed ones
    this.starvedSince = null;           // start of the one under way
    this.writes = new Marks();          // [t, lines]: host writes (lines loaded at one instant)
  }

  /** Total starved time up to `t` (the open starvation counted to `t`). */
  starvedTotal(t) {
    return this.starvedS + (this.starvedSince === null ? 0 : Math.max(0, t - this.starvedSince));
  }

  setStarved(t, on) {
    this.starved.set(t, on);
    if (on && this.starvedSince === null) {
      this.starvations++;
      this.starvedSince = t;
    } else if (!on && this.starvedSince !== null) {
      if (t > this.starvedSince) this.starvedS += t - this.starvedSince;
      else this.starvations--;          // lines arrived at the instant it ran out: no starvation
      this.starvedSince = null;
    }
  }

  setAhead(t, n) {
    this.linesAhead = n;
    this.aheadSeries.push(t, n);
  }

  line(n) {
    return this.lines.get(n);
  }
}

class Axis {
  constructor(axis) {
    this.axis = axis;
    this.mtype = 0;
    this.ntype = 0;
    this.pb = 0;                        // the move type a process buffer holds for this axis
    this.pbProcess = null;
    this.lanes = { mtype: new Steps(0), ntype: new Steps(0), pb: new Steps(0) };
    this.stalled = new Intervals();     // idle while a process waits to load a move for it
    this.stalls = 0;                    // every stall since the log began (exact)
    this.stalledS = 0;
    this.stalledSince = null;
  }

  setStalled(t, on) {
    this.stalled.set(t, on);
    if (on && this.stalledSince === null) {
      this.stalls++;
      this.stalledSince = t;
    } else if (!on && this.stalledSince !== null) {
      if (t > this.stalledSince) this.stalledS += t - this.stalledSince;
      else this.stalls--;               // over at the instant it began: no stall
      this.stalledSince = null;
    }
  }

  stalledTotal(t) {
    return this.stalledS + (this.stalledSince === null ? 0 : Math.max(0, t - this.stalledSince));
  }
}

class Process {
  constructor(p) {
    this.process = p;
    this.state = "stopped";
    this.line = null;
    this.blockedOn = null;
    this.program = null;
    this.buffer = null;                 // {axis, mtype}: the move in its process buffer
    this.blocked = new Intervals();
  }
}

export class ControllerModel {
  constructor(id, kind) {
    this.id = id;
    this.kind = kind;
    this.reset();
  }

  /** Forget everything (a new log epoch or a `reset` event: a power cycle). */
  reset() {
    this.lastSeq = 0;
    this.received = 0;
    this.gaps = [];                     // [{from, to}]: events the stream could not deliver
    this.duplicates = 0;
    this.t = 0;
    this.tFirst = null;                 // t of the first event applied
    this.coords = new Map();
    this.axes = new Map();
    this.processes = new Map();
    this.syncM = new Marks();           // [t, "M1=1", cs]: synchronous M writes
    this.unplaced = [];                 // sync writes whose CS is not known yet
    this.mvars = new Map();             // name -> {value, sync, t}
    this.alerts = [];                   // rti_overrun, watchdog, ...
    this.prints = [];                   // Trio PRINT output [{t, process, text}]
    this.replies = [];                  // terminal_reply events not yet matched
    this.locked = false;
    this.counts = {};
  }

  cs(n) {
    let c = this.coords.get(n);
    if (!c) this.coords.set(n, (c = new CoordSystem(n)));
    return c;
  }

  axis(n) {
    let a = this.axes.get(n);
    if (!a) this.axes.set(n, (a = new Axis(n)));
    return a;
  }

  proc(n) {
    let p = this.processes.get(n);
    if (!p) this.processes.set(n, (p = new Process(n)));
    return p;
  }

  /** Apply a batch of stream messages; returns true when anything changed. */
  apply(messages) {
    let changed = false;
    for (const m of messages) {
      if (m.type === "gap") {
        this.gaps.push({ from: m.from, to: m.to });
        if (typeof m.to === "number") this.lastSeq = Math.max(this.lastSeq, m.to);
        changed = true;
        continue;
      }
      if (typeof m.seq !== "number") continue;      // stream metadata, not an event
      if (m.seq <= this.lastSeq) { this.duplicates++; continue; }
      if (m.seq !== this.lastSeq + 1) this.gaps.push({ from: this.lastSeq + 1, to: m.seq - 1 });
      this.lastSeq = m.seq;
      this.received++;
      this.counts[m.type] = (this.counts[m.type] || 0) + 1;
      if (m.t > this.t) this.t = m.t;
      if (this.tFirst === null) this.tFirst = m.t;
      this.event(m);
      changed = true;
    }
    if (changed) this.prune();
    return changed;
  }

  event(e) {
    const handler = HANDLERS[e.type];
    if (handler) handler(this, e);
    if (STALL_INPUTS.has(e.type)) {
      const stalled = stalledAxes(this);
      for (const [n, a] of this.axes) a.setStalled(e.t, stalled.has(n));
    }
  }

  prune() {
    const tmin = this.t - HISTORY_S;
    for (const c of this.coords.values()) {
      c.aheadSeries.prune(tmin);
      c.breqSeries.prune(tmin);
      c.starved.prune(tmin);
      c.writes.prune(tmin);
    }
    for (const a of this.axes.values()) {
      for (const s of Object.values(a.lanes)) s.prune(tmin);
      a.stalled.prune(tmin);
    }
    for (const p of this.processes.values()) p.blocked.prune(tmin);
    this.syncM.prune(tmin);
    if (this.alerts.length > 50) this.alerts.splice(0, this.alerts.length - 50);
    if (this.prints.length > 200) this.prints.splice(0, this.prints.length - 200);
  }
}

const STALL_INPUTS = new Set(["axis", "process", "process_buffer", "reset"]);

function setAxisLanes(a, t) {
  a.lanes.mtype.push(t, a.mtype);
  a.lanes.ntype.push(t, a.ntype);
}

const HANDLERS = {
  reset(m) {
    const { id, kind, lastSeq, received, gaps, duplicates, counts, t, tFirst } = m;
    m.reset();
    Object.assign(m, { id, kind, lastSeq, received, gaps, duplicates, counts, t, tFirst });
  },

  // -- PMAC ------------------------------------------------------------------------------
  line_loaded(m, e) {
    const c = m.cs(e.cs);
    if (e.n <= c.loaded) { c.lines.clear(); c.executing = null; }  // a new buffer numbers from 1
    c.loaded = e.n;
    c.lines.set(e.n, { n: e.n, text: e.text, words: e.words, state: "loaded" });
    while (c.lines.size > LAST_LINES) c.lines.delete(c.lines.keys().next().value);
    c.setAhead(e.t, e.lines_ahead);
    const last = c.writes.items[c.writes.items.length - 1];
    if (last && last[0] === e.t) last[1]++;          // the same write: one more line
    else c.writes.push(e.t, 1);
  },
  line_calculated(m, e) {
    const c = m.cs(e.cs);
    c.setAhead(e.t, Math.max(0, c.linesAhead - 1));
    const line = c.line(e.n);
    if (line && line.state === "loaded") line.state = "calculated";
  },
  move_start(m, e) {
    if (e.cs === undefined) return;   // Trio moves are followed through `axis` events
    const c = m.cs(e.cs);
    const line = c.line(e.n);
    if (line) line.state = "executing";
    c.executing = e.n;
    // A synchronous M write is made just before the move_start of the move it is tied to,
    // at the same instant (sim/pmac/lookahead.py): that names its CS, which `mvar` lacks.
    for (const mark of m.unplaced) if (mark[0] === e.t) mark[2] = e.cs;
    m.unplaced = [];
    for (const l of c.lines.values()) {   // lines before it that are not moves (M==, ...)
      if (l.n < e.n && (l.state === "loaded" || l.state === "calculated")) l.state = "done";
    }
  },
  move_end(m, e) {
    if (e.cs === undefined) return;
    const c = m.cs(e.cs);
    const line = c.line(e.n);
    if (line) line.state = "done";
    if (c.executing === e.n) c.executing = null;
  },
  breq(m, e) {
    const c = m.cs(e.cs);
    c.breq = !!e.level;
    c.breqSeries.push(e.t, e.level ? 1 : 0);
  },
  program(m, e) {
    if (e.cs !== undefined) {
      const c = m.cs(e.cs);
      c.program = { state: e.state, line: e.line ?? null, error: e.error ?? null };
      c.setStarved(e.t, e.state === "waiting");
      if (e.error) c.errors.push({ t: e.t, state: e.state, error: e.error });
      if (c.errors.length > 20) c.errors.shift();
      if (e.state !== "running" && e.state !== "waiting") c.executing = null;
    } else if (e.process !== undefined) {
      const p = m.proc(e.process);
      p.state = e.state;
    }
  },
  mvar(m, e) {
    m.mvars.set(e.name, { value: e.value, sync: !!e.sync, t: e.t });
    if (!e.sync) return;
    m.syncM.push(e.t, `${e.name}=${e.value}`);
    m.unplaced.push(m.syncM.items[m.syncM.items.length - 1]);
  },
  rti_overrun(m, e) {
    m.alerts.push({ t: e.t, text: `RTI overrun by ${(e.over_s * 100).toFixed(0)} %` });
  },
  watchdog(m, e) {
    m.alerts.push({ t: e.t, text: `watchdog tripped: ${e.reason}` });
  },

  // -- Trio ------------------------------------------------------------------------------
  axis(m, e) {
    const a = m.axis(e.axis);
    a.mtype = e.mtype;
    a.ntype = e.ntype;
    setAxisLanes(a, e.t);
  },
  process_buffer(m, e) {
    const p = m.proc(e.process);
    const axisNo = e.axis ?? p.buffer?.axis;
    if (e.mtype) p.buffer = { axis: axisNo, mtype: e.mtype };
    else p.buffer = null;
    if (axisNo === undefined || axisNo === null) return;
    const a = m.axis(axisNo);
    a.pb = e.mtype;
    a.pbProcess = e.mtype ? e.process : null;
    a.lanes.pb.push(e.t, e.mtype);
  },
  process(m, e) {
    const p = m.proc(e.process);
    p.state = e.state;
    p.line = e.line ?? null;
    p.blockedOn = e.state === "blocked" ? (e.blocked_on ?? null) : null;
    p.blocked.set(e.t, e.state === "blocked");
  },
  print(m, e) {
    m.prints.push({ t: e.t, process: e.process, text: e.text });
  },
  terminal(m, e) {
    m.locked = !!e.locked;
  },
  terminal_reply(m, e) {
    m.replies.push({ command: e.command, reply: e.reply, error: e.error });
  },
};

/** The axis a blocked move line loads (`AXIS(n)` in its text), or null (the BASE axis). */
export function axisOfLine(text) {
  const hit = /AXIS\s*\(\s*(\d+)\s*\)/i.exec(text || "");
  return hit ? Number(hit[1]) : null;
}

/**
 * What a blocked Trio process waits for: a move line waits until the move buffers of the
 * axis it loads can take it — the process buffer is one per process, shared by every axis
 * (TN20-16), so a process blocked behind another axis' move starves the axis it wants.
 */
export function waitsFor(model, p) {
  if (p.state !== "blocked") return null;
  const target = axisOfLine(p.blockedOn);
  const held = p.buffer;
  if (held && held.axis !== undefined && target !== null && held.axis !== target) {
    return { axis: target, behind: held.axis, mtype: held.mtype,
             text: `process buffer holds ${mtypeName(held.mtype)} for axis ${held.axis}` };
  }
  if (target !== null) return { axis: target, behind: null, text: `buffers of axis ${target}` };
  return { axis: null, behind: null, text: "move buffers of its BASE axis" };
}

/** Axes idle (MTYPE = NTYPE = 0) while a process waits to load a move for them. */
export function stalledAxes(model) {
  const out = new Map();
  for (const p of model.processes.values()) {
    const w = waitsFor(model, p);
    if (!w || w.axis === null) continue;
    const a = model.axes.get(w.axis);
    if (a && a.mtype === 0 && a.ntype === 0) out.set(w.axis, { process: p.process, ...w });
  }
  return out;
}
