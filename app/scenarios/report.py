"""A run's metrics: per controller / coordinate system / axis, the starvations with their
diagnosis, and one flat row of headline numbers (what a sweep tabulates)."""

from __future__ import annotations

from typing import Any

from app.scenarios.diagnosis import (
    diagnose_axis_blocked,
    diagnose_buffer_empty,
    diagnose_run_time_error,
    lookahead_breaks,
)
from app.scenarios.metrics import (
    Starvation,
    pmac_cs_metrics,
    pmac_traces,
    run_time_errors,
    trio_metrics,
    waiting_intervals,
)
from app.scenarios.runner import RunResult
from sim.events import Event

#: The flat metrics of a run, in table order (a sweep's columns).
HEADLINE = (
    "time_starved_s",
    "starvations",
    "longest_starvation_s",
    "min_lines_ahead",
    "breq_rate_hz",
    "breq_missed",
    "host_writes",
    "host_interrupts",
    "line_latency_mean_s",
    "line_latency_max_s",
    "lookahead_breaks",
    "idle_while_blocked_s",
    "axis_stalls",
    "mvar_lead_max_s",
    "lines_executed",
    "run_time_errors",
)


def pmac_report(
    events: list[Event],
    t_end: float,
    *,
    controller: str = "",
    i16: int = 5,
    total_lines: dict[int, int | None] | None = None,
    rti_period_s: float | None = None,
) -> dict[str, Any]:
    """Metrics of a PMAC log, per coordinate system, with diagnosed starvations."""
    out: dict[str, Any] = {"kind": "pmac", "cs": {}}
    episodes: list[Starvation] = []
    for cs, c in sorted(pmac_traces(events).items()):
        total = (total_lines or {}).get(cs)
        m = pmac_cs_metrics(c, t_end, controller=controller, total_lines=total)
        starv = m.pop("starvation_list")
        for s in starv:
            diagnose_buffer_empty(s, c, i16)
        breaks = lookahead_breaks(c, waiting_intervals(c, t_end), controller)
        m["lookahead_breaks"] = len(breaks)
        m["lookahead_stopped_s"] = sum(b.length for b in breaks)
        errors = [
            diagnose_run_time_error(s, c, rti_period_s)
            for s in run_time_errors(c, t_end, controller)
        ]
        episodes += starv + breaks + errors
        out["cs"][cs] = m
    out["starvation_list"] = sorted(episodes, key=lambda s: s.start)
    return out


def trio_report(
    events: list[Event], t_end: float, *, controller: str = "", servo_period_s: float = 0.001
) -> dict[str, Any]:
    m = trio_metrics(events, t_end, controller=controller, min_idle_s=1.5 * servo_period_s)
    for s in m["starvation_list"]:
        diagnose_axis_blocked(s)
    m["kind"] = "trio"
    return m


def report(result: RunResult) -> dict[str, Any]:
    """Everything: ``{"controllers": {...}, "starvations": [...], "headline": {...}}``."""
    scn = result.scenario
    per: dict[str, Any] = {}
    episodes: list[Starvation] = []
    for cid, spec in scn.controllers.items():
        events = result.events(cid)
        if spec.kind == "pmac":
            i16, _ = spec.i16_i17()
            totals = {r.cs: result.total_lines(cid, r.cs) for r in spec.rotary}
            rti = result.controllers[cid].status().get("rti_period_s")
            r = pmac_report(
                events, result.t_end, controller=cid, i16=i16, total_lines=totals,
                rti_period_s=rti,
            )  # fmt: skip
        else:
            servo_s = float(spec.config.get("servo_period_ms", 1.0)) / 1000
            r = trio_report(events, result.t_end, controller=cid, servo_period_s=servo_s)
        episodes += r.pop("starvation_list")
        r["events"] = result.controllers[cid].log.last_seq
        r["events_lost"] = result.events_lost(cid)
        per[cid] = r
    episodes.sort(key=lambda s: (s.start, s.controller))
    return {
        "scenario": scn.name,
        "seed": scn.seed,
        "t_end_s": result.t_end,
        "stopped_by": result.stopped_by,
        "controllers": per,
        "starvations": [s.to_dict() for s in episodes],
        "headline": headline(per),
    }


def headline(per: dict[str, Any]) -> dict[str, Any]:
    """One flat row summarising every controller of a run."""
    cs_rows = [m for r in per.values() if r["kind"] == "pmac" for m in r["cs"].values()]
    trio = [r for r in per.values() if r["kind"] == "trio"]

    def total(key: str) -> Any:
        vals = [m[key] for m in cs_rows if m.get(key) is not None]
        return sum(vals) if vals else (0 if cs_rows else None)

    def extreme(key: str, fn: Any) -> Any:
        vals = [m[key] for m in cs_rows if m.get(key) is not None]
        return fn(vals) if vals else None

    leads = [
        x["lead_s"] for m in cs_rows for x in m.get("mvar", []) if x.get("lead_s") is not None
    ]
    executed = sum(m["lines_executed"] for m in cs_rows)
    weighted = [
        (m["line_latency_mean_s"], m["lines_executed"])
        for m in cs_rows
        if m.get("line_latency_mean_s") is not None
    ]
    return {
        "time_starved_s": total("time_starved_s"),
        "starvations": total("starvations"),
        "longest_starvation_s": extreme("longest_starvation_s", max),
        "min_lines_ahead": extreme("min_lines_ahead", min),
        "breq_rate_hz": total("breq_rate_hz"),
        "breq_missed": total("breq_missed"),
        "host_writes": total("host_writes"),
        "host_interrupts": total("host_interrupts"),
        "line_latency_mean_s": (
            sum(v * n for v, n in weighted) / max(1, sum(n for _, n in weighted))
            if weighted
            else None
        ),
        "line_latency_max_s": extreme("line_latency_max_s", max),
        "lookahead_breaks": total("lookahead_breaks"),
        "idle_while_blocked_s": sum(r["idle_while_blocked_s"] for r in trio) if trio else None,
        "axis_stalls": sum(r["starvations"] for r in trio) if trio else None,
        "mvar_lead_max_s": max(leads) if leads else None,
        "lines_executed": executed if cs_rows else None,
        "run_time_errors": total("run_time_errors"),
    }


__all__ = ["HEADLINE", "headline", "pmac_report", "report", "trio_report"]
