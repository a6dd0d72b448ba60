"""``motionsim run --realtime``: play a scenario on a running server in wall-clock time.

The controllers are created on the server with a realtime clock (``factor`` simulated seconds
per wall second) and set up through the REST API; the host models then run *here*, as the
user's host software would, over HTTP: a PR-polling host reads ``lines_ahead``, a BREQ host
polls the ``breq`` flag (it cannot take a PC interrupt over HTTP), the naive host posts back
to back, Trio feeders post moves (``?wait=true`` for the blind one). PMAC PLC programs are
stored (``PUT /plcs/{n}``) and those enabled at t = 0 enabled; ``enable_at_ms``, faults and
host latency distributions other than the poll period are not replayed: the network and the
server supply their own. PMAC writers post their lines to the rotary endpoint whatever their
``write_via`` (the REST batch write; a command line per program line is not replayed). At the
end the server's event logs are fetched and the same metrics and summary as a virtual run are
printed.
"""

from __future__ import annotations

import contextlib
import time
from typing import Any

from ...sim.events import Event
from .errors import ScenarioError
from .model import (
    BreqInterruptSpec,
    NaiveSpec,
    PrPollingSpec,
    Scenario,
    TrioFeederSpec,
)


class _Host:
    def __init__(self, client: Any, cid: str, spec: Any, factor: float) -> None:
        self.c, self.cid, self.spec, self.factor = client, cid, spec, factor
        self.next_t = 0.0
        self.done = False

    def wall(self, sim_s: float) -> float:
        return sim_s / self.factor


class _PmacHost(_Host):
    def __init__(self, *a: Any) -> None:
        super().__init__(*a)
        self.lines = self.spec.program.to_lines()
        self.sent = 0
        self.started = False

    def post(self, n: int) -> Any:
        from ..client import MotionSimHTTPError

        batch = self.lines[self.sent : self.sent + n]
        try:
            res = self.c.load_lines(self.cid, self.spec.cs, batch, first_seq=self.sent + 1)
        except MotionSimHTTPError as exc:
            if exc.status == 409:
                return None
            raise
        self.sent += len(batch)
        if not self.started and self.spec.start_program:
            self.started = True
            self.c.run(self.cid, self.spec.cs)
        self.done = self.sent >= len(self.lines)
        return res

    def step(self, now: float) -> None:
        s = self.spec
        if isinstance(s, PrPollingSpec):
            ahead = self.c.coord(self.cid, s.cs)["rotary"]["lines_ahead"]
            if ahead <= s.low_water:
                while not self.done and ahead < s.high_water:
                    res = self.post(min(s.lines_per_write, s.high_water - ahead))
                    if res is None:
                        break
                    ahead = res.lines_ahead
            self.next_t = now + self.wall(s.poll_period_ms / 1000)
        elif isinstance(s, BreqInterruptSpec):
            rot = self.c.coord(self.cid, s.cs)["rotary"]
            if rot["breq"] or not self.started:
                while not self.done:
                    res = self.post(s.lines_per_interrupt)
                    if res is None or not s.recheck_breq or not res.breq:
                        break
            self.next_t = now + self.wall(max(s.latency.to_delay().upper_s, 0.001))
        else:
            assert isinstance(s, NaiveSpec)
            res = self.post(s.lines_per_write)
            self.next_t = now + (0.001 if res is None else 0.0)


class _TrioHost(_Host):
    def __init__(self, *a: Any) -> None:
        super().__init__(*a)
        self.moves = self.spec.moves.to_moves()
        self.i = 0

    def step(self, now: float) -> None:
        s = self.spec
        m = self.moves[self.i]
        if s.type == "trio_blind":
            self.c.move(self.cid, m.axis, m.type, m.args, process=s.process, wait=True)
            self.i += 1
        else:
            ax = self.c.axis(self.cid, m.axis)
            busy = ax["ntype"] != 0 if s.type == "trio_ntype" else (
                int(ax["mtype"] != 0) + int(ax["ntype"] != 0) >= s.max_buffered
            )
            if not busy:
                self.c.move(self.cid, m.axis, m.type, m.args, process=s.process)
                self.i += 1
            self.next_t = now + self.wall(s.poll_period_ms / 1000)
        self.done = self.i >= len(self.moves)


