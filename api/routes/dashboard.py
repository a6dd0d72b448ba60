"""``GET /dashboard``: a single self-contained page to watch and poke the controllers.

It uses only the public API (``/controllers``, ``/clock``, ``/terminal``, the events
WebSocket, PMAC ``/coord/{cs}``), no external scripts or styles, so it works offline and in
a container. Not part of ``/openapi.json``.
"""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.responses import HTMLResponse

router = APIRouter(tags=["service"])

_PAGE = """<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>motionsim</title>
<style>
 body{font:14px system-ui,sans-serif;margin:0;display:grid;grid-template-columns:14rem 1fr;
      height:100vh}
 nav{background:#1d2733;color:#dde;padding:1rem;overflow:auto}
 nav button{display:block;width:100%;margin:.2rem 0;text-align:left;background:#2c3a4a;
      color:#eef;border:0;padding:.4rem;border-radius:4px;cursor:pointer}
 nav button.on{background:#4a6a8a}
 main{padding:1rem;overflow:auto;display:grid;grid-template-rows:auto auto 1fr;gap:.8rem}
 section{border:1px solid #ccd;border-radius:6px;padding:.6rem}
 h2{font-size:1rem;margin:.1rem 0 .5rem}
 #events{font:12px ui-monospace,monospace;height:45vh;overflow:auto;white-space:pre}
 input{font:inherit;padding:.2rem}.k{color:#667}.err{color:#b00}
</style></head><body>
<nav><h1 style="font-size:1.1rem">motionsim</h1><div id="list"></div>
 <p><a style="color:#9cf" href="/docs">API docs</a></p></nav>
<main>
 <section><h2 id="title">no controller</h2><div id="clock"></div>
  <div><button onclick="pause()">pause / resume</button>
   <input id="adv" size="6" value="0.1"> s <button onclick="advance()">advance</button>
   <span id="msg" class="err"></span></div><div id="coord"></div></section>
 <section><h2>terminal</h2><input id="cmd" size="50" placeholder="&amp;1 B0 R  /  PRINT MTYPE">
  <button onclick="send()">send</button><pre id="out"></pre></section>
 <section><h2>events <span class="k" id="count"></span></h2><div id="events"></div></section>
</main>
<script>
let cur = null, ws = null, n = 0, info = {};
const $ = id => document.getElementById(id);
async function api(method, path, body) {
  const r = await fetch(path, {method, headers: {"content-type": "application/json"},
                               body: body === undefined ? undefined : JSON.stringify(body)});
  const data = r.status === 204 ? null : await r.json();
  if (!r.ok) throw new Error(data.code + ": " + data.message);
  return data;
}
async function refresh() {
  const list = await api("GET", "/controllers");
  $("list").innerHTML = "";
  for (const c of list) {
    const b = document.createElement("button");
    b.textContent = c.id + " (" + c.kind + ")"; b.className = c.id === cur ? "on" : "";
    b.onclick = () => select(c.id); $("list").appendChild(b); info[c.id] = c;
  }
  if (!cur && list.length) select(list[0].id);
  if (cur && info[cur]) {
    const k = info[cur].clock;
    $("clock").textContent = `t = ${k.t.toFixed(4)} s  ·  ${k.mode}  ·  factor ${k.factor}` +
      (k.paused ? "  ·  paused" : "");
    if (info[cur].kind === "pmac") {
      try { const c = await api("GET", `/controllers/${cur}/coord/1`); const r = c.rotary;
        $("coord").textContent = `&1 program ${c.program.state}` + (r ? `  ·  rotary ` +
          `${r.used_words}/${r.size_words} words, lines ahead ${r.lines_ahead}, BREQ ` +
          (r.breq ? "high" : "low") : "  ·  no rotary buffer"); } catch (e) {}
    } else $("coord").textContent = "";
  }
}
function select(id) {
  cur = id; n = 0; $("title").textContent = id; $("events").textContent = "";
  if (ws) ws.close();
  ws = new WebSocket(location.origin.replace("http", "ws") + `/controllers/${id}/events` +
                     "?batch=true");
  ws.onmessage = m => {
    const box = $("events"), lines = [];
    for (const e of JSON.parse(m.data)) {
      if (e.type === "epoch") continue;
      n++; const {seq, t, type, controller, ...f} = e;
      lines.push(e.type === "gap" ? `-- gap ${e.from}..${e.to}` :
                 `${String(seq).padStart(7)} ${t.toFixed(6)} ${type} ${JSON.stringify(f)}`);
    }
    box.textContent = (box.textContent + lines.join("\\n") + "\\n").split("\\n").slice(-400)
      .join("\\n");
    box.scrollTop = box.scrollHeight; $("count").textContent = `(${n})`;
  };
  refresh();
}
async function act(f) { $("msg").textContent = ""; try { await f(); } catch (e) {
  $("msg").textContent = e.message; } refresh(); }
function pause() { act(() => api("PATCH", `/controllers/${cur}/clock`,
                                 {paused: !info[cur].clock.paused})); }
function advance() { act(() => api("POST", `/controllers/${cur}/clock/advance`,
                                   {seconds: parseFloat($("adv").value)})); }
function send() { act(async () => { const r = await api("POST", `/controllers/${cur}/terminal`,
                                                        {command: $("cmd").value});
  $("out").textContent = r.pending ? "(pending)" : (r.error ? r.error : r.reply); }); }
$("cmd").addEventListener("keydown", e => { if (e.key === "Enter") send(); });
refresh(); setInterval(refresh, 1000);
</script></body></html>
"""


@router.get("/dashboard", response_class=HTMLResponse, include_in_schema=False)
async def dashboard() -> HTMLResponse:
    """The dashboard page."""
    return HTMLResponse(_PAGE)
