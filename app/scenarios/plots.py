"""PNG plots of a run (matplotlib, Agg backend: no display needed).

* PMAC, one figure per coordinate system: lines ahead over time (what ``PR`` reports) with
  I16 and I17 marked, starvations shaded (red: buffer empty, orange: lookahead stopped), and
  below it BREQ as a step trace with the host's writes as ticks. A watchdog trip is a red
  vertical line across both panels, labelled with its time, the stopped card hatched after
  it; a PLC 0 being enabled is a dotted grey line.
* Trio, one figure per controller: per axis a timeline of MTYPE, NTYPE and the process buffer
  occupied, with the time the axis idled while its process was blocked shaded.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
from motionsim.app.scenarios.metrics import pmac_traces, trio_traces  # noqa: E402
from motionsim.app.scenarios.runner import RunResult  # noqa: E402

_SHADE = {"buffer_empty": "tab:red", "lookahead_break": "tab:orange", "axis_blocked": "tab:red"}
_MAX_POINTS = 20_000


def _thin(ts: list[float], vs: list[Any]) -> tuple[list[float], list[Any]]:
    """Keep at most ~_MAX_POINTS steps, always keeping each bucket's min and max."""
    if len(ts) <= _MAX_POINTS:
        return ts, vs
    step = len(ts) // (_MAX_POINTS // 2) + 1
    out_t, out_v = [], []
    for i in range(0, len(ts), step):
        chunk = vs[i : i + step]
        lo = min(range(len(chunk)), key=chunk.__getitem__)
        hi = max(range(len(chunk)), key=chunk.__getitem__)
        for j in sorted({lo, hi}):
            out_t.append(ts[i + j])
            out_v.append(chunk[j])
    return out_t, out_v


def plot_pmac_cs(
    events: list[Any],
    cs: int,
    *,
    i16: int,
    i17: int,
    t_end: float,
    starvations: list[dict[str, Any]],
    title: str,
    path: Path,
) -> Path:
    c = pmac_traces(events)[cs]
    fig, (ax1, ax2) = plt.subplots(
        2, 1, figsize=(10, 6), dpi=100, sharex=True, gridspec_kw={"height_ratios": [3, 1]}
    )
    ts = [t for t, _ in c.lines_ahead]
    vs = [v for _, v in c.lines_ahead]
    ts, vs = _thin(ts, vs)
    if ts:
        ax1.step([*ts, t_end], [*vs, vs[-1]], where="post", lw=0.8, label="lines ahead (PR)")
    ax1.axhline(i17, ls="--", color="tab:green", lw=1, label=f"I17 = {i17}")
    ax1.axhline(i16, ls="--", color="tab:purple", lw=1, label=f"I16 = {i16}")
    for s in starvations:
        if s.get("cs") == cs:
            ax1.axvspan(s["start_s"], s["end_s"], color=_SHADE.get(s["kind"], "grey"), alpha=0.3)
            ax2.axvspan(s["start_s"], s["end_s"], color=_SHADE.get(s["kind"], "grey"), alpha=0.3)
    for t, label, style in _card_marks(events):
        for ax in (ax1, ax2):
            ax.axvline(t, **style)
            if style["color"] == "tab:red" and t < t_end:  # the card is stopped from here
                ax.axvspan(t, t_end, facecolor="none", edgecolor="gray", hatch="//", lw=0)
        ax1.annotate(label, (t, 0.55), xycoords=("data", "axes fraction"), xytext=(4, 0),
                     textcoords="offset points", fontsize=8, color=style["color"],
                     backgroundcolor="white")  # fmt: skip
    ax1.set_ylabel("lines ahead")
    ax1.set_title(title)
    ax1.legend(loc="upper right", fontsize=8)
    bt = [0.0] + [t for t, _ in c.breq]
    bv = [0] + [int(lv) for _, lv in c.breq]
    bt, bv = _thin(bt, bv)
    ax2.step([*bt, t_end], [*bv, bv[-1]], where="post", color="tab:blue", lw=0.8, label="BREQ")
    if c.host_writes:
        wt = [t for t, _ in c.host_writes][:_MAX_POINTS]
        ax2.plot(wt, [1.15] * len(wt), "|", color="black", ms=6, label="host write")
    ax2.set_ylim(-0.1, 1.35)
    ax2.set_yticks([0, 1])
    ax2.set_yticklabels(["low", "high"])
    ax2.set_xlabel("simulated time (s)")
    ax2.set_xlim(0, t_end)
    ax2.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _card_marks(events: list[Any]) -> list[tuple[float, str, dict[str, Any]]]:
    """Instants that concern the whole card: PLC 0 enabled, the watchdog trip."""
    out = []
    for e in events:
        if e.type == "watchdog":
            style = {"color": "tab:red", "lw": 1.5}
            out.append((e.t, f"watchdog trip {e.t:.3f} s", style))
        elif e.type == "plc" and e.fields.get("plc") == 0 and e.fields.get("state") == "enabled":
            style = {"color": "dimgray", "lw": 1, "ls": ":"}
            out.append((e.t, f"PLC 0 enabled {e.t:.3f} s", style))
    return out


