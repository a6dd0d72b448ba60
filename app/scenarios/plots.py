"""PNG plots of a run (matplotlib, Agg backend: no display needed).

* PMAC, one figure per coordinate system: lines ahead over time (what ``PR`` reports) with
  I16 and I17 marked, starvations shaded (red: buffer empty, orange: lookahead stopped), and
  below it BREQ as a step trace with the host's writes as ticks. A watchdog trip is a red
  vertical line across both panels, labelled with its time, the stopped card hatched after
  it; a PLC 0 being enabled is a dotted grey line.
* Trio, one figure per controller: per axis a timeline of MTYPE, NTYPE and the process buffer
  occupied, with the time the axis idled while its process was blocked shaded.

* A controller that recorded (PMAC data gathering set up by the scenario's ``setup`` commands,
  Trio SCOPE / TRIGGER): ``<controller>_recording.png``, one panel per source against
  simulated time (``sim/recording.py``).

Every shading, hatch and mark has a legend entry, and the end of the program (the last move
ending) is a dash-dotted line. ``window=(start, end)`` shows only that span of simulated time;
without it each PMAC figure shows the whole run, and a second one (``..._zoom.png``) the first
refill cycles (:data:`ZOOM_REFILLS` host writes), where a host's timing can be seen.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from ...sim.errors import NotFound  # noqa: E402
from .metrics import pmac_traces, trio_traces  # noqa: E402
from .runner import RunResult  # noqa: E402

_SHADE = {"buffer_empty": "tab:red", "lookahead_break": "tab:orange", "axis_blocked": "tab:red",
          "run_time_error": "tab:brown"}
_SHADE_LABEL = {"buffer_empty": "buffer empty (starved)", "lookahead_break": "lookahead stopped",
                "axis_blocked": "axis idle while its process waits",
                "run_time_error": "program aborted (run-time error)"}
_END_STYLE = {"color": "black", "lw": 1, "ls": "-."}
_MAX_POINTS = 20_000
#: Host writes the default zoom covers (the first refill cycles).
ZOOM_REFILLS = 8

Window = tuple[float, float]


def parse_window(text: str) -> Window:
    """``"0.2:0.5"`` → ``(0.2, 0.5)`` seconds; ``":0.5"`` starts at 0.

    Raises:
        ValueError: not ``START:END`` with 0 <= START < END.
    """
    start, sep, end = text.partition(":")
    try:
        if not sep:
            raise ValueError
        a = float(start) if start.strip() else 0.0
        b = float(end)
    except ValueError:
        raise ValueError(f"--window {text!r}: expected START:END in seconds, e.g. 0.2:0.5") \
            from None
    if not (0 <= a < b) or b != b:
        raise ValueError(f"--window {text!r}: need 0 <= START < END")
    return a, b


def zoom_window(host_writes: list[float], t_end: float) -> Window | None:
    """The first :data:`ZOOM_REFILLS` refill cycles: from 0 to the write after them (None when
    the run has no more refills than that — the whole run is the zoom)."""
    if len(host_writes) <= ZOOM_REFILLS:
        return None
    writes = sorted(host_writes)
    end = min(t_end, writes[ZOOM_REFILLS] * 1.1)
    return (0.0, end) if end > 0 else None


def _legend(ax: Any, extra: list[Any]) -> None:
    handles, _ = ax.get_legend_handles_labels()
    ax.legend(handles=[*handles, *extra], loc="upper right", fontsize=8, framealpha=0.9)


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
    window: Window | None = None,
) -> Path:
    c = pmac_traces(events)[cs]
    t0, t1 = window if window is not None else (0.0, max(t_end, 1e-6))
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
    extra: list[Any] = []
    shaded: set[str] = set()
    for s in starvations:
        if s.get("cs") == cs:
            color = _SHADE.get(s["kind"], "grey")
            for ax in (ax1, ax2):
                ax.axvspan(s["start_s"], s["end_s"], color=color, alpha=0.3)
            if s["kind"] not in shaded:
                shaded.add(s["kind"])
                extra.append(Patch(color=color, alpha=0.3,
                                   label=_SHADE_LABEL.get(s["kind"], s["kind"])))
    stopped = False
    for t, label, style in _card_marks(events):
        for ax in (ax1, ax2):
            ax.axvline(t, **style)
            if style["color"] == "tab:red" and t < t_end:  # the card is stopped from here
                ax.axvspan(t, t_end, facecolor="none", edgecolor="gray", hatch="//", lw=0)
                stopped = True
        if t0 <= t <= t1:
            ax1.annotate(label, (t, 0.55), xycoords=("data", "axes fraction"), xytext=(4, 0),
                         textcoords="offset points", fontsize=8, color=style["color"],
                         backgroundcolor="white")  # fmt: skip
        extra.append(Line2D([], [], label=label.rsplit(" ", 2)[0], **style))
    if stopped:
        extra.append(Patch(facecolor="none", edgecolor="gray", hatch="//",
                           label="card stopped (watchdog)"))
    t_last = program_end(events, cs)
    if t_last is not None:
        for ax in (ax1, ax2):
            ax.axvline(t_last, **_END_STYLE)
        extra.append(Line2D([], [], label=f"last move ends {t_last:.3f} s", **_END_STYLE))
    ax1.set_ylabel("lines ahead")
    ax1.set_title(title if window is None else f"{title} ({t0:.3f}-{t1:.3f} s)")
    _legend(ax1, extra)
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
    ax2.set_xlim(t0, t1)
    ax2.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def program_end(events: list[Any], cs: int) -> float | None:
    """When the program of ``cs`` ended: its last move's end, if the program then stopped
    (waiting for lines that never came, quit, aborted) and nothing more was loaded; None while
    it still ran at the end of the run."""
    last_move = None
    state: tuple[float, str] | None = None
    loaded = None
    for e in events:
        f = e.fields
        if f.get("cs") != cs:
            continue
        if e.type == "move_end":
            last_move = e.t
        elif e.type == "program":
            state = (e.t, f.get("state", ""))
        elif e.type == "line_loaded":
            loaded = e.t
    if last_move is None or state is None or state[1] == "running" or state[0] < last_move:
        return None
    if loaded is not None and loaded > state[0]:
        return None
    return last_move


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
    events: list[Any], *, t_end: float, starvations: list[dict[str, Any]], title: str, path: Path,
    window: Window | None = None, moves: dict[int, dict[str, Any]] | None = None,
) -> Path:
    """Per axis the MTYPE lane (one bar per move, from its ``move_start`` to its ``move_end``:
    back-to-back moves stay separate bars), NTYPE and the process buffer; each axis labelled
    with the moves it executed (``moves``: the report's per-axis ``moves_done`` and
    ``moves_planned``), so a run that skipped moves cannot pass for one that made them."""
    axes, _ = trio_traces(events)
    t0, t1 = window if window is not None else (0.0, max(t_end, 1e-6))
    ends = [e.t for e in events if e.type == "move_end"]
    n = max(1, len(axes))
    fig, subs = plt.subplots(n, 1, figsize=(10, 1.6 * n + 1.6), dpi=100, sharex=True,
                             squeeze=False)
    lanes_seen: list[Any] = []
    shaded = False
    for row, (axis, a) in zip(subs[:, 0], sorted(axes.items()), strict=False):
        lanes = [
            ("MTYPE", [(t, m) for t, m, _ in a.states], "tab:blue"),
            ("NTYPE", [(t, nt) for t, _, nt in a.states], "tab:cyan"),
            ("process buffer", a.pbuf, "tab:gray"),
        ]
        for lane, (label, series, color) in enumerate(lanes):
            if lane == 0:
                bars = _move_bars(events, axis, t_end)
                row.broken_barh(bars, (2 - lane - 0.4, 0.8), facecolor=color,
                                edgecolor="white", linewidth=1.5, gid=label)
            else:
                row.broken_barh(_busy_bars(series, t_end), (2 - lane - 0.4, 0.8), color=color,
                                gid=label)
        if not lanes_seen:
            lanes_seen = [Patch(color=color, label=f"{label} occupied")
                          for label, _, color in lanes]
        for s in starvations:
            if s.get("axis") == axis:
                row.axvspan(s["start_s"], s["end_s"], color="tab:red", alpha=0.25)
                shaded = True
        if ends:
            row.axvline(max(ends), **_END_STYLE)
        row.set_yticks([2, 1, 0])
        row.set_yticklabels([lb for lb, _, _ in lanes], fontsize=8)
        row.set_ylim(-0.6, 2.6)
        done, planned = _moves_of(axis, a.moves_done, moves)
        short = planned is not None and done < planned
        row.set_ylabel(f"axis {axis}\n{done}" + (f" of {planned}" if planned is not None else "")
                       + " moves", color="tab:red" if short else "black", fontsize=9)
    extra = list(lanes_seen)
    if shaded:
        extra.append(Patch(color="tab:red", alpha=0.25, label=_SHADE_LABEL["axis_blocked"]))
    if ends:
        extra.append(Line2D([], [], label=f"last move ends {max(ends):.3f} s", **_END_STYLE))
    subs[0, 0].set_title(title if window is None else f"{title} ({t0:.3f}-{t1:.3f} s)")
    if extra:
        fig.legend(handles=extra, loc="lower center", ncol=min(5, len(extra)), fontsize=8)
    subs[-1, 0].set_xlabel("simulated time (s)")
    subs[-1, 0].set_xlim(t0, t1)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.savefig(path)
    plt.close(fig)
    return path


def _moves_of(axis: int, done: int, moves: dict[int, dict[str, Any]] | None
              ) -> tuple[int, int | None]:
    """(moves executed, moves planned or None) for an axis's label."""
    row = (moves or {}).get(axis) or (moves or {}).get(str(axis)) or {}  # type: ignore[call-overload]
    return int(row.get("moves_done", done)), row.get("moves_planned")


