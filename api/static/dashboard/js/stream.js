// The events WebSocket of one controller (`batch=true`), resumed by `seq` and `epoch`.
//
// After any close that is not final (4404 unknown controller, 4410 deleted) it reconnects
// with `since=` the last seq applied and the log's `epoch`, so nothing still held is missed
// or applied twice. A different epoch means a new log (the controller was re-created or the
// service restarted): the model starts again from seq 1.

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
    this.ws = null;
    this.stopped = false;
    this.backoff = 100;
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
    let messages = JSON.parse(data);
    if (!Array.isArray(messages)) messages = [messages];
    const events = [];
    for (const m of messages) {
      if (m && m.epoch !== undefined && m.epoch !== null) this.noteEpoch(m.epoch);
      if (m && m.type === "reset" && m.seq === undefined) {   // the log said: start again
        this.model.reset();
        continue;
      }
      events.push(m);
    }
    if (this.model.apply(events)) this.onChange();
  }

  noteEpoch(epoch) {
    if (this.epoch !== null && epoch !== this.epoch) this.model.reset();
    this.epoch = epoch;
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
