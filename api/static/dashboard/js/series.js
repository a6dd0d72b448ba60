// Bounded time series: what the charts draw. The model's *state* (lines ahead, BREQ, ...)
// is never bounded; only the history kept for drawing is (a time window and a point cap).

// The page's `?history=S&points=N` lower (or raise) them, e.g. for a small machine.
const query = new URLSearchParams(globalThis.location?.search ?? "");

function positive(text, fallback) {
  const x = Number(text);
  return text !== null && Number.isFinite(x) && x > 0 ? x : fallback;
}

export const HISTORY_S = positive(query.get("history"), 120);  // simulated s kept per series
export const MAX_POINTS = Math.ceil(positive(query.get("points"), 20000));  // points kept
// A series is trimmed back to MAX_POINTS when it reaches MAX_HELD (one splice per
// MAX_POINTS / 4 pushes, not one per push): MAX_HELD is the most it ever holds.
export const MAX_HELD = MAX_POINTS + Math.ceil(MAX_POINTS / 4);

/** A piecewise-constant signal: value v[i] from t[i] until t[i+1]. */
export class Steps {
  constructor(initial = 0) {
    this.t = [];
    this.v = [];
    this.initial = initial;   // the value before the first point still held
  }

  push(t, v) {
    this.t.push(t);
    this.v.push(v);
    if (this.t.length >= MAX_HELD) this.dropBefore(this.t.length - MAX_POINTS);
  }

  /** Drop points before index k, remembering the value they left behind. */
  dropBefore(k) {
    if (k <= 0) return;
    this.initial = this.v[k - 1];
    this.t.splice(0, k);
    this.v.splice(0, k);
  }

  prune(tmin) {
    let k = 0;
    while (k < this.t.length && this.t[k] < tmin) k++;
    this.dropBefore(k);
  }

  get last() {
    return this.v.length ? this.v[this.v.length - 1] : this.initial;
  }

  /** First index with t >= t0 (binary search). */
  indexAt(t0) {
    let lo = 0, hi = this.t.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (this.t[mid] < t0) lo = mid + 1; else hi = mid;
    }
    return lo;
  }

  valueBefore(t0) {
    const i = this.indexAt(t0);
    return i === 0 ? this.initial : this.v[i - 1];
  }
}

/** Intervals [t0, t1) of a condition (t1 = null while it holds), e.g. starvation. */
export class Intervals {
  constructor() {
    this.items = [];
  }

  set(t, on) {
    const open = this.items.length && this.items[this.items.length - 1][1] === null;
    if (on && !open) this.items.push([t, null]);
    else if (!on && open) this.items[this.items.length - 1][1] = t;
    if (this.items.length >= MAX_HELD) this.items.splice(0, this.items.length - MAX_POINTS);
  }

  prune(tmin) {
    let k = 0;
    while (k < this.items.length && this.items[k][1] !== null && this.items[k][1] < tmin) k++;
    if (k) this.items.splice(0, k);
  }
}

/** Instants with a label, e.g. synchronous M-variable writes. */
export class Marks {
  constructor() {
    this.items = [];
  }

  push(t, label) {
    this.items.push([t, label]);
    if (this.items.length >= MAX_HELD) this.items.splice(0, this.items.length - MAX_POINTS);
  }

  prune(tmin) {
    let k = 0;
    while (k < this.items.length && this.items[k][0] < tmin) k++;
    if (k) this.items.splice(0, k);
  }
}
