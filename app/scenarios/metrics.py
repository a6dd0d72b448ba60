"""Metrics of a run, computed from the event log alone.

Everything here reads :class:`motionsim.sim.events.Event` values (``type``, ``t``, fields as in
API.md's table, plus the hosts' ``host_*`` events), so it works on a log from any source: a scenario
run, a log fed by hand in a test, or a JSON Lines file from the service.

PMAC, per coordinate system with a rotary buffer:

* ``lines_ahead`` over time = lines loaded − lines calculated (what ``PR`` reports);
  ``min_lines_ahead`` while the program streams (first move start .. last line loaded).
* starvations: the program ``waiting`` (it ran out of rotary lines) while lines are still to
  come — a later ``line_loaded``, or fewer lines loaded than the host had to send. Count,
  total ``time_starved_s``, longest.
* run-time errors: the program aborted by the controller (calculation fell behind).
* ``breq_rising`` edges and their rate, host writes and interrupts, line latency
  (``line_loaded`` → ``move_start`` of the same line); a PR-polling host's reply latency
  (``host_pr``: command received → answered) and its unanswered polls (``host_timeout``);
  a terminal writer's write latency (``host_write.reply_s``: program line sent → answered).
* ``mvar_lead``: for each M-variable write, how long before the move that follows it in the
  program actually starts (0 for ``M1==1``, about a move early for ``M1=1``).

The card's processor (RTI overruns, background cycle, the watchdog) is in
:mod:`motionsim.app.scenarios.cpu_metrics`.

Trio, per axis: time with MTYPE / NTYPE / process buffer occupied, and the time an axis stood
idle between its moves while a process (or a feeding host) was blocked waiting on another axis.

:mod:`motionsim.app.scenarios.diagnosis` explains each starvation.
"""

from __future__ import annotations

import bisect
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from ...sim.events import Event

_MOVE_WORD = re.compile(r"(?<![A-Z])([XYZABCUVW])\s*-?[\d.(]", re.I)
_MASSIGN = re.compile(r"^\s*(M\d+)\s*(==|&=|\|=|\^=|=)", re.I)


def is_move_line(text: str) -> bool:
    """A rotary line that commands motion (an axis word) or a DWELL / DELAY."""
    up = text.upper()
    if _MASSIGN.match(up) or re.match(r"^\s*[PQI]\d+\s*=", up):
        return False
    return bool(_MOVE_WORD.search(up)) or "DWELL" in up or "DELAY" in up


@dataclass(slots=True)
class Interval:
    start: float
    end: float

    @property
    def length(self) -> float:
        return self.end - self.start


@dataclass(slots=True)
class Starvation:
    """One episode where motion could not go on although work remained.

    ``kind``: ``buffer_empty`` (PMAC program waiting for lines), ``lookahead_break`` (PMAC motion
    stopped at a DWELL / RAPID with lines in the buffer), ``run_time_error`` (PMAC program
    aborted by the controller, until the next ``R``), ``axis_blocked`` (Trio axis idle
    while its process waited on another axis). ``cause`` and ``detail`` come from the diagnosis.
    """

    controller: str
    kind: str
    start: float
    end: float
    cs: int | None = None
    axis: int | None = None
    cause: str = "unknown"
    detail: str = ""
    facts: dict[str, Any] = field(default_factory=dict)

    @property
    def length(self) -> float:
        return self.end - self.start

    def to_dict(self) -> dict[str, Any]:
        d = {
            "controller": self.controller,
            "kind": self.kind,
            "cs": self.cs,
            "axis": self.axis,
            "start_s": self.start,
            "end_s": self.end,
            "length_s": self.length,
            "cause": self.cause,
            "detail": self.detail,
        }
        d.update(self.facts)
        return {k: v for k, v in d.items() if v is not None}


# -- PMAC ------------------------------------------------------------------------------------


