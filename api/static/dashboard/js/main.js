// The dashboard: one tab per controller (created and deleted live), each with its own event
// stream and model kept current in the background; the selected one is drawn at most
// FPS times a second, however fast its events arrive. Only the public API is used.

import { ClockPanel } from "./clock.js";
import { fill, h } from "./dom.js";
import { ControllerModel } from "./model.js";
import { PmacView } from "./pmac_view.js";
import { RecordingPanel } from "./recording.js";
import { HISTORY_S, MAX_HELD, MAX_POINTS } from "./series.js";
import { EventStream } from "./stream.js";
import { Terminal } from "./terminal.js";
import { TrioView } from "./trio_view.js";

const FPS = 30;
const POLL_MS = 500;
const SPANS = [["fit", "all held"], ["0.1", "0.1 s"], ["0.5", "0.5 s"], ["2", "2 s"],
               ["10", "10 s"], ["60", "60 s"]];

const query = new URLSearchParams(location.search);
const token = query.get("token");
// Deep link: /dashboard?controller=ID or /dashboard#ID opens that controller's tab (as soon
// as it exists); the page keeps #ID in its address, so the address names the tab shown.
let wanted = query.get("controller") || decodeURIComponent(location.hash.slice(1)) || null;
const $ = (id) => document.getElementById(id);
const controllers = new Map();
let selected = null;
let span = "fit";
const stats = { frames: 0, renders: 0, renderMs: 0 };   // frames drawn and their cost

async function api(method, path, body) {
  const headers = { "content-type": "application/json" };
  if (token) headers.authorization = `Bearer ${token}`;
  const r = await fetch(path, { method, headers,
                                body: body === undefined ? undefined : JSON.stringify(body) });
  const data = r.status === 204 ? null : await r.json().catch(() => null);
  if (!r.ok) throw new Error(data ? `${data.code}: ${data.message}` : `HTTP ${r.status}`);
  return data;
}

// -- controllers ---------------------------------------------------------------------------

function add(info) {
  const model = new ControllerModel(info.id, info.kind);
  const ctl = { id: info.id, kind: info.kind, model, snap: { clock: info.clock } };
  ctl.stream = new EventStream(info.id, model, { onChange: schedule, onStatus: schedule, token });
  ctl.el = h("div", { class: "controller", "data-controller": info.id, "data-kind": info.kind });
  ctl.status = h("div", { class: "stream-status", "data-role": "stream" });
  ctl.clock = new ClockPanel(ctl, api, () => pollNow());
  ctl.terminal = new Terminal(ctl, api, () => { schedule(); pollSoon(); });
  const views = h("div", { class: "views" });
  const side = h("div", { class: "side" }, ctl.clock.el, ctl.terminal.el);
  ctl.el.append(h("div", { class: "strip" }, ctl.status), h("div", { class: "columns" }, views, side));
  ctl.view = info.kind === "pmac" ? new PmacView(views, ctl)
           : info.kind === "trio" ? new TrioView(views, ctl)
           : { render() {} };
  if (info.kind === "pmac" || info.kind === "trio") {   // gather / SCOPE, drawn on request
    ctl.recording = new RecordingPanel(ctl, api);
    views.append(ctl.recording.el);
  }
  controllers.set(info.id, ctl);
  return ctl;
}

function remove(id) {
  const ctl = controllers.get(id);
  if (!ctl) return;
  ctl.stream.close();
  ctl.el.remove();
  controllers.delete(id);
  if (selected === id) selected = controllers.keys().next().value ?? null;
}

function select(id, byUser = false) {
  if (byUser) wanted = null;           // the user's click wins over the link
  selected = id;
  if (id !== null && decodeURIComponent(location.hash.slice(1)) !== id) {
    history.replaceState(null, "", `${location.pathname}${location.search}#${encodeURIComponent(id)}`);
  }
  fill($("main"), controllers.get(id)?.el ?? h("p", { class: "hint" }, "No controller: create one above."));
  pollNow();
  schedule();
}

