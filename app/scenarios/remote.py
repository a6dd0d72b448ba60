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
printed; the CLI writes the same files as a virtual run from them (:class:`RemoteRun`).

The server's controllers are the user's: a scenario controller ``c`` is created as
``{prefix}c`` (the prefix defaults to the scenario's name, :func:`server_ids`), and a server
controller of that id is replaced only when ``replace`` is given — otherwise the run is
refused before anything is created, naming it. A server that cannot be reached is one
line (:class:`~.errors.ScenarioError`), not a traceback.
"""

from __future__ import annotations

import contextlib
import re
import time
from dataclasses import dataclass, field
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

#: A server controller id (API.md: ``^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$``).
_ID_CHARS = re.compile(r"[^A-Za-z0-9_.-]")
_ID_MAX = 64


def default_prefix(scn: Scenario) -> str:
    """``{scenario name}-`` with the characters an id may not hold made ``-``."""
    return _ID_CHARS.sub("-", scn.name) + "-"


def server_ids(scn: Scenario, prefix: str) -> dict[str, str]:
    """The server id of each scenario controller: ``{prefix}{id}``.

    Raises:
        ScenarioError: an id the API would refuse (empty, too long, a bad character).
    """
    out = {}
    for cid in scn.controllers:
        sid = prefix + cid
        if not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", sid) or len(sid) > _ID_MAX:
            raise ScenarioError(
                f"--id-prefix {prefix!r}: {sid!r} is not a controller id (a letter or digit, "
                f"then letters, digits, '_', '.', '-'; at most {_ID_MAX} characters)")
        out[cid] = sid
    return out


@dataclass
class RemoteRun:
    """What a realtime run leaves for the output files: the scenario, the events fetched
    from the server per scenario controller, the simulated end time. It answers what
    :func:`.outputs.write_outputs` and the plots read of a virtual
    :class:`~.runner.RunResult`."""

    scenario: Scenario
    t_end: float
    logs: dict[str, list[Event]] = field(default_factory=dict)

    def events(self, controller: str) -> list[Event]:
        return self.logs[controller]

    def to_jsonl(self) -> str:
        from .runner import events_jsonl

        return events_jsonl(list(self.logs), self.events)


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


def play(scn: Scenario, server: str, *, factor: float = 1.0, echo: Any = print,
         prefix: str | None = None, replace: bool = False,
         progress: Any = None) -> tuple[dict[str, Any], RemoteRun]:
    """Create the scenario's controllers on ``server`` (as ``{prefix}{id}``) and feed them in
    wall-clock time; the report and the run (events fetched from the server).

    Raises:
        ScenarioError: the server cannot be reached or refuses; a controller of one of the
        ids exists there and ``replace`` is not given (nothing was created then).
    """
    import httpx

    try:
        return _play(scn, server, factor=factor, echo=echo,
                     prefix=default_prefix(scn) if prefix is None else prefix,
                     replace=replace, progress=progress)
    except httpx.TransportError as exc:
        raise ScenarioError(f"cannot reach the server at {server} ({exc}); start one with "
                            "`motionsim serve` or give --server URL") from None


def _play(scn: Scenario, server: str, *, factor: float, echo: Any, prefix: str,
          replace: bool, progress: Any) -> tuple[dict[str, Any], RemoteRun]:
    from ..client import MotionSimClient, MotionSimHTTPError
    from .report import (
        headline,
        pmac_report,
        summarise_starvations,
        trio_report,
    )
    if factor <= 0:
        raise ScenarioError("--factor must be > 0")
    ids = server_ids(scn, prefix)
    run = RemoteRun(scn, scn.duration_s)
    with MotionSimClient(server) as c:
        try:
            present = {x["id"] for x in c.controllers()}
            taken = [ids[cid] for cid in scn.controllers if ids[cid] in present]
            if taken and not replace:
                raise ScenarioError(
                    f"server {server} already has controller(s) {', '.join(taken)}: "
                    "--replace to delete and re-create them (their programs and variables "
                    "are lost), or --id-prefix for other ids")
            for scid, spec in scn.controllers.items():
                cid = ids[scid]
                if cid in present:
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
                cid = ids[scn.host_controller(i)]
                cls = _TrioHost if isinstance(h, TrioFeederSpec) else _PmacHost
                hosts.append(cls(c, cid, h, factor))
            t0 = time.monotonic()
            end = scn.duration_s / factor
            while True:
                now = time.monotonic() - t0
                if progress is not None:
                    progress(min(now, end) * factor, scn.duration_s)
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
            for scid, spec in scn.controllers.items():
                cid = ids[scid]
                evs = [
                    Event(e["seq"], e["t"], e["type"],
                          {k: v for k, v in e.items() if k not in ("seq", "t", "type",
                                                                   "controller")})
                    for e in c.all_events(cid)
                ]  # fmt: skip
                t_end = c.clock(cid).t
                run.logs[scid] = evs
                run.t_end = max(run.t_end, t_end)
                if spec.kind == "pmac":
                    i16, _ = spec.i16_i17()
                    r = pmac_report(evs, t_end, controller=scid, i16=i16)
                else:
                    r = trio_report(evs, t_end, controller=scid)
                r["server_id"] = cid
                episodes += r.pop("starvation_list")
                per[scid] = r
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
    echo(f"played {scn.name} on {server} at factor {factor} as "
         + ", ".join(ids[cid] for cid in scn.controllers))
    return rep, run


__all__ = ["RemoteRun", "default_prefix", "play", "server_ids"]