@dataclass(slots=True)
class CsTrace:
    """What happened to one coordinate system's rotary buffer, distilled from the log."""

    cs: int
    loaded: dict[int, float] = field(default_factory=dict)  # n -> t
    texts: dict[int, str] = field(default_factory=dict)
    calculated: dict[int, float] = field(default_factory=dict)
    move_start: dict[int, float] = field(default_factory=dict)
    move_end: dict[int, float] = field(default_factory=dict)
    lines_ahead: list[tuple[float, int]] = field(default_factory=list)
    breq: list[tuple[float, bool]] = field(default_factory=list)
    program: list[tuple[float, str]] = field(default_factory=list)
    host_writes: list[tuple[float, int]] = field(default_factory=list)
    host_irqs: list[tuple[float, bool, float]] = field(default_factory=list)  # t, missed, lat
    mvars: list[tuple[float, str, bool]] = field(default_factory=list)
    errors: list[tuple[float, str]] = field(default_factory=list)  # program aborted: t, error
    host_done: float | None = None
    host_sent: int | None = None
    host_prs: list[tuple[float, float]] = field(default_factory=list)  # t, reply_s
    host_timeouts: list[tuple[float, float]] = field(default_factory=list)  # t, waited_s
    write_replies: list[tuple[float, float]] = field(default_factory=list)  # t, reply_s


def pmac_traces(events: Iterable[Event]) -> dict[int, CsTrace]:
    """Per coordinate system, the rotary-related history of a PMAC log."""
    out: dict[int, CsTrace] = {}
    ahead: dict[int, int] = {}
    last_cs: int | None = None

    def tr(cs: int) -> CsTrace:
        if cs not in out:
            out[cs] = CsTrace(cs)
            ahead[cs] = 0
        return out[cs]

    for e in events:
        f = e.fields
        typ = e.type
        if typ == "line_loaded":
            c = tr(f["cs"])
            c.loaded[f["n"]] = e.t
            c.texts[f["n"]] = f.get("text", "")
            ahead[c.cs] += 1
            c.lines_ahead.append((e.t, ahead[c.cs]))
            last_cs = c.cs
        elif typ == "line_calculated":
            c = tr(f["cs"])
            c.calculated[f["n"]] = e.t
            ahead[c.cs] = max(0, ahead[c.cs] - 1)
            c.lines_ahead.append((e.t, ahead[c.cs]))
        elif typ == "move_start" and "cs" in f:
            tr(f["cs"]).move_start.setdefault(f["n"], e.t)
        elif typ == "move_end" and "cs" in f:
            tr(f["cs"]).move_end[f["n"]] = e.t
        elif typ == "breq":
            tr(f["cs"]).breq.append((e.t, bool(f["level"])))
        elif typ == "program" and "cs" in f:
            tr(f["cs"]).program.append((e.t, f["state"]))
            if f.get("error") and f["error"] != "watchdog":  # a trip is not a run-time error
                tr(f["cs"]).errors.append((e.t, str(f["error"])))
        elif typ == "host_write" and "cs" in f:
            c = tr(f["cs"])
            c.host_writes.append((e.t, f.get("lines", 1)))
            if "reply_s" in f:
                c.write_replies.append((e.t, float(f["reply_s"])))
        elif typ == "host_irq" and "cs" in f:
            tr(f["cs"]).host_irqs.append((e.t, bool(f.get("missed")), f.get("latency_s", 0.0)))
        elif typ == "host_pr" and "cs" in f:
            tr(f["cs"]).host_prs.append((e.t, float(f["reply_s"])))
        elif typ == "host_timeout" and "cs" in f:
            tr(f["cs"]).host_timeouts.append((e.t, float(f.get("waited_s", 0.0))))
        elif typ == "host_done" and "cs" in f:
            c = tr(f["cs"])
            c.host_done, c.host_sent = e.t, f.get("sent")
        elif typ == "mvar":
            cs = last_cs if last_cs is not None else (min(out) if out else 1)
            tr(cs).mvars.append((e.t, str(f["name"]).upper(), bool(f.get("sync"))))
    return out


def waiting_intervals(c: CsTrace, t_end: float) -> list[Interval]:
    """Intervals where the program state was ``waiting`` (ran out of rotary lines)."""
    out: list[Interval] = []
    start: float | None = None
    for t, state in c.program:
        if state == "waiting":
            if start is None:
                start = t
        elif start is not None:
            out.append(Interval(start, t))
            start = None
    if start is not None:
        out.append(Interval(start, t_end))
    return out