let tabsKey = "";
function tabs() {
  const key = JSON.stringify([selected, ...[...controllers.values()].map((c) => [c.id, c.stream.state])]);
  if (key === tabsKey) return;        // unchanged: keep the buttons (and a click in progress)
  tabsKey = key;
  fill($("tabs"), [...controllers.values()].map((c) =>
    h("span", { class: `tab${c.id === selected ? " on" : ""}`, "data-tab": c.id },
      h("button", { class: "pick", onclick: () => select(c.id, true) }, c.id, " ",
        h("small", {}, c.kind), c.stream.state === "live" ? null : h("small", { class: "warn" },
                                                                     ` ${c.stream.state}`)),
      h("button", { class: "del", title: `delete controller ${c.id}`, "data-delete": c.id,
                    onclick: () => del(c.id) }, "×"))));
}

async function del(id) {
  try {
    await api("DELETE", `/controllers/${encodeURIComponent(id)}`);
  } catch (e) {
    $("create-msg").textContent = e.message;
  }
  pollNow();
}

async function create(ev) {
  ev.preventDefault();
  const form = ev.target;
  const body = { kind: form.kind.value, clock: { mode: form.mode.value } };
  if (form.cid.value.trim()) body.id = form.cid.value.trim();
  try {
    const c = await api("POST", "/controllers", body);
    $("create-msg").textContent = "";
    form.cid.value = "";
    await pollNow();
    select(c.id, true);
  } catch (e) {
    $("create-msg").textContent = e.message;
  }
}

// -- polling: what no event carries (clock time, I16/I17, rotary words, DPOS, program names) -

async function pollList() {
  const list = await api("GET", "/controllers");
  const ids = new Set(list.map((c) => c.id));
  for (const id of [...controllers.keys()]) if (!ids.has(id)) remove(id);
  for (const info of list) {
    const old = controllers.get(info.id);
    const again = old && old.stream.state === "deleted";   // deleted and created again
    const wasSelected = selected === info.id;
    if (again) remove(info.id);
    const ctl = controllers.get(info.id) ?? add(info);
    if (again && wasSelected) select(info.id);
    ctl.snap.clock = info.clock;
    ctl.snap.clockWall = performance.now();
    if (info.coord) ctl.snap.coordStates = info.coord;
  }
  if (wanted !== null && controllers.has(wanted)) {
    if (selected !== wanted) select(wanted);
    wanted = null;
  } else if (wanted !== null) {
    missing(wanted);                  // a link to a controller that is not there (yet)
  } else if (selected === null || !controllers.has(selected)) {
    select(controllers.keys().next().value ?? null);
  }
}

// A deep link names a controller the server does not have: say so, and show no other
// controller in its place (the tab opens when it is created; a click on a tab wins).
let missingShown = null;
function missing(id) {
  if (missingShown === id && selected === null) return;
  missingShown = id;
  selected = null;
  fill($("main"), h("p", { class: "hint", "data-role": "missing" },
    `No controller "${id}" on this server (yet): its tab opens as soon as it is created. `,
    "Pick a tab above to see another one."));
  schedule();
}

async function pollDetail(ctl) {
  const base = `/controllers/${encodeURIComponent(ctl.id)}`;
  if (ctl.kind === "pmac") {
    const [i16, i17] = await Promise.all(["I16", "I17"].map((v) => api("GET", `${base}/variables/${v}`)));
    ctl.snap.i16 = i16.value;
    ctl.snap.i17 = i17.value;
    const numbers = new Set([...Object.keys(ctl.snap.coordStates || {}).map(Number),
                             ...ctl.model.coords.keys()]);
    const coords = {};
    await Promise.all([...numbers].map(async (n) => {
      coords[n] = await api("GET", `${base}/coord/${n}`);
    }));
    ctl.snap.coords = coords;
  } else if (ctl.kind === "trio") {
    const procs = await api("GET", `${base}/processes`);
    ctl.snap.programs = Object.fromEntries(procs.map((p) => [p.process, p.program]));
    const axes = {};
    await Promise.all(ctl.view.axisNumbers().map(async (n) => {
      axes[n] = await api("GET", `${base}/axes/${n}`).catch(() => undefined);
    }));
    ctl.snap.axes = axes;
  }
}

