"""The Rich summary printed after a run: one row per coordinate system / Trio controller,
the PMAC processor (when PLCs ran, an RTI overran or the watchdog tripped), then each
starvation with its diagnosis."""

from __future__ import annotations

from typing import Any

from rich.console import Console
from rich.table import Table


def _f(v: Any, unit: str = "", scale: float = 1.0, digits: int = 3) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v * scale:.{digits}f}{unit}"
    return f"{v}{unit}"


def summary_tables(rep: dict[str, Any], *, max_starvations: int = 20) -> list[Table]:
    tables = []
    pm = Table(title=f"{rep['scenario']} — rotary buffers (t = {rep['t_end_s']:.3f} s)")
    for col in ("controller", "&cs", "lines run", "starved", "time starved", "longest",
                "min ahead", "BREQ/s", "missed", "writes", "write reply",
                "latency max"):  # fmt: skip
        pm.add_column(col, justify="right" if col not in ("controller",) else "left")
    trio = Table(title=f"{rep['scenario']} — Trio axes")
    for col in ("controller", "axis", "MTYPE busy", "NTYPE busy", "proc buf busy",
                "idle while blocked"):  # fmt: skip
        trio.add_column(col, justify="right" if col != "controller" else "left")
    for cid, r in rep["controllers"].items():
        if r["kind"] == "pmac":
            for cs, m in r["cs"].items():
                pm.add_row(
                    cid, str(cs), _f(m["lines_executed"]), _f(m["starvations"]),
                    _f(m["time_starved_s"], " ms", 1e3), _f(m["longest_starvation_s"], " ms", 1e3),
                    _f(m["min_lines_ahead"]), _f(m["breq_rate_hz"], "", 1, 1),
                    _f(m["breq_missed"]), _f(m["host_writes"]),
                    _f(m.get("write_reply_mean_s"), " ms", 1e3),
                    _f(m["line_latency_max_s"], " ms", 1e3),
                )  # fmt: skip
        else:
            for axis, m in r["axes"].items():
                trio.add_row(
                    cid, str(axis), _f(m["mtype_busy_s"], " s"), _f(m["ntype_busy_s"], " s"),
                    _f(m["process_buffer_busy_s"], " s"), _f(m["idle_while_blocked_s"], " s"),
                )  # fmt: skip
    if pm.row_count:
        tables.append(pm)
    cpu = _cpu_table(rep)
    if cpu.row_count:
        tables.append(cpu)
    if trio.row_count:
        tables.append(trio)
    st = Table(title="starvations and why")
    for col in ("controller", "where", "start", "length", "cause", "detail"):
        st.add_column(col, no_wrap=col != "detail")
    episodes = rep["starvations"]
    for s in episodes[:max_starvations]:
        if "cs" in s:
            where = f"&{s['cs']}"
        elif "axis" in s:
            where = f"axis {s['axis']}"
        else:
            where = "card"
        st.add_row(
            s["controller"], where, _f(s["start_s"], " s", 1, 4), _f(s["length_s"], " ms", 1e3),
            s["cause"], s["detail"],
        )  # fmt: skip
    if len(episodes) > max_starvations:
        st.caption = f"{len(episodes) - max_starvations} more in metrics.json"
    if episodes:
        tables.append(st)
    return tables


def _cpu_table(rep: dict[str, Any]) -> Table:
    t = Table(title=f"{rep['scenario']} — PMAC processor")
    for col in ("controller", "PLC 0 stmts", "RTI overruns", "bg cycle mean", "bg cycle max",
                "PR reply mean", "PR reply max", "timeouts", "watchdog trip"):  # fmt: skip
        t.add_column(col, justify="left" if col == "controller" else "right")
    cpus = {cid: r["cpu"] for cid, r in rep["controllers"].items() if r.get("cpu")}
    if not any(c["cpu_samples"] or c["rti_overruns"] or c["watchdog_tripped"]
               for c in cpus.values()):  # fmt: skip
        return t  # no PLCs, no overrun, no trip: nothing to compare
    for cid, c in cpus.items():
        t.add_row(
            cid, _f(c["plc0_statements_max"]), _f(c["rti_overruns"]),
            _f(c["background_cycle_mean_s"], " ms", 1e3),
            _f(c["background_cycle_max_s"], " ms", 1e3),
            _f(c["pr_reply_mean_s"], " ms", 1e3), _f(c["pr_reply_max_s"], " ms", 1e3),
            _f(c["host_timeouts"]), _f(c["watchdog_trip_s"], " s", 1, 4),
        )  # fmt: skip
    return t


def print_summary(rep: dict[str, Any], console: Console | None = None) -> None:
    console = console or Console()
    for t in summary_tables(rep):
        console.print(t)
    for cid, r in rep["controllers"].items():
        if r.get("events_lost"):
            console.print(
                f"[yellow]{cid}: the first {r['events_lost']} events left the log before they "
                "were read; metrics cover the rest (set log_capacity in the scenario)[/yellow]"
            )
    for cid, r in rep["controllers"].items():
        stopped = (r.get("cpu") or {}).get("stopped")
        if stopped:
            console.print(f"[red]{cid}: the watchdog tripped; stopped: {'; '.join(stopped)}[/red]")
    if not rep["starvations"]:
        console.print("[green]no starvation[/green]")


__all__ = ["print_summary", "summary_tables"]