def starvations(
    c: CsTrace, t_end: float, controller: str = "", total_lines: int | None = None
) -> list[Starvation]:
    """Waiting intervals with lines still to come (a later load, or lines never sent)."""
    loads = sorted(c.loaded.values())
    n_loaded = len(c.loaded)
    out = []
    for iv in waiting_intervals(c, t_end):
        later_load = _any_after(loads, iv.start)
        unsent = total_lines is not None and n_loaded < total_lines
        if later_load or unsent:
            out.append(Starvation(controller, "buffer_empty", iv.start, iv.end, cs=c.cs))
    return out


def run_time_errors(c: CsTrace, t_end: float, controller: str = "") -> list[Starvation]:
    """Programs the controller aborted itself (``program`` event with an ``error``), each
    until the program runs again (the next ``R``) or the end of the run."""
    out = []
    for t, error in c.errors:
        again = [t1 for t1, state in c.program if t1 > t and state == "running"]
        end = again[0] if again else t_end
        out.append(Starvation(controller, "run_time_error", t, end, cs=c.cs, cause=error))
    return out


def _any_after(sorted_ts: Sequence[float], t: float) -> bool:
    return bisect.bisect_right(sorted_ts, t) < len(sorted_ts)


def motion_gaps(c: CsTrace) -> list[tuple[Interval, int, int]]:
    """Intervals with no move executing between two moves: (gap, n before, n after)."""
    spans = sorted(
        (t0, c.move_end.get(n, t0), n) for n, t0 in c.move_start.items()
    )
    out = []
    active_end = None
    prev_n = None
    for t0, t1, n in spans:
        if active_end is not None and t0 > active_end + 1e-12:
            out.append((Interval(active_end, t0), prev_n, n))
        if active_end is None or t1 >= active_end:
            active_end, prev_n = t1, n
    return out


def line_latency(c: CsTrace) -> list[float]:
    """Loaded → executing (``move_start``) for every line that started a move."""
    return [c.move_start[n] - c.loaded[n] for n in c.move_start if n in c.loaded]


def mvar_leads(c: CsTrace) -> list[dict[str, Any]]:
    """For each M-variable write: how long before the next move in the program it happened."""
    assigns: dict[str, list[int]] = {}
    for n in sorted(c.texts):
        m = _MASSIGN.match(c.texts[n].upper())
        if m:
            assigns.setdefault(m.group(1), []).append(n)
    used: dict[str, int] = {}
    out = []
    order = sorted(c.texts)
    for t, name, sync in c.mvars:
        k = used.get(name, 0)
        used[name] = k + 1
        lines = assigns.get(name, [])
        if k >= len(lines):
            continue
        n_m = lines[k]
        nxt = next((n for n in order if n > n_m and is_move_line(c.texts[n])), None)
        t_move = c.move_start.get(nxt) if nxt is not None else None
        out.append(
            {
                "name": name,
                "sync": sync,
                "t": t,
                "line": n_m,
                "next_move_line": nxt,
                "lead_s": None if t_move is None else t_move - t,
            }
        )
    return out


