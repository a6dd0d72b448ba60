"""The performance targets ``make bench`` reports against: each a ratio to a reference
measured in the same run (or, where the issue names one, an absolute bound), read from
``bench/results/<file>.json`` under ``"ratios"``."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Target:
    file: str  # bench/results/<file>.json
    key: str  # its "ratios" entry
    text: str  # what is compared with what
    op: str  # ">=" or "<="
    value: float

    def met(self, ratio: float) -> bool:
        return ratio >= self.value if self.op == ">=" else ratio <= self.value


TARGETS: tuple[Target, ...] = (
    Target("pmac_stream", "core", "PMAC rotary stream in the core / bare SimPy loop", ">=", 0.5),
    Target("pmac_stream", "memory_growth", "PMAC stream RSS growth 1e5 -> 1e6 lines", "<=", 0.05),
    Target("pmac_stream", "pvt_vs_linear", "PVT stream / LINEAR stream lines/s", ">=", 0.8),
    Target("rest_stream", "batches_500", "PMAC stream over REST (batches of 500) / bare loop",
           ">=", 0.25),
    Target("rest_stream", "one_line_p99", "1-line POST p99 / bare FastAPI POST p99", "<=", 2.0),
    Target("parse", "program_lines", "PMAC program lines -> statements / bare regex tokens",
           ">=", 0.4),
    Target("trio", "ratio", "Trio 4-axis BASIC stream / its bare SimPy reference", ">=", 0.2),
    Target("trio_include", "compile_ms",
           "Trio 1 000-line program with 20 INCLUDEs stored and compiled (ms, absolute)", "<=",
           50.0),
    Target("check", "ms_per_file",
           "motionsim check DIR, 200 mixed PMAC / Trio files in one process (ms per file, "
           "absolute)", "<=", 500.0),
    Target("trio_library", "compile_ms",
           "Trio 1 000-line program calling a 20-function BASIC library, compiled (ms, absolute)",
           "<=", 50.0),
    Target("websocket", "p99_100x250", "WS p99, 100 subscribers x 250 ev/s / bare broadcaster",
           "<=", 2.0),
    Target("websocket", "p99_10x1000", "WS p99, 10 subscribers x 1000 ev/s / bare broadcaster",
           "<=", 1.5),
    Target("realtime_lateness", "lateness_p99",
           "realtime clock lateness p99 under load / bare stepping", "<=", 2.0),
    Target("realtime", "drift_s_10min",
           "factor-1 clock, service loaded: cumulative drift / 10 sim. min (s)", "<=", 0.01),
    Target("realtime", "health_p99_ms_factor10_plc", "/health p99 at factor 10 with a PLC (ms)",
           "<=", 50.0),
    Target("pmacanalyse", "full_read_s", "dls-pmacanalyse full read of the card, realtime (s)",
           "<=", 5.0),
    Target("wire", "getresponse", "PMAC Ethernet GETRESPONSE round trips / bare echo server",
           ">=", 0.7),
    Target("many_controllers", "aggregate_vs_alone",
           "one service, 100 PMACs streaming at once: aggregate lines/s / one controller alone",
           ">=", 0.8),
    Target("many_controllers", "slowest_vs_fastest",
           "100 PMACs streaming at once: slowest controller's lines/s / the fastest's", ">=",
           0.8),
    Target("pmac_kinematics", "kinematic_vs_plain",
           "10 000-segment PROG: kinematic CS / plain CS simulated s per wall s", ">=", 0.3),
    Target("pmac_poll", "poll_ms",
           "EPICS driver poll, 8 motors + 2 CS over PMAC Ethernet, factor 1: median ms", "<=",
           5.0),
    Target("pmac_gather", "gather_vs_plain",
           "PMAC stream with 8 sources gathered every servo cycle / the same stream (wall)",
           "<=", 2.0),
    Target("sweep", "speedup_2_workers", "64 scenario runs: 2 local workers vs 1 (speed-up)",
           ">=", 1.8),
    Target("dashboard", "fps_1000", "dashboard frames/s at 1000 events/s (absolute; ~30)",
           "<=", 31.0),
    Target("dashboard", "delivered_1000", "dashboard events applied / logged at 1000 events/s",
           ">=", 1.0),
    Target("idle_memory", "mb_per_idle_pmac",
           "memory per idle PMAC controller, 500 on one service (MB, absolute)", "<=", 0.25),
    Target("idle_memory", "mb_per_idle_trio",
           "memory per idle Trio controller, 500 on one service (MB, absolute)", "<=", 0.25),
    Target("attacks", "health_p99_ms_worst_attack",
           "/health p99 during the worst of issue 23's attacks (ms, absolute)", "<=", 50.0),
)
