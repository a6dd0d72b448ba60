"""A run's metrics: per controller / coordinate system / axis, the starvations with their
diagnosis (a watchdog trip is one too), the PMAC processor (``cpu``), and one flat row of
headline numbers (what a sweep tabulates)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...sim.events import Event
from ...sim.timing import pmac_servo_period_s
from .cpu_metrics import CpuTrace, cpu_metrics, cpu_trace
from .diagnosis import (
    diagnose_axis_blocked,
    diagnose_buffer_empty,
    diagnose_run_time_error,
    diagnose_unanswered,
    diagnose_watchdog,
    lookahead_breaks,
)
from .metrics import (
    Starvation,
    pmac_cs_metrics,
    pmac_traces,
    run_time_errors,
    trio_metrics,
    waiting_intervals,
)
from .runner import RunResult

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
    "rti_overruns",
    "watchdog_trips",
    "watchdog_trip_s",
    "pr_reply_mean_s",
    "pr_reply_max_s",
    "host_timeouts",
    "background_cycle_max_s",
    "write_reply_mean_s",
    "write_reply_max_s",
)

#: Turbo PMAC default servo period (I10 = 3713707): 442.7 µs.
_SERVO_S = pmac_servo_period_s(3713707)


def pmac_report(
    events: list[Event],
    t_end: float,
    *,
    controller: str = "",
    i16: int = 5,
    total_lines: dict[int, int | None] | None = None,
    rti_period_s: float | None = None,
    servo_period_s: float | None = None,
    config: dict[str, Any] | None = None,
    i40: int | None = None,
    plc0_statements: int | None = None,
) -> dict[str, Any]:
    """Metrics of a PMAC log, per coordinate system, with diagnosed starvations; the card's
    processor under ``"cpu"`` (a watchdog trip diagnosed as an episode).

    Args:
        config: the controller's config (processor costs ``cpu_*_us``, ``i40``).
        i40: I40 at the end of the run (else from ``config``, else 0).
        plc0_statements: PLC 0's last scan, when the log has no ``cpu_sample`` to say it.
    """
    out: dict[str, Any] = {"kind": "pmac", "cs": {}}
    episodes: list[Starvation] = []
    for cs, c in sorted(pmac_traces(events).items()):
        total = (total_lines or {}).get(cs)
        m = pmac_cs_metrics(c, t_end, controller=controller, total_lines=total)
        starv = m.pop("starvation_list")
        for s in starv:
            diagnose_buffer_empty(s, c, i16)
            diagnose_unanswered(s, c)
        breaks = lookahead_breaks(c, waiting_intervals(c, t_end), controller)
        m["lookahead_breaks"] = len(breaks)
        m["lookahead_stopped_s"] = sum(b.length for b in breaks)
        errors = [
            diagnose_run_time_error(s, c, rti_period_s)
            for s in run_time_errors(c, t_end, controller)
        ]
        episodes += starv + breaks + errors
        out["cs"][cs] = m
    ct = cpu_trace(events)
    out["cpu"] = cpu_metrics(ct)
    if ct.trip is not None:
        trip = _watchdog_episode(
            ct, t_end, controller, config or {}, i40, plc0_statements,
            servo_period_s or _SERVO_S, rti_period_s,
        )  # fmt: skip
        episodes.append(trip)
        # the background cycle that never completed: from the last one to the trip
        open_cycle = trip.start - trip.facts["last_background_s"]
        out["cpu"]["background_cycle_max_s"] = max(
            open_cycle, out["cpu"]["background_cycle_max_s"] or 0.0
        )
    out["starvation_list"] = sorted(episodes, key=lambda s: s.start)
    return out


def _watchdog_episode(
    ct: CpuTrace,
    t_end: float,
    controller: str,
    config: dict[str, Any],
    i40: int | None,
    plc0_statements: int | None,
    servo_s: float,
    rti_s: float | None,
) -> Starvation:
    """The trip as an episode, with the PLC 0 / RTI arithmetic that explains it."""
    from ...sim.pmac.tasks.cpu import CpuCosts
    from ...sim.pmac.tasks.watchdog import DEFAULT_LIMIT_CYCLES

    assert ct.trip is not None
    t_trip = ct.trip[0]
    cfg = {k.lower(): v for k, v in config.items()}
    costs = CpuCosts.from_config(cfg)
    if i40 is None:
        i40 = int(cfg.get("i40", 0))
    limit = DEFAULT_LIMIT_CYCLES if i40 <= 0 else i40
    if rti_s is None:
        rti_s = (int(cfg.get("i8", 2)) + 1) * servo_s
    before = [f for t, f in ct.samples if t <= t_trip]
    stmts = int(before[-1].get("plc0_statements", 0)) if before else plc0_statements
    scan = costs.plc_scan_s + costs.plc_statement_s * stmts if stmts else None
    servo_share = float(before[-1]["servo"]) if before else 0.0
    # move planning per RTI over the last second before the trip
    t0 = max(0.0, t_trip - 1.0)
    lines = sum(1 for t in ct.lines_calculated if t0 < t <= t_trip)
    rtis = max(1.0, (t_trip - t0) / rti_s)
    planning = costs.rti_base_s + costs.plan_line_s * lines / rtis
    plc0_on = [t for t, n, on in ct.enabled if n == 0 and on and t <= t_trip]
    return diagnose_watchdog(
        controller, t_trip, t_end,
        limit_cycles=limit, i40=i40, servo_period_s=servo_s, rti_period_s=rti_s,
        servo_share=servo_share, plc0_statements=stmts, plc0_scan_s=scan,
        planning_s=planning, rti_overruns=len(ct.overruns),
        first_overrun_s=ct.overruns[0][0] if ct.overruns else None,
        plc0_enabled_s=plc0_on[-1] if plc0_on else None,
    )  # fmt: skip


def trio_report(
    events: list[Event], t_end: float, *, controller: str = "", servo_period_s: float = 0.001
) -> dict[str, Any]:
    m = trio_metrics(events, t_end, controller=controller, min_idle_s=1.5 * servo_period_s)
    for s in m["starvation_list"]:
        diagnose_axis_blocked(s)
    m["kind"] = "trio"
    return m


def report(result: RunResult,
           progress: Callable[[float, float], None] | None = None) -> dict[str, Any]:
    """Everything: ``{"controllers": {...}, "starvations": [...], "headline": {...}}``;
    ``progress(done, total)`` after each controller's analysis (a long log takes a while)."""
    scn = result.scenario
    per: dict[str, Any] = {}
    episodes: list[Starvation] = []
    for k, (cid, spec) in enumerate(scn.controllers.items()):
        if progress is not None:
            progress(k, len(scn.controllers))
        events = result.events(cid)
        if spec.kind == "pmac":
            i16, _ = spec.i16_i17()
            totals = {r.cs: result.total_lines(cid, r.cs) for r in spec.rotary}
            ctl: Any = result.controllers[cid]
            status = ctl.status()
            plcs = getattr(ctl, "plcs", None)
            r = pmac_report(
                events, result.t_end, controller=cid, i16=i16, total_lines=totals,
                rti_period_s=status.get("rti_period_s"),
                servo_period_s=status.get("servo_period_s"), config=spec.config,
                i40=int(ctl.get_variable("I40")),
                plc0_statements=plcs.plc(0).last_statements if plcs is not None else None,
            )  # fmt: skip
            # the card's own load figure at the end (meaningless once the watchdog tripped)
            r["cpu"]["at_end"] = None if status["watchdog"]["tripped"] else status.get("cpu")
        else:
            servo_s = float(spec.config.get("servo_period_ms", 1.0)) / 1000
            r = trio_report(events, result.t_end, controller=cid, servo_period_s=servo_s)
            _moves_planned(r, {**spec.expected_moves, **planned_moves(scn, cid)})
        episodes += r.pop("starvation_list")
        r["events"] = result.controllers[cid].log.last_seq
        r["events_lost"] = result.events_lost(cid)
        per[cid] = r
    if progress is not None:
        progress(len(scn.controllers), len(scn.controllers))
    episodes.sort(key=lambda s: (s.start, s.controller))
    return {
        "scenario": scn.name,
        "seed": scn.seed,
        "t_end_s": result.t_end,
        "stopped_by": result.stopped_by,
        "controllers": per,
        "starvations": [s.to_dict() for s in episodes],
        "starvation_summary": summarise_starvations(episodes),
        "headline": headline(per),
    }


