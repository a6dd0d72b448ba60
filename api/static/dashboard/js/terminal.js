// The controller's own command line (POST /controllers/{id}/terminal): a transcript with the
// echoed command, its reply or error, history on up / down, and `pending` replies filled in
// when their `terminal_reply` event arrives (a PMAC whose background cycle is starved; a Trio
// move that cannot be buffered yet and locks the terminal). Trio PRINT output of programs
// appears in the same transcript.

import { fill, h } from "./dom.js";

const MAX_ENTRIES = 300;
const MAX_HISTORY = 100;

export class Terminal {
  constructor(ctl, api, onChange) {
    this.ctl = ctl;
    this.api = api;
    this.onChange = onChange;
    this.entries = [];                  // {cmd, reply, error, pending, other?, print?}
    this.history = [];
    this.cursor = 0;
    this.repliesSeen = 0;
    this.printsSeen = 0;
    this.dirty = true;                 // the transcript needs redrawing
    this.log = h("div", { class: "transcript", "data-role": "transcript" });
    this.input = h("input", { class: "cmd", "data-role": "command", spellcheck: "false",
                              autocomplete: "off",
                              placeholder: ctl.kind === "trio" ? "PRINT MTYPE AXIS(0)"
                                                               : "&1 B0 R   ·   PR   ·   I16" });
    this.input.addEventListener("keydown", (ev) => this.key(ev));
    this.status = h("span", { class: "muted", "data-role": "terminal-status" });
    this.el = h("section", { class: "card terminal" },
      h("h3", {}, "Terminal ", this.status), this.log,
      h("form", { class: "cmd-row", onsubmit: (ev) => { ev.preventDefault(); this.send(); } },
        h("span", { class: "prompt" }, ">"), this.input, h("button", { type: "submit" }, "send")));
  }

  key(ev) {
    if (ev.key !== "ArrowUp" && ev.key !== "ArrowDown") return;
    ev.preventDefault();
    if (!this.history.length) return;
    this.cursor += ev.key === "ArrowUp" ? -1 : 1;
    this.cursor = Math.max(0, Math.min(this.history.length, this.cursor));
    this.input.value = this.history[this.cursor] ?? "";
  }

  async send() {
    const cmd = this.input.value;
    if (!cmd.trim()) return;
    this.input.value = "";
    if (this.history[this.history.length - 1] !== cmd) this.history.push(cmd);
    if (this.history.length > MAX_HISTORY) this.history.shift();
    this.cursor = this.history.length;
    const entry = { cmd, reply: null, error: null, pending: true };
    this.push(entry);
    try {
      const r = await this.api("POST", `/controllers/${encodeURIComponent(this.ctl.id)}/terminal`,
                               { command: cmd });
      entry.pending = !!r.pending;
      if (!r.pending) Object.assign(entry, { reply: r.reply, error: r.error });
    } catch (e) {
      Object.assign(entry, { pending: false, error: e.message });
    }
    this.dirty = true;
    this.onChange();
  }

  push(entry) {
    this.entries.push(entry);
    if (this.entries.length > MAX_ENTRIES) this.entries.shift();
    this.dirty = true;
    this.onChange();
  }

  /** Take new `terminal_reply` and `print` events from the model. */
  absorb() {
    const { model } = this.ctl;
    if (this.repliesSeen > model.replies.length || this.printsSeen > model.prints.length) {
      this.repliesSeen = this.printsSeen = 0;   // the model was reset
    }
    for (const r of model.replies.slice(this.repliesSeen)) {
      const waiting = this.entries.find((e) => e.pending && e.cmd.trim() === r.command.trim());
      if (waiting) {
        Object.assign(waiting, { pending: false, reply: r.reply, error: r.error });
        this.dirty = true;
      } else this.push({ cmd: r.command, reply: r.reply, error: r.error, pending: false, other: true });
    }
    this.repliesSeen = model.replies.length;
    for (const p of model.prints.slice(this.printsSeen)) {
      this.push({ print: true, cmd: "", reply: `[process ${p.process}] ${p.text}` });
    }
    this.printsSeen = model.prints.length;
  }

  render() {
    this.absorb();
    const { model } = this.ctl;
    this.status.textContent = model.locked ? "· locked (a move waits to be buffered)" : "";
    if (!this.dirty) return;
    this.dirty = false;
    const atBottom = this.log.scrollTop + this.log.clientHeight >= this.log.scrollHeight - 4;
    fill(this.log, this.entries.map((e) => {
      if (e.print) return h("div", { class: "print" }, e.reply);
      const parts = [h("div", { class: "echo" }, e.other ? "(another port) " : "> ", e.cmd)];
      if (e.pending) parts.push(h("div", { class: "pending" }, "… pending"));
      if (e.reply) parts.push(h("div", { class: "reply" }, e.reply.replaceAll("\r", "\n")));
      if (e.error) parts.push(h("div", { class: "error" }, e.error));
      return h("div", { class: "entry", "data-command": e.cmd }, parts);
    }));
    if (atBottom) this.log.scrollTop = this.log.scrollHeight;
  }
}
