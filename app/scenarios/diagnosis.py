"""Why did the program starve? Explanations read off the event log.

For each episode found by :mod:`motionsim.app.scenarios.metrics`:

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
  - ``host_commands_unanswered``: the host polls ``PR`` and its polls went unanswered
    (``host_timeout``) between its last write and the buffer running dry: the card answers
    host commands in the background, which PLC 0 and the RTI left no processor time.

* PMAC ``watchdog`` — the card tripped (TUM p215): ``plc0_too_long`` when PLC 0's
  scan alone needs more processor time than one RTI period leaves after the servo task (the
  RTI overruns every time and the background never completes a cycle), ``rti_tasks_too_long``
  when PLC 0 plus move planning do, else ``background_starved``. The detail names the scan
  (statements, µs), the RTI period, I40 and when the last background cycle ended.
* Trio ``axis_blocked`` — ``process_blocked_on_other_axis``: the axis had room and moves still
  to come, but the process (or host) feeding it was blocked on another axis's move line
  (TN20-16).
"""

from __future__ import annotations

import re

from .metrics import CsTrace, Interval, Starvation, motion_gaps

_RAPID = re.compile(r"\bRAPID\b", re.I)
_MODE = re.compile(r"\b(LINEAR|CIRCLE[12]|PVT|SPLINE[12]?)\b", re.I)
_DWELL = re.compile(r"\bDWELL\b", re.I)


def _ms(s: float) -> str:
    return f"{s * 1e3:.3f} ms"


def _us(s: float) -> str:
    return f"{s * 1e6:.0f} µs"


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


def diagnose_unanswered(s: Starvation, c: CsTrace) -> Starvation:
    """A ``buffer_empty`` starvation of a PR-polling host whose polls timed out since its
    last write: the card did not answer (its background was starved), not a slow host."""
    if s.kind != "buffer_empty":
        return s
    last_write = max((t for t in c.loaded.values() if t <= s.start), default=0.0)
    lost = [(t, w) for t, w in c.host_timeouts if last_write < t <= s.end]
    if not lost:
        return s
    t_first = lost[0][0] - lost[0][1]
    before = sum(1 for t, _ in lost if t <= s.start)
    s.cause = "host_commands_unanswered"
    for stale in ("covered_s", "host_response_s"):
        s.facts.pop(stale, None)
    s.facts.update(first_unanswered_s=t_first, host_timeouts=len(lost))
    s.detail = (
        f"the host's PR polls went unanswered from {t_first:.6f} s ({before} timed out before "
        f"the buffer ran dry at {s.start:.6f} s, {len(lost)} in all): the card answers host "
        f"commands in the background, which got no processor time, so the host never "
        f"learned it had to refill"
    )
    return s


def diagnose_watchdog(
    controller: str,
    t_trip: float,
    t_end: float,
    *,
    limit_cycles: int,
    i40: int,
    servo_period_s: float,
    rti_period_s: float,
    servo_share: float,
    plc0_statements: int | None,
    plc0_scan_s: float | None,
    planning_s: float = 0.0,
    rti_overruns: int = 0,
    first_overrun_s: float | None = None,
    plc0_enabled_s: float | None = None,
) -> Starvation:
    """Explain a watchdog trip: which foreground work left the background no time.

    Args:
        limit_cycles: servo cycles the watchdog allows (I40, 4096 when I40 = 0).
        servo_share: share of the processor the servo task takes.
        plc0_statements, plc0_scan_s: PLC 0's last scan before the trip and its cost.
        planning_s: move planning per RTI before the trip (processor seconds).
    """
    window = limit_cycles * servo_period_s
    last_bg = t_trip - window  # the model: trip = last background cycle end + I40 cycles
    room = rti_period_s * max(0.0, 1.0 - servo_share)
    scan = plc0_scan_s or 0.0
    i40_text = f"I40 = {i40}" + (f" → {limit_cycles}" if i40 <= 0 else "")
    within = (
        f"the background could not complete a cycle within {i40_text} servo cycles "
        f"({window:.3f} s): its last cycle ended at {last_bg:.6f} s and the watchdog tripped "
        f"at {t_trip:.6f} s"
    )
    servo = f" ({_us(room)} left after the servo task)" if servo_share > 0 else ""
    if plc0_statements and scan > room:
        cause = "plc0_too_long"
        detail = (
            f"PLC 0 scan of {plc0_statements} statements ≈ {_us(scan)} exceeds the RTI period "
            f"{_us(rti_period_s)}{servo}: {within}"
        )
    elif plc0_statements and scan + planning_s > room:
        cause = "rti_tasks_too_long"
        detail = (
            f"PLC 0 scan of {plc0_statements} statements ≈ {_us(scan)} plus move planning "
            f"≈ {_us(planning_s)} per RTI exceed the RTI period {_us(rti_period_s)}{servo}: "
            f"{within}"
        )
    else:
        cause = "background_starved"
        detail = f"servo and RTI tasks left the background no processor time: {within}"
    if rti_overruns and first_overrun_s is not None:
        detail += f"; {rti_overruns} RTIs overran from {first_overrun_s:.6f} s"
    if plc0_enabled_s is not None:
        detail += f"; PLC 0 was enabled at {plc0_enabled_s:.6f} s"
    return Starvation(
        controller,
        "watchdog",
        t_trip,
        max(t_trip, t_end),
        cause=cause,
        detail=detail,
        facts={
            "plc0_statements": plc0_statements,
            "plc0_scan_s": plc0_scan_s,
            "rti_period_s": rti_period_s,
            "planning_s": planning_s,
            "limit_cycles": limit_cycles,
            "last_background_s": last_bg,
            "rti_overruns": rti_overruns,
        },
    )


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
    "diagnose_unanswered",
    "diagnose_watchdog",
    "lookahead_breaks",
]
