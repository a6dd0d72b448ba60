// A controller's clock (GET|PATCH /controllers/{id}/clock, POST .../clock/advance): time,
// mode (virtual, realtime, host-paced), factor, paused, a realtime clock's lag, and the
// controls that can act on it. `advance` only moves a clock
// that is not realtime (the service answers 409 otherwise); `factor` only scales a realtime
// clock, so each is disabled where it cannot act.

import { fmt, h } from "./dom.js";

export class ClockPanel {
  constructor(ctl, api, refresh) {
    this.ctl = ctl;
    const path = `/controllers/${encodeURIComponent(ctl.id)}/clock`;
    const act = (fn) => async () => {
      try {
        this.msg.textContent = "";
        await fn();
      } catch (e) {
        this.msg.textContent = e.message;
      }
      refresh();
    };
    this.time = h("b", { "data-role": "clock-t" });
    this.mode = h("span", { "data-role": "clock-mode" });
    this.paused = h("span", { "data-role": "clock-paused" });
    this.pause = h("button", { "data-role": "pause", onclick: act(() =>
      api("PATCH", path, { paused: !this.ctl.snap.clock.paused })) }, "pause");
    this.seconds = h("input", { size: 6, value: "0.1", "aria-label": "seconds to advance" });
    this.advance = h("button", { "data-role": "advance", onclick: act(() =>
      api("POST", `${path}/advance`, { seconds: Number(this.seconds.value) })) }, "advance");
    this.factor = h("input", { size: 5, value: "1", "aria-label": "factor" });
    this.setFactor = h("button", { "data-role": "set-factor", onclick: act(() =>
      api("PATCH", path, { factor: Number(this.factor.value) })) }, "set factor");
    this.switchMode = h("button", { "data-role": "switch-mode", onclick: act(() =>
      api("PATCH", path, { mode: this.ctl.snap.clock.mode === "realtime" ? "virtual"
                                                                       : "realtime" })) });
    this.msg = h("span", { class: "error" });
    this.el = h("section", { class: "card clock" },
      h("h3", {}, "Clock"),
      h("div", { class: "clock-line" }, "simulated time ", this.time, " s · ", this.mode, " · ",
        this.paused),
      h("div", { class: "controls" }, this.pause, " ", this.seconds, " s ", this.advance, " ",
        this.factor, " × ", this.setFactor, " ", this.switchMode),
      this.msg);
  }

  /** `now`: the simulated time the page shows everywhere (the charts' right edge): the
   *  clock's last polled time, run on in wall time × factor for a running realtime clock,
   *  and never behind the last event received. */
  render(now) {
    const c = this.ctl.snap.clock;
    if (!c) return;
    this.time.textContent = fmt(now ?? c.t, 4);
    const lag = c.lag_s !== undefined && c.lag_s !== null ? `, lag ${fmt(c.lag_s, 3)} s` : "";
    this.mode.textContent = `${c.mode}, factor ${fmt(c.factor, 2)}${lag}${c.behind ? " (behind)" : ""}`;
    this.paused.textContent = c.paused ? "paused" : "running";
    this.pause.textContent = c.paused ? "resume" : "pause";
    const realtime = c.mode === "realtime";
    this.advance.disabled = realtime;
    this.advance.title = realtime ? "a realtime clock cannot be advanced" : "";
    this.setFactor.disabled = !realtime;
    this.setFactor.title = realtime ? "" : "factor scales a realtime clock only";
    this.switchMode.textContent = realtime ? "switch to virtual" : "switch to realtime";
  }
}