def play(scn: Scenario, server: str, *, factor: float = 1.0, echo: Any = print) -> dict[str, Any]:
    """Create the scenario's controllers on ``server`` and feed them in wall-clock time."""
    from ..client import MotionSimClient, MotionSimHTTPError
    from .report import (
        headline,
        pmac_report,
        summarise_starvations,
        trio_report,
    )
    from .summary import print_summary

    if factor <= 0:
        raise ScenarioError("--factor must be > 0")
    with MotionSimClient(server) as c:
        try:
            for cid, spec in scn.controllers.items():
                with contextlib.suppress(MotionSimHTTPError):
                    c.delete_controller(cid)
                c.create_controller(spec.kind, id=cid, clock="realtime", factor=factor,
                                    config=spec.config)  # fmt: skip
                for name, value in spec.variables.items():
                    c.set_variable(cid, name, value)
                for rot in sorted(spec.rotary, key=lambda r: -r.cs):
                    c.define_rotary(cid, rot.cs, rot.size_words)
                for plc in spec.plcs:
                    base = f"/controllers/{cid}/plcs/{plc.plc}"
                    c.request("PUT", base, json={"text": plc.text or ""})
                    if plc.enabled_at_start:
                        c.request("POST", base + "/enable")
                for axis, params in spec.axes.items():
                    c.set_axis(cid, axis, **params)
                for name, text in spec.programs.items():
                    c.store_program(cid, name, text)
                for run in spec.run:
                    c.run_program(cid, run.program, run.process)
                for cmd in spec.setup:
                    c.terminal(cid, cmd)
            hosts: list[_Host] = []
            for i, h in enumerate(scn.hosts):
                cid = scn.host_controller(i)
                cls = _TrioHost if isinstance(h, TrioFeederSpec) else _PmacHost
                hosts.append(cls(c, cid, h, factor))
            t0 = time.monotonic()
            end = scn.duration_s / factor
            while True:
                now = time.monotonic() - t0
                if now >= end:
                    break
                live = [h for h in hosts if not h.done]
                due = [h for h in live if h.next_t <= now]
                for h in due:
                    h.step(now)
                if not due:
                    nxt = min((h.next_t for h in live), default=end)
                    time.sleep(max(0.0, min(nxt, end) - now))
            per: dict[str, Any] = {}
            episodes = []
            for cid, spec in scn.controllers.items():
                evs = [
                    Event(e["seq"], e["t"], e["type"],
                          {k: v for k, v in e.items() if k not in ("seq", "t", "type",
                                                                   "controller")})
                    for e in c.all_events(cid)
                ]  # fmt: skip
                t_end = c.clock(cid).t
                if spec.kind == "pmac":
                    i16, _ = spec.i16_i17()
                    r = pmac_report(evs, t_end, controller=cid, i16=i16)
                else:
                    r = trio_report(evs, t_end, controller=cid)
                episodes += r.pop("starvation_list")
                per[cid] = r
        except MotionSimHTTPError as exc:
            raise ScenarioError(f"server {server}: {exc}") from None
    rep = {
        "scenario": scn.name,
        "seed": scn.seed,
        "t_end_s": scn.duration_s,
        "stopped_by": "realtime",
        "controllers": per,
        "starvations": [s.to_dict() for s in sorted(episodes, key=lambda s: s.start)],
        "starvation_summary": summarise_starvations(sorted(episodes, key=lambda s: s.start)),
        "headline": headline(per),
    }
    print_summary(rep)
    echo(f"played {scn.name} on {server} at factor {factor}")
    return rep


__all__ = ["play"]