def plot_trio(
    events: list[Any], *, t_end: float, starvations: list[dict[str, Any]], title: str, path: Path
) -> Path:
    axes, _ = trio_traces(events)
    n = max(1, len(axes))
    fig, subs = plt.subplots(n, 1, figsize=(10, 1.6 * n + 1.2), dpi=100, sharex=True, squeeze=False)
    for row, (axis, a) in zip(subs[:, 0], sorted(axes.items()), strict=False):
        lanes = [
            ("MTYPE", [(t, m) for t, m, _ in a.states], "tab:blue"),
            ("NTYPE", [(t, nt) for t, _, nt in a.states], "tab:cyan"),
            ("process buffer", a.pbuf, "tab:gray"),
        ]
        for lane, (_label, series, color) in enumerate(lanes):
            bars = _busy_bars(series, t_end)
            row.broken_barh(bars, (2 - lane - 0.4, 0.8), color=color)
        for s in starvations:
            if s.get("axis") == axis:
                row.axvspan(s["start_s"], s["end_s"], color="tab:red", alpha=0.25)
        row.set_yticks([2, 1, 0])
        row.set_yticklabels([lb for lb, _, _ in lanes], fontsize=8)
        row.set_ylim(-0.6, 2.6)
        row.set_ylabel(f"axis {axis}")
    subs[0, 0].set_title(title)
    subs[-1, 0].set_xlabel("simulated time (s)")
    subs[-1, 0].set_xlim(0, t_end)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _busy_bars(series: list[tuple[float, int]], t_end: float) -> list[tuple[float, float]]:
    bars, since = [], None
    for t, v in series:
        if v and since is None:
            since = t
        elif not v and since is not None:
            bars.append((since, max(t - since, 1e-9)))
            since = None
    if since is not None:
        bars.append((since, max(t_end - since, 1e-9)))
    return bars


def plot_run(result: RunResult, rep: dict[str, Any], out_dir: Path) -> dict[str, Path]:
    """Every plot of a run into ``out_dir``; returns ``{file name: path}``."""
    paths: dict[str, Path] = {}
    scn = result.scenario
    for cid, spec in scn.controllers.items():
        events = result.events(cid)
        if spec.kind == "pmac":
            i16, i17 = spec.i16_i17()
            for cs in rep["controllers"][cid]["cs"]:
                name = f"{cid}_cs{cs}_lines_ahead.png"
                paths[name] = plot_pmac_cs(
                    events, cs, i16=i16, i17=i17, t_end=result.t_end,
                    starvations=[s for s in rep["starvations"] if s["controller"] == cid],
                    title=f"{scn.name}: {cid} &{cs} rotary buffer", path=out_dir / name,
                )  # fmt: skip
        else:
            name = f"{cid}_buffers.png"
            paths[name] = plot_trio(
                events, t_end=result.t_end,
                starvations=[s for s in rep["starvations"] if s["controller"] == cid],
                title=f"{scn.name}: {cid} MTYPE / NTYPE / process buffer", path=out_dir / name,
            )  # fmt: skip
    return paths


__all__ = ["plot_pmac_cs", "plot_run", "plot_trio"]