def _stats(xs: Sequence[float]) -> dict[str, float | None]:
    if not xs:
        return {"mean": None, "p50": None, "p99": None, "max": None}
    s = sorted(xs)
    return {
        "mean": sum(s) / len(s),
        "p50": s[len(s) // 2],
        "p99": s[min(len(s) - 1, int(len(s) * 0.99))],
        "max": s[-1],
    }


def pmac_cs_metrics(
    c: CsTrace,
    t_end: float,
    *,
    controller: str = "",
    total_lines: int | None = None,
    t_start: float = 0.0,
) -> dict[str, Any]:
    """The numbers for one coordinate system (starvation list under ``"starvations"``)."""
    starv = starvations(c, t_end, controller, total_lines)
    first_move = min(c.move_start.values(), default=None)
    last_load = max(c.loaded.values(), default=None)
    window = [
        v
        for t, v in c.lines_ahead
        if first_move is not None and last_load is not None and first_move < t < last_load
    ]
    rising = sum(1 for (_, lvl) in c.breq if lvl)
    span = max(t_end - t_start, 1e-12)
    lat = _stats(line_latency(c))
    pr = _stats([r for _, r in c.host_prs])
    wr = _stats([r for _, r in c.write_replies])
    leads = mvar_leads(c)
    return {
        "lines_loaded": len(c.loaded),
        "lines_executed": len(c.move_start),
        "run_time_errors": len(c.errors),
        "starvations": len(starv),
        "time_starved_s": sum(s.length for s in starv),
        "longest_starvation_s": max((s.length for s in starv), default=0.0),
        "min_lines_ahead": min(window) if window else None,
        "breq_rising": rising,
        "breq_rate_hz": rising / span,
        "host_writes": len(c.host_writes),
        "host_interrupts": sum(1 for _, missed, _ in c.host_irqs if not missed),
        "breq_missed": sum(1 for _, missed, _ in c.host_irqs if missed),
        "line_latency_mean_s": lat["mean"],
        "line_latency_p99_s": lat["p99"],
        "line_latency_max_s": lat["max"],
        "pr_replies": len(c.host_prs),
        "pr_reply_mean_s": pr["mean"],
        "pr_reply_max_s": pr["max"],
        "host_timeouts": len(c.host_timeouts),
        "write_replies": len(c.write_replies),
        "write_reply_mean_s": wr["mean"],
        "write_reply_p99_s": wr["p99"],
        "write_reply_max_s": wr["max"],
        "mvar": leads,
        "starvation_list": starv,
    }


# -- Trio ------------------------------------------------------------------------------------


@dataclass(slots=True)
class AxisTrace:
    axis: int
    states: list[tuple[float, int, int]] = field(default_factory=list)  # t, mtype, ntype
    pbuf: list[tuple[float, int]] = field(default_factory=list)  # t, process-buffer mtype
    moves_done: int = 0  # move_end events: moves the axis completed


def trio_traces(events: Iterable[Event]) -> tuple[dict[int, AxisTrace], list[dict[str, Any]]]:
    """Per axis MTYPE/NTYPE/process-buffer history; and every blocked interval (processes and
    feeding hosts) as ``{"who", "process", "start", "end", "blocked_on", "holder"}``: ``end``
    ``None`` = still blocked; ``holder`` = the axis whose move sat in that process's buffer
    when it blocked (what it really waited for, TN20-16)."""
    axes: dict[int, AxisTrace] = {}
    blocked: list[dict[str, Any]] = []
    open_: dict[str, dict[str, Any]] = {}
    pbuf_axis: dict[int, int | None] = {}

    def ax(n: int) -> AxisTrace:
        if n not in axes:
            axes[n] = AxisTrace(n)
        return axes[n]

    for e in events:
        f = e.fields
        if e.type == "axis":
            ax(f["axis"]).states.append((e.t, int(f["mtype"]), int(f["ntype"])))
        elif e.type == "move_end" and "axis" in f:
            ax(f["axis"]).moves_done += 1
        elif e.type == "process_buffer":
            p = f["process"]
            a = f.get("axis")
            if a is None:
                a = pbuf_axis.get(p)
            pbuf_axis[p] = a if f.get("mtype", 0) else None
            if a is not None:
                ax(a).pbuf.append((e.t, int(f.get("mtype", 0))))
        elif e.type in ("process", "host_blocked", "host_resumed"):
            if e.type == "process":
                p = f["process"]
                who = f"process {p}"
                is_blocked = f.get("state") == "blocked"
                on = f.get("blocked_on")
            else:
                p = f.get("process", 0)
                who = f"host {f['host']}"
                is_blocked = e.type == "host_blocked"
                on = f"AXIS({f.get('axis')})"
            if is_blocked and who not in open_:
                open_[who] = {
                    "who": who,
                    "process": p,
                    "start": e.t,
                    "end": None,
                    "blocked_on": on,
                    "blocked_axis": _axis_of(on),
                    "holder": pbuf_axis.get(p),
                }
                blocked.append(open_[who])
            elif not is_blocked and who in open_:
                open_.pop(who)["end"] = e.t
    return axes, blocked


def _axis_of(v: Any) -> int | None:
    if isinstance(v, int):
        return v
    if isinstance(v, dict):
        return _axis_of(v.get("axis"))
    if isinstance(v, str):  # the move line, e.g. "MOVE(VR(103)) AXIS(1)"
        m = re.search(r"AXIS\s*\(\s*(\d+)\s*\)", v, re.I) or re.fullmatch(r"\s*(\d+)\s*", v)
        return int(m.group(1)) if m else None
    return None


def idle_between_moves(a: AxisTrace) -> list[Interval]:
    """Intervals with MTYPE = 0 after the axis's first move and before its last one."""
    out = []
    idle_from: float | None = None
    started = False
    for t, mtype, _ in a.states:
        if mtype == 0:
            if started and idle_from is None:
                idle_from = t
        else:
            if idle_from is not None and t > idle_from:
                out.append(Interval(idle_from, t))
            idle_from = None
            started = True
    return out


def occupancy_s(a: AxisTrace, t_end: float) -> dict[str, float]:
    """Time with MTYPE, NTYPE and the process buffer (for this axis) occupied."""
    def busy(series: list[tuple[float, int]]) -> float:
        total, since = 0.0, None
        for t, v in series:
            if v and since is None:
                since = t
            elif not v and since is not None:
                total += t - since
                since = None
        return total + (t_end - since if since is not None else 0.0)

    return {
        "mtype_busy_s": busy([(t, m) for t, m, _ in a.states]),
        "ntype_busy_s": busy([(t, n) for t, _, n in a.states]),
        "process_buffer_busy_s": busy(a.pbuf),
    }


def trio_metrics(
    events: Sequence[Event], t_end: float, *, controller: str = "", min_idle_s: float = 0.0015
) -> dict[str, Any]:
    """Per axis occupancy and ``idle_while_blocked_s``; the axis stalls as starvations.

    An axis that is idle (MTYPE 0) between two of its moves while a process feeding the
    controller is blocked at a move line is stalled: an idle axis has free NTYPE and MTYPE, so
    what blocks the process is another axis's move holding the process buffer (TN20-16).
    Idle spells no longer than ``min_idle_s`` (the one-servo-period hand-over from one move
    to the next, 1 ms by default on a Trio) are not stalls.
    """
    axes, blocked = trio_traces(events)
    per_axis: dict[int, dict[str, Any]] = {}
    starv: list[Starvation] = []
    for n, a in sorted(axes.items()):
        m: dict[str, Any] = occupancy_s(a, t_end)
        idle_blocked = 0.0
        for iv in idle_between_moves(a):
            if iv.length <= min_idle_s:
                continue
            for b in blocked:
                s = max(iv.start, b["start"])
                e = min(iv.end, b["end"] if b["end"] is not None else t_end)
                if e > s:
                    idle_blocked += e - s
                    starv.append(
                        Starvation(
                            controller,
                            "axis_blocked",
                            s,
                            e,
                            axis=n,
                            facts={
                                "who": b["who"],
                                "blocked_on": b["blocked_on"],
                                "holder_axis": b["holder"],
                            },
                        )
                    )
        m["idle_while_blocked_s"] = idle_blocked
        m["moves_done"] = a.moves_done
        per_axis[n] = m
    return {
        "axes": per_axis,
        "blocked_intervals": len(blocked),
        "time_blocked_s": sum(
            (b["end"] if b["end"] is not None else t_end) - b["start"] for b in blocked
        ),
        "idle_while_blocked_s": sum(m["idle_while_blocked_s"] for m in per_axis.values()),
        "starvations": len(starv),
        "starvation_list": starv,
    }


__all__ = [
    "AxisTrace",
    "CsTrace",
    "Interval",
    "Starvation",
    "is_move_line",
    "line_latency",
    "motion_gaps",
    "mvar_leads",
    "pmac_cs_metrics",
    "pmac_traces",
    "starvations",
    "trio_metrics",
    "trio_traces",
    "waiting_intervals",
]
