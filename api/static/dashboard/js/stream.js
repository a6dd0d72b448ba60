// The events WebSocket of one controller (`batch=true`), resumed by `seq` and `epoch`.
//
// The first message of a stream is `{"type": "epoch", "epoch", "first_seq", "last_seq",
// "reset"}`. After any close that is not final (4404 unknown controller, 4410 deleted) it
// reconnects with `since=` the last seq applied and that `epoch`, so nothing still held is
// missed or applied twice. A `reset` (or another epoch) means a new log — the controller was
// re-created or the service restarted — and the model starts again from its first event.

const FINAL_CLOSE = new Set([4404, 4410]);

export class EventStream {
  constructor(id, model, { onChange, onStatus, token = null }) {
    this.id = id;
    this.model = model;
    this.onChange = onChange;
    this.onStatus = onStatus;
    this.token = token;
    this.epoch = null;
    this.state = "connecting";
    this.reconnects = 0;
    this.closes = [];                   // [code]: every close seen, for the status line
    this.resets = 0;                    // resumes the service answered with a new log
    this.error = null;
    this.ws = null;
    this.stopped = false;
    this.backoff = 100;
    // what handling the stream costs the page: messages, events and the milliseconds spent
    // parsing and applying them (read by tests/browser and bench/bench_dashboard.py)
    this.cost = { messages: 0, events: 0, ms: 0 };
    this.open();
  }

  url() {
    const base = location.origin.replace(/^http/, "ws");
    const q = new URLSearchParams({ batch: "true", since: String(this.model.lastSeq) });
    if (this.epoch !== null) q.set("epoch", String(this.epoch));
    if (this.token) q.set("token", this.token);
    return `${base}/controllers/${encodeURIComponent(this.id)}/events?${q}`;
  }

  open() {
    const ws = new WebSocket(this.url());
    this.ws = ws;
    ws.onopen = () => {
      this.backoff = 100;
      this.status("live");
    };
    ws.onmessage = (msg) => this.receive(msg.data);
    ws.onclose = (ev) => {
      if (this.ws !== ws) return;
      this.closes.push(ev.code);
      if (this.stopped) return;
      if (FINAL_CLOSE.has(ev.code)) {
        this.status(ev.code === 4410 ? "deleted" : "unknown controller");
        return;
      }
      this.status("reconnecting");
      this.reconnects++;
      setTimeout(() => !this.stopped && this.open(), this.backoff);
      this.backoff = Math.min(this.backoff * 2, 2000);
    };
  }

  receive(data) {
    const start = performance.now();
    const n = this.handle(data);
    this.cost.messages++;
    this.cost.events += n;
    this.cost.ms += performance.now() - start;
  }

  /** Parse one WebSocket message and apply what it holds; returns how many events. */
  handle(data) {
    let messages = JSON.parse(data);
    if (!Array.isArray(messages)) messages = [messages];
    let events = [];
    let count = 0;
    for (const m of messages) {
      if (m.type === "epoch") {            // the first message: the log's incarnation
        if (events.length) this.model.apply(events);
        events = [];
        if (m.reset || (this.epoch !== null && m.epoch !== this.epoch)) this.model.reset();
        this.epoch = m.epoch;
        this.resets += m.reset ? 1 : 0;
      } else if (m.type === "error") {     // a refused query, just before close 4422
        this.error = m.message;
      } else {
        events.push(m);
        count++;
      }
    }
    if (this.model.apply(events) || messages.length) this.onChange();
    return count;
  }

  status(s) {
    this.state = s;
    this.onStatus();
  }

  close() {
    this.stopped = true;
    if (this.ws) this.ws.close(1000, "dashboard closed");
  }
}