def _move_bars(events: list[Any], axis: int, t_end: float) -> list[tuple[float, float]]:
    """One (start, length) per move of ``axis``: its ``move_start`` to its ``move_end``."""
    bars, since = [], None
    for e in events:
        if e.fields.get("axis") != axis:
            continue
        if e.type == "move_start":
            since = e.t
        elif e.type == "move_end" and since is not None:
            bars.append((since, max(e.t - since, 1e-9)))
            since = None
    if since is not None:
        bars.append((since, max(t_end - since, 1e-9)))
    return bars


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


def plot_run(result: RunResult, rep: dict[str, Any], out_dir: Path,
             window: Window | None = None) -> dict[str, Path]:
    """Every plot of a run into ``out_dir``; returns ``{file name: path}``. With ``window``
    each figure shows that span; without, each PMAC figure also gets its ``_zoom`` twin."""
    paths: dict[str, Path] = {}
    scn = result.scenario
    for cid, spec in scn.controllers.items():
        events = result.events(cid)
        starv = [s for s in rep["starvations"] if s["controller"] == cid]
        if spec.kind == "pmac":
            i16, i17 = spec.i16_i17()
            traces = pmac_traces(events)
            for cs in rep["controllers"][cid]["cs"]:
                name = f"{cid}_cs{cs}_lines_ahead"
                common = {"i16": i16, "i17": i17, "t_end": result.t_end, "starvations": starv,
                          "title": f"{scn.name}: {cid} &{cs} rotary buffer"}
                paths[f"{name}.png"] = plot_pmac_cs(
                    events, cs, path=out_dir / f"{name}.png", window=window, **common)
                zoom = None
                if window is None and cs in traces:
                    zoom = zoom_window([t for t, _ in traces[cs].host_writes], result.t_end)
                if zoom is not None:
                    paths[f"{name}_zoom.png"] = plot_pmac_cs(
                        events, cs, path=out_dir / f"{name}_zoom.png", window=zoom, **common)
        else:
            name = f"{cid}_buffers.png"
            paths[name] = plot_trio(
                events, t_end=result.t_end, starvations=starv,
                title=f"{scn.name}: {cid} MTYPE / NTYPE / process buffer", path=out_dir / name,
                window=window, moves=rep["controllers"][cid].get("axes"),
            )  # fmt: skip
        try:
            rec = result.controllers[cid].recording()
        except (NotFound, AttributeError):  # a kind that records nothing
            rec = None
        if rec is not None and rec.cycles:
            name = f"{cid}_recording.png"
            paths[name] = plot_recording(rec, f"{scn.name}: {cid} {rec.kind}", out_dir / name,
                                         window)
    return paths


def plot_recording(rec: Any, title: str, path: Path, window: Window | None = None) -> Path:
    """What a controller recorded (``sim.recording.Recording``): one panel per source, its
    samples against simulated time (every sample at ``cycle × servo period``)."""
    times = rec.times()
    n = len(rec.names)
    fig, axes = plt.subplots(n, 1, figsize=(10, 1.8 + 1.6 * n), sharex=True, squeeze=False)
    step = max(1, len(times) // _MAX_POINTS)
    for ax, name, column in zip(axes[:, 0], rec.names, rec.columns, strict=True):
        ax.plot(times[::step], column[::step], lw=1, label=name)
        ax.set_ylabel(name, fontsize=8)
        ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
        if window is not None:
            ax.set_xlim(*window)
    axes[-1, 0].set_xlabel("simulated time (s)")
    every = f"every {rec.period_cycles} servo cycle(s)" if rec.period_cycles else "single shot"
    axes[0, 0].set_title(f"{title} ({len(times)} samples, {every})")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


__all__ = ["ZOOM_REFILLS", "Window", "parse_window", "plot_pmac_cs", "plot_recording",
           "plot_run", "plot_trio", "program_end", "zoom_window"]
