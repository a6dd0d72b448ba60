"""The Rich summary printed after a run, at most 100 columns wide (piped too): per coordinate
system the rotary buffer and its host, the PMAC processor (when PLCs ran, an RTI overran or the
watchdog tripped), per Trio axis the moves it ran and its buffers, then the starvations grouped
by place and cause (count, total, longest, first / last; every episode is in metrics.json)
with the diagnosis of the longest of each group."""

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


#: Widest a table may be: readable in a 100-column terminal and in piped output.
WIDTH = 100


def summary_tables(rep: dict[str, Any]) -> list[Table]:
    tables = []
    pm = Table(title=f"{rep['scenario']} — rotary buffers (t = {rep['t_end_s']:.3f} s)")
    for col in ("controller", "&cs", "lines run", "starved", "time starved", "longest",
                "min ahead"):  # fmt: skip
        pm.add_column(col, justify="right" if col != "controller" else "left")
    host = Table(title=f"{rep['scenario']} — hosts and BREQ",
                 caption="write reply: command → answer, mean; line wait: loaded → executed, max")
    for col in ("controller", "&cs", "BREQ/s", "missed BREQ", "writes", "write reply",
                "line wait"):  # fmt: skip
        host.add_column(col, justify="right" if col != "controller" else "left")
    trio = Table(title=f"{rep['scenario']} — Trio axes",
                 caption="moves: completed (of expected_moves or the hosts' moves, where known)")
    for col in ("controller", "axis", "moves", "MTYPE busy", "NTYPE busy", "proc buf busy",
                "idle while blocked"):  # fmt: skip
        trio.add_column(col, justify="right" if col != "controller" else "left")
    for cid, r in rep["controllers"].items():
        if r["kind"] == "pmac":
            for cs, m in r["cs"].items():
                pm.add_row(
                    cid, str(cs), _f(m["lines_executed"]), _f(m["starvations"]),
                    _f(m["time_starved_s"], " ms", 1e3), _f(m["longest_starvation_s"], " ms", 1e3),
                    _f(m["min_lines_ahead"]),
                )  # fmt: skip
                host.add_row(
                    cid, str(cs), _f(m["breq_rate_hz"], "", 1, 1), _f(m["breq_missed"]),
                    _f(m["host_writes"]), _f(m.get("write_reply_mean_s"), " ms", 1e3),
                    _f(m["line_latency_max_s"], " ms", 1e3),
                )  # fmt: skip
        else:
            for axis, m in r["axes"].items():
                trio.add_row(
                    cid, str(axis), _moves(m), _f(m["mtype_busy_s"], " s"),
                    _f(m["ntype_busy_s"], " s"), _f(m["process_buffer_busy_s"], " s"),
                    _f(m["idle_while_blocked_s"], " s"),
                )  # fmt: skip
    for t in (pm, host):
        if t.row_count:
            tables.append(t)
    tables += _cpu_tables(rep)
    if trio.row_count:
        tables.append(trio)
    groups = rep.get("starvation_summary") or []
    if groups:
        st = Table(title="starvations and why",
                   caption=f"{len(rep['starvations'])} episodes; each one is in metrics.json")
        for col in ("where", "cause", "count", "total", "longest", "first", "last"):
            st.add_column(col, justify="left" if col in ("where", "cause") else "right",
                          no_wrap=col != "cause", overflow="fold")
        for g in groups:
            st.add_row(f"{g['controller']} {g['where']}", g["cause"], str(g["count"]),
                       _f(g["total_s"], " ms", 1e3, 1), _f(g["longest_s"], " ms", 1e3, 1),
                       _f(g["first_s"], " s", 1, 3), _f(g["last_s"], " s", 1, 3))
        tables.append(st)
    return tables


def _moves(m: dict[str, Any]) -> str:
    done, planned = m.get("moves_done"), m.get("moves_planned")
    if done is None:
        return "—"
    if planned is None:
        return str(done)
    text = f"{done}/{planned}"
    return text if done >= planned else f"[red]{text}[/red]"


def incomplete_axes(rep: dict[str, Any]) -> list[str]:
    """``"trio axis 1: 2 of 6 moves"`` for every axis that did not run all its moves."""
    out = []
    for cid, r in rep["controllers"].items():
        for axis, m in (r.get("axes") or {}).items():
            planned = m.get("moves_planned")
            if planned is not None and m.get("moves_done", 0) < planned:
                out.append(f"{cid} axis {axis}: {m['moves_done']} of {planned} moves")
    return out


def _cpu_tables(rep: dict[str, Any]) -> list[Table]:
    """The PMAC processor and the host's PR polls, one row per card (only when some card ran
    PLCs, overran an RTI or tripped its watchdog: else there is nothing to compare)."""
    cpus = {cid: r["cpu"] for cid, r in rep["controllers"].items() if r.get("cpu")}
    if not any(c["cpu_samples"] or c["rti_overruns"] or c["watchdog_tripped"]
               for c in cpus.values()):  # fmt: skip
        return []
    t = Table(title=f"{rep['scenario']} — PMAC processor")
    for col in ("controller", "PLC 0 stmts", "RTI overruns", "bg cycle mean", "bg cycle max",
                "watchdog trip"):  # fmt: skip
        t.add_column(col, justify="left" if col == "controller" else "right")
    pr = Table(title=f"{rep['scenario']} — PR polls",
               caption="PR reply: poll sent → card's answer; timeouts: polls never answered "
                       "within reply_timeout_ms")
    for col in ("controller", "PR reply mean", "PR reply max", "timeouts"):
        pr.add_column(col, justify="left" if col == "controller" else "right")
    for cid, c in cpus.items():
        t.add_row(
            cid, _f(c["plc0_statements_max"]), _f(c["rti_overruns"]),
            _f(c["background_cycle_mean_s"], " ms", 1e3),
            _f(c["background_cycle_max_s"], " ms", 1e3), _f(c["watchdog_trip_s"], " s", 1, 4),
        )  # fmt: skip
        pr.add_row(cid, _f(c["pr_reply_mean_s"], " ms", 1e3), _f(c["pr_reply_max_s"], " ms", 1e3),
                   _f(c["host_timeouts"]))
    return [t, pr]


def summary_console() -> Console:
    """A console at most :data:`WIDTH` columns wide, also when the output is piped."""
    console = Console()
    return Console(width=min(WIDTH, console.width) if console.is_terminal else WIDTH)


def print_summary(rep: dict[str, Any], console: Console | None = None) -> None:
    console = console or summary_console()
    for t in summary_tables(rep):
        console.print(t)
    for g in rep.get("starvation_summary") or []:
        console.print(f"{g['controller']} {g['where']} {g['cause']} (longest): {g['detail']}",
                      highlight=False)
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
    short = incomplete_axes(rep)
    for line in short:
        console.print(f"[red]not every move ran: {line}[/red]")
    if not rep["starvations"] and not short:
        console.print("[green]no starvation[/green]")


__all__ = ["WIDTH", "incomplete_axes", "print_summary", "summary_console", "summary_tables"]
