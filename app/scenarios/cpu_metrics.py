"""What the PMAC's processor did in a run: PLC 0 load, RTI overruns, background cycle time,
host-command reply latency, and the watchdog — read from the event log.

Events used: ``rti_overrun`` (an RTI found the previous RTI's tasks still running),
``watchdog`` (the card tripped), ``program`` with ``error="watchdog"`` (programs aborted by
the trip), ``mvar`` at the trip instant (outputs turned off), the run's ``cpu_sample`` events
(:mod:`motionsim.sim.hosts.monitor`: the card's ``status()["cpu"]`` sampled on a grid) and the
hosts' ``host_pr`` / ``host_timeout`` / ``host_stopped`` (:mod:`motionsim.sim.hosts.pmac`).

TUM p236-237: the more foreground work (servo, RTI: move planning and PLC 0), the slower the
background cycles; the background answers host commands and each of its cycles reloads the
watchdog, so a PLC 0 longer than the RTI period leaves no background cycle and the watchdog
trips I40 servo cycles (0 → 4096, ≈ 1.81 s at the default 442.7 µs) after the last one.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

from ...sim.events import Event
from .metrics import _stats


@dataclass(slots=True)
class CpuTrace:
    """The processor-related history of one PMAC log."""

    overruns: list[tuple[float, float]] = field(default_factory=list)  # t, over_s
    samples: list[tuple[float, dict[str, Any]]] = field(default_factory=list)
    replies: list[tuple[float, float, str]] = field(default_factory=list)  # t, reply_s, host
    timeouts: list[tuple[float, str]] = field(default_factory=list)  # t, host
    trip: tuple[float, str] | None = None  # t, reason
    enabled: list[tuple[float, int, bool]] = field(default_factory=list)  # t, plc, enabled
    aborted: list[tuple[float, int]] = field(default_factory=list)  # t, cs (by the watchdog)
    outputs_off: list[str] = field(default_factory=list)  # M-variables zeroed by the trip
    hosts_stopped: list[tuple[float, str]] = field(default_factory=list)
    lines_calculated: list[float] = field(default_factory=list)


def cpu_trace(events: Iterable[Event]) -> CpuTrace:
    c = CpuTrace()
    for e in events:
        typ, f = e.type, e.fields
        if typ == "rti_overrun":
            c.overruns.append((e.t, float(f.get("over_s", 0.0))))
        elif typ == "cpu_sample":
            c.samples.append((e.t, f))
        elif typ == "host_pr":
            c.replies.append((e.t, float(f["reply_s"]), str(f.get("host"))))
        elif typ == "host_timeout":
            c.timeouts.append((e.t, str(f.get("host"))))
        elif typ == "host_stopped":
            c.hosts_stopped.append((e.t, str(f.get("host"))))
        elif typ == "watchdog" and c.trip is None:
            c.trip = (e.t, str(f.get("reason", "")))
        elif typ == "plc":
            c.enabled.append((e.t, int(f["plc"]), f.get("state") == "enabled"))
        elif typ == "program" and f.get("error") == "watchdog":
            c.aborted.append((e.t, int(f.get("cs", 0))))
        elif typ == "mvar" and c.trip is not None and e.t == c.trip[0] and f.get("value") == 0:
            c.outputs_off.append(str(f["name"]))
        elif typ == "line_calculated":
            c.lines_calculated.append(e.t)
    return c


def _mean(xs: list[float]) -> float | None:
    return sum(xs) / len(xs) if xs else None


def stopped_by_trip(c: CpuTrace) -> list[str]:
    """What the watchdog trip stopped, in words (empty when it did not trip)."""
    if c.trip is None:
        return []
    out = [f"&{cs} program aborted (motors killed, no deceleration)" for _, cs in c.aborted]
    if c.outputs_off:
        out.append(f"outputs off: {', '.join(c.outputs_off)}")
    out += [f"host {h} stopped at {t:.6f} s (the card answers nothing)"
            for t, h in c.hosts_stopped]  # fmt: skip
    out.append("the card: no command answered, no task run until reset (power cycle)")
    return out


def cpu_metrics(c: CpuTrace) -> dict[str, Any]:
    """The numbers: overruns, background cycle (sampled), PR reply latency, the trip.

    Background cycle figures are the sampled ``background_cycle_s`` (the last *completed*
    cycle); a cycle that never completes shows only in the watchdog trip (the report then
    raises ``background_cycle_max_s`` to the I40 window)."""
    cycles = [float(f["background_cycle_s"]) for _, f in c.samples]
    rti = [float(f["rti"]) for _, f in c.samples]
    stmts = [int(f.get("plc0_statements", 0)) for _, f in c.samples]
    replies = [r for _, r, _ in c.replies]
    pr = _stats(replies)
    return {
        "rti_overruns": len(c.overruns),
        "first_rti_overrun_s": c.overruns[0][0] if c.overruns else None,
        "plc0_statements_max": max(stmts) if stmts else None,
        "rti_load_max": max(rti) if rti else None,
        "background_cycle_mean_s": _mean(cycles),
        "background_cycle_max_s": max(cycles) if cycles else None,
        "background_cycle_last_s": cycles[-1] if cycles else None,
        "cpu_samples": len(c.samples),
        "pr_replies": len(replies),
        "pr_reply_mean_s": _mean(replies),
        "pr_reply_p99_s": pr["p99"],
        "pr_reply_max_s": pr["max"],
        "host_timeouts": len(c.timeouts),
        "watchdog_tripped": c.trip is not None,
        "watchdog_trip_s": c.trip[0] if c.trip else None,
        "watchdog_reason": c.trip[1] if c.trip else None,
        "stopped": stopped_by_trip(c),
    }


__all__ = ["CpuTrace", "cpu_metrics", "cpu_trace", "stopped_by_trip"]