let polling = false;
async function pollNow() {
  if (polling) return;
  polling = true;
  try {
    await pollList();
    const ctl = controllers.get(selected);
    if (ctl) await pollDetail(ctl);
    $("service").textContent = "";
  } catch (e) {
    $("service").textContent = `service: ${e.message}`;
  } finally {
    polling = false;
  }
  schedule();
}

let soon = null;
function pollSoon() {
  if (soon === null) soon = setTimeout(() => { soon = null; pollNow(); }, 50);
}

// -- drawing, at most FPS frames a second ----------------------------------------------------

let pending = false;
let lastFrame = 0;

function schedule() {
  if (pending) return;
  pending = true;
  requestAnimationFrame(frame);
}

function frame(now) {
  if (now - lastFrame < 1000 / FPS - 1) {
    requestAnimationFrame(frame);
    return;
  }
  pending = false;
  lastFrame = now;
  stats.frames++;
  const start = performance.now();
  render();
  stats.renderMs += performance.now() - start;
}

function window_(ctl) {
  const c = ctl.snap.clock;
  let tClock = c ? c.t : 0;
  if (c && c.mode === "realtime" && !c.paused && ctl.snap.clockWall !== undefined) {
    tClock += ((performance.now() - ctl.snap.clockWall) / 1000) * c.factor;
  }
  const now = Math.max(ctl.model.t, tClock);
  const t1 = Math.max(now, 1e-3);
  const first = ctl.model.tFirst ?? 0;
  const t0 = span === "fit" ? Math.max(Math.min(first, t1 - 1e-3), t1 - HISTORY_S)
                            : t1 - Number(span);
  return { t0, t1, now };
}

function render() {
  tabs();
  const ctl = controllers.get(selected);
  if (!ctl) return;
  const m = ctl.model;
  const s = ctl.stream;
  ctl.status.dataset.lastSeq = m.lastSeq;
  ctl.status.dataset.received = m.received;
  ctl.status.dataset.gaps = m.gaps.length;
  ctl.status.dataset.duplicates = m.duplicates;
  ctl.status.dataset.reconnects = s.reconnects;
  ctl.status.dataset.state = s.state;
  ctl.status.dataset.epoch = s.epoch ?? "";
  ctl.status.dataset.resets = s.resets;
  ctl.status.dataset.modelT = m.t;     // the last event's time (the clock card shows "now")
  ctl.status.textContent =
    `${ctl.id} (${ctl.kind}) · stream ${s.state} · seq ${m.lastSeq}` +
    (s.epoch !== null ? ` · epoch ${s.epoch}` : "") + (s.resets ? ` · ${s.resets} resets` : "") +
    (s.error ? ` · ${s.error}` : "") +
    ` · ${m.received} events · ${m.gaps.length ? `${m.gaps.length} gaps` : "no gaps"}` +
    ` · ${s.reconnects} reconnects`;
  const win = window_(ctl);
  ctl.clock.render(win.now);
  ctl.view.render(win);
  ctl.terminal.render();
  stats.renders++;
  const c = ctl.snap.clock;
  if (c && c.mode === "realtime" && !c.paused) schedule();   // keep the time axis moving
}

// -- start ---------------------------------------------------------------------------------

function start() {
  fill($("span"), SPANS.map(([v, label]) => h("option", { value: v, selected: v === span }, label)));
  $("span").addEventListener("change", (ev) => { span = ev.target.value; schedule(); });
  $("create").addEventListener("submit", create);
  window.addEventListener("resize", schedule);
  window.addEventListener("hashchange", () => {
    const id = decodeURIComponent(location.hash.slice(1));
    if (id && id !== selected) {
      wanted = id;
      pollNow();
    }
  });
  pollNow();
  setInterval(pollNow, POLL_MS);
}

// For tests and benches: the controllers (model, stream and its cost), frame counts, bounds.
window.motionsimDashboard = {
  controllers, stats,
  bounds: { fps: FPS, historyS: HISTORY_S, maxPoints: MAX_POINTS, maxHeld: MAX_HELD },
};
start();
