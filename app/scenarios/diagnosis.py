"""Why did the program starve? Explanations read off the event log.

For each episode found by :mod:`app.scenarios.metrics`:

* PMAC ``buffer_empty`` — the rotary buffer ran dry while lines were still to come:

  - ``breq_missed``: BREQ rose while the host's interrupt was masked (the host was inside its
    service routine) and was still high when the routine returned; with an edge-triggered
    interrupt no new edge comes while the line stays high, so the host never wrote again in
    time (host event ``host_irq`` with ``missed``).
  - ``host_latency``: the host answered too late. Lines ahead fell below I16 (BREQ rose) at
    ``t16``; those lines covered ``covered_s`` of motion, and the host's next write came
    ``host_response_s`` after ``t16`` — longer (the manual's rule: the host must refill
    within the time the I16 lines take to execute).

* PMAC ``lookahead_break`` — motion stopped with lines in the buffer because move planning
  does not look past a DWELL or a RAPID move (TUM p341): ``lookahead_dwell`` /
  ``lookahead_rapid``.
* PMAC ``run_time_error`` — ``calculation_fell_behind``: the controller aborted the program
  because a move's successor was not calculated in time (TUM p339); move planning runs once
  per RTI (every I8+1 servo cycles), so moves shorter than the RTI period outrun it.
* Trio ``axis_blocked`` — ``process_blocked_on_other_axis``: the axis had room and moves still
  to come, but the process (or host) feeding it was blocked on another axis's move line
  (TN20-16).
"""

from __future__ import annotations

import re

from app.scenarios.metrics import CsTrace, Interval, Starvation, motion_gaps

_RAPID = re.compile(r"\bRAPID\b", re.I)
_MODE = re.compile(r"\b(LINEAR|CIRCLE[12]|PVT|SPLINE[12]?)\b", re.I)
_DWELL = re.compile(r"\bDWELL\b", re.I)


def _ms(s: float) -> str:
    return f"{s * 1e3:.3f} ms"


def diagnose_buffer_empty(s: Starvation, c: CsTrace, i16: int) -> Starvation:
    """Fill ``cause``, ``detail`` and facts of a ``buffer_empty`` starvation."""
    ts = s.start
    t16 = None
    prev = None
    for t, v in c.lines_ahead:
        if t > ts:
            break
        if prev is not None and prev >= i16 > v:
            t16 = t
        prev = v
    loads_before = [t for t in c.loaded.values() if t <= ts]
    t_last_write = max(loads_before, default=None)
    t_next_write = min((t for t in c.loaded.values() if t > ts), default=None)
    rising = [t for t, lvl in c.breq if lvl and t <= ts]
    tr = rising[-1] if rising else None
    if c.host_irqs:
        # interrupts serviced for an edge at or after the last rising edge before the start
        served = [
            t
            for t, missed, lat in c.host_irqs
            if not missed and tr is not None and t - lat >= tr - 1e-12
        ]
        missed = [
            (t, lat)
            for t, m, lat in c.host_irqs
            if m and t_last_write is not None and t_last_write - 1e-12 <= t <= ts
        ]
        if missed and not [t for t in served if t <= ts]:
            t_edge = missed[-1][0] - missed[-1][1]
            s.cause = "breq_missed"
            s.detail = (
                f"BREQ rose at {t_edge:.6f} s while the host's interrupt was masked and was "
                f"still high when its service routine returned; no new edge came, and the "
                f"buffer ran dry at {ts:.6f} s"
            )
            s.facts.update(breq_edge_s=t_edge)
            return s
        t_ref = t16 if t16 is not None else tr
        t_resp = served[0] if served else t_next_write
    else:
        t_ref = t16
        t_resp = t_next_write
    s.cause = "host_latency"
    if t_ref is not None:
        covered = ts - t_ref
        s.facts.update(covered_s=covered)
        if t_resp is not None:
            resp = t_resp - t_ref
            s.facts.update(host_response_s=resp)
            s.detail = (
                f"lines ahead fell below I16={i16} at {t_ref:.6f} s; they covered "
                f"{_ms(covered)} of motion but the host answered after {_ms(resp)}"
            )
        else:
            s.detail = (
                f"lines ahead fell below I16={i16} at {t_ref:.6f} s and covered "
                f"{_ms(covered)}; the host never answered"
            )
    else:
        gap = (t_next_write - t_last_write) if (t_next_write and t_last_write) else None
        s.detail = "the host never had I16 lines ahead" + (
            f"; {_ms(gap)} between its writes around the starvation" if gap else ""
        )
    return s


def lookahead_breaks(
    c: CsTrace, waiting: list[Interval], controller: str = ""
) -> list[Starvation]:
    """Motion gaps (no move executing) caused by a DWELL or a RAPID move, outside waiting."""
    out = []
    order = sorted(c.texts)
    rapid_at: dict[int, bool] = {}
    rapid = False
    for n in order:
        text = c.texts[n]
        if _RAPID.search(text):
            rapid = True
        elif _MODE.search(text):
            rapid = False
        rapid_at[n] = rapid
    for gap, n0, n1 in motion_gaps(c):
        if any(w.start < gap.end and gap.start < w.end for w in waiting):
            continue
        between = [n for n in order if n0 <= n < n1]
        if any(_DWELL.search(c.texts[n]) for n in between):
            cause, what = "lookahead_dwell", "DWELL"
        elif rapid_at.get(n0) or any(rapid_at.get(n) for n in between):
            cause, what = "lookahead_rapid", "RAPID move"
        else:
            continue
        out.append(
            Starvation(
                controller,
                "lookahead_break",
                gap.start,
                gap.end,
                cs=c.cs,
                cause=cause,
                detail=(
                    f"motion stopped {_ms(gap.length)} after line {n0}: planning does not "
                    f"look past a {what}, the next move was calculated only after it"
                ),
            )
        )
    return out


def diagnose_run_time_error(
    s: Starvation, c: CsTrace, rti_period_s: float | None = None
) -> Starvation:
    """Explain a ``run_time_error`` episode: which moves outran the RTI planning."""
    if s.cause != "run_time_error":
        return s  # an error this diagnosis does not know
    s.cause = "calculation_fell_behind"
    starts = sorted(t for t in c.move_start.values() if t <= s.start)[-6:]
    steps = [b - a for a, b in zip(starts, starts[1:], strict=False)]
    move_s = sum(steps) / len(steps) if steps else None
    s.facts.update(move_s=move_s, rti_period_s=rti_period_s)
    moves = f"moves of about {_ms(move_s)}" if move_s is not None else "moves"
    rti = f" ({_ms(rti_period_s)})" if rti_period_s is not None else ""
    s.detail = (
        f"calculation fell behind: {moves} are shorter than the RTI period{rti} in which move "
        f"planning runs, and at {s.start:.6f} s a move's successor was not calculated — "
        f"run-time error, program aborted (lower I8, or use longer moves)"
    )
    return s


def diagnose_axis_blocked(s: Starvation) -> Starvation:
    s.cause = "process_blocked_on_other_axis"
    on = s.facts.get("blocked_on")
    holder = s.facts.get("holder_axis")
    held = f"; its process buffer held a move for axis {holder}" if holder is not None else ""
    s.detail = (
        f"axis {s.axis} idle {_ms(s.length)} with moves still to come while {s.facts.get('who')}"
        f" waited at {on if on is not None else 'a move line'}{held}"
    )
    return s


__all__ = [
    "diagnose_axis_blocked",
    "diagnose_buffer_empty",
    "diagnose_run_time_error",
    "lookahead_breaks",
]