def planned_moves(scn: Any, controller: str) -> dict[int, int]:
    """Moves per axis the scenario's feeder hosts issue to ``controller`` (a BASIC program's
    moves are not known before it runs)."""
    out: dict[int, int] = {}
    for i, h in enumerate(scn.hosts):
        if h.type.startswith("trio_") and scn.host_controller(i) == controller:
            for move in h.moves.to_moves():
                out[move.axis] = out.get(move.axis, 0) + 1
    return out


def _moves_planned(r: dict[str, Any], planned: dict[int, int]) -> None:
    """``moves_planned`` per axis (None where unknown); an axis with planned moves that never
    moved gets a row too."""
    for axis in planned:
        r["axes"].setdefault(axis, {"mtype_busy_s": 0.0, "ntype_busy_s": 0.0,
                                    "process_buffer_busy_s": 0.0, "idle_while_blocked_s": 0.0,
                                    "moves_done": 0})
    for axis, m in r["axes"].items():
        m["moves_planned"] = planned.get(axis)
    r["axes"] = dict(sorted(r["axes"].items()))


def summarise_starvations(episodes: list[Starvation]) -> list[dict[str, Any]]:
    """Starvations grouped by controller, place and cause: ``count``, ``total_s``,
    ``longest_s``, ``first_s`` / ``last_s`` (starts) and the longest one's ``detail``."""
    groups: dict[tuple[Any, ...], list[Starvation]] = {}
    for s in episodes:
        where = f"&{s.cs}" if s.cs is not None else (
            f"axis {s.axis}" if s.axis is not None else "card")
        groups.setdefault((s.controller, where, s.cause), []).append(s)
    out = []
    for (controller, where, cause), items in groups.items():
        longest = max(items, key=lambda x: x.length)
        out.append({
            "controller": controller, "where": where, "cause": cause, "count": len(items),
            "total_s": sum(x.length for x in items), "longest_s": longest.length,
            "first_s": min(x.start for x in items), "last_s": max(x.start for x in items),
            "detail": longest.detail,
        })
    return out


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
    cpus = [r["cpu"] for r in per.values() if r["kind"] == "pmac" and "cpu" in r]
    trips = [c["watchdog_trip_s"] for c in cpus if c["watchdog_trip_s"] is not None]
    replies = [(m["pr_reply_mean_s"], m["pr_replies"]) for m in cs_rows
               if m.get("pr_reply_mean_s") is not None]  # fmt: skip
    writes = [(m["write_reply_mean_s"], m["write_replies"]) for m in cs_rows
              if m.get("write_reply_mean_s") is not None]  # fmt: skip
    cycles = [c["background_cycle_max_s"] for c in cpus
              if c.get("background_cycle_max_s") is not None]  # fmt: skip
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
        "rti_overruns": sum(c["rti_overruns"] for c in cpus) if cpus else None,
        "watchdog_trips": len(trips) if cpus else None,
        "watchdog_trip_s": min(trips) if trips else None,
        "pr_reply_mean_s": (
            sum(v * n for v, n in replies) / max(1, sum(n for _, n in replies))
            if replies
            else None
        ),
        "pr_reply_max_s": extreme("pr_reply_max_s", max),
        "host_timeouts": total("host_timeouts"),
        "background_cycle_max_s": max(cycles) if cycles else None,
        "write_reply_mean_s": (
            sum(v * n for v, n in writes) / max(1, sum(n for _, n in writes)) if writes else None
        ),
        "write_reply_max_s": extreme("write_reply_max_s", max),
    }


__all__ = ["HEADLINE", "headline", "planned_moves", "pmac_report", "report",
           "summarise_starvations", "trio_report"]
