"""``assert_fed``: was the controller kept fed? The scenario runner's diagnosis, for a test.

A served controller's event log is read back over REST and handed to the same report a
``motionsim run`` writes (:func:`motionsim.app.scenarios.report.pmac_report` /
``trio_report``): the starvation episodes and their diagnosis (``host_latency``,
``breq_missed``, ``host_commands_unanswered``, ``calculation_fell_behind``, watchdog causes,
``process_blocked_on_other_axis``) come from there, not from a second reading of the log.
What this module adds is the sentence a failing test prints: per episode the simulated
instant, the line it happened after, the lines ahead of move planning, and the cause.

    from .fed import assert_fed
    assert_fed(motionsim, "pmac", cs=1)     # AssertionError naming each starvation
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from ...sim.events import Event
from .metrics import CsTrace, Starvation, pmac_traces

#: Episodes ``assert_fed`` tolerates unless told otherwise: a DWELL or RAPID stops lookahead
#: by design (TUM p341), so motion pausing there is what the program asked for.
ALLOWED = ("lookahead_break",)


def to_events(records: Iterable[Mapping[str, Any]]) -> list[Event]:
    """Wire-form events (``{"seq", "t", "type", ...fields}``) back into :class:`Event`."""
    out = []
    for r in records:
        fields = {k: v for k, v in r.items() if k not in ("seq", "t", "type", "controller")}
        out.append(Event(int(r["seq"]), float(r["t"]), str(r["type"]), fields))
    return out


def _at(series: Sequence[tuple[float, int]], t: float) -> int | None:
    """The last value of a (t, value) series at or before ``t``."""
    value = None
    for ts, v in series:
        if ts > t:
            break
        value = v
    return value


def _last_line(c: CsTrace, t: float) -> int | None:
    started = [(ts, n) for n, ts in c.move_start.items() if ts <= t]
    return max(started)[1] if started else None


def describe(s: Starvation, traces: Mapping[int, CsTrace], *, controller: bool = True) -> str:
    """One line: where, when, for how long, after which line, lines ahead, cause, why
    (``controller``: start with the controller's id; off where a header names it once)."""
    name = s.controller if controller else ""
    where = f"{name} &{s.cs}" if s.cs is not None else (
        f"{name} axis {s.axis}" if s.axis is not None else name or "controller")
    where = where.strip()
    text = f"{where}: {s.kind} at t={s.start:.6f} s for {s.length * 1e3:.3f} ms"
    c = traces.get(s.cs) if s.cs is not None else None
    if c is not None:
        line = _last_line(c, s.start)
        ahead = _at(c.lines_ahead, s.start)
        text += (f", after line {line if line is not None else '(none yet)'}"
                 f" with {ahead or 0} lines ahead ({len(c.loaded)} loaded in all)")
    text += f" — cause {s.cause}"
    return text + (f": {s.detail}" if s.detail else "")


def episodes(client: Any, id: str, *, cs: int | None = None,
             total_lines: Mapping[int, int] | None = None
             ) -> tuple[list[Starvation], dict[int, CsTrace]]:
    """The diagnosed starvations of controller ``id`` so far, and (PMAC) the coordinate
    systems' traces :func:`describe` reads the line and lines ahead from."""
    from .report import pmac_report, trio_report

    kind = client.controller(id)["kind"]
    t_end = client.clock(id).t
    events = to_events(client.all_events(id))
    traces: dict[int, CsTrace] = {}
    if kind == "pmac":
        i16 = int(client.get_variable(id, "I16"))
        i40 = int(client.get_variable(id, "I40"))
        rep = pmac_report(events, t_end, controller=id, i16=i16, i40=i40,
                          total_lines=dict(total_lines or {}))
        traces = pmac_traces(events)
    elif kind == "trio":
        rep = trio_report(events, t_end, controller=id)
    else:
        raise ValueError(f"assert_fed knows kinds pmac and trio, not {kind!r}")
    found = [s for s in rep["starvation_list"] if cs is None or s.cs in (None, cs)]
    return found, traces


def assert_fed(client: Any, id: str | None = None, cs: int | None = None, *,
               total_lines: Mapping[int, int] | None = None,
               allow: Sequence[str] = ALLOWED) -> None:
    """Fail unless controller ``id`` (coordinate system ``cs``, default all) never starved.

    Args:
        client: a :class:`motionsim.app.client.MotionSimClient` (the ``motionsim`` fixture),
            or a fixture's controller (``motionsim_pmac``: then no ``id``).
        total_lines: per coordinate system, the lines the host meant to send: a program that
            ran dry before all of them were loaded starved even if the host then stopped.
        allow: episode kinds that do not fail (default: lookahead breaks at DWELL / RAPID).
    """
    __tracebackhide__ = True  # pytest shows the test's line, not this function's source
    if id is None:  # a bound controller (pytest_plugin.Controller)
        client, id = client.client, client.id
    found, traces = episodes(client, id, cs=cs, total_lines=total_lines)
    bad = [s for s in found if s.kind not in allow]
    if bad:  # the id once (a fixture's id can be long), then one line per starvation
        lines = "\n".join(f"  {describe(s, traces, controller=False)}" for s in bad)
        raise AssertionError(f"{id} starved {len(bad)} time(s):\n{lines}")


__all__ = ["ALLOWED", "assert_fed", "describe", "episodes", "to_events"]
