"""Running a scenario in virtual time.

Builds the controllers (each with its own ``simpy.Environment``), sets them up at t = 0
(variables, rotary buffers from the highest CS down as the manual requires, PMAC PLC programs
and their enables, Trio axes and programs, terminal commands), starts the host models, the
processor-load sampler (``cpu_sample`` events) and faults, and runs until
``duration_s`` — or until the ``stop_event`` is logged by any controller, the controllers then
kept in lock-step so they all stop at that instant.

Each host draws from its own ``random.Random`` seeded from the scenario seed and the host's
name, so adding a host does not change the others' draws, and the same seed gives the same
event log byte for byte.
"""

from __future__ import annotations

import contextlib
import functools
import json
import random
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from ...sim.controller import Controller
from ...sim.errors import Halted, MotionSimError
from ...sim.events import Event
from ..faults import faults_of
from .model import (
    BreqInterruptSpec,
    HostStallFault,
    InjectFault,
    NaiveSpec,
    PrPollingSpec,
    Scenario,
    SetVariableFault,
    TerminalFault,
    TrioFeederSpec,
)


@functools.lru_cache(maxsize=8)
def controller_class(kind: str) -> type[Controller]:
    """The kind's class: the plug-in registry, else the core package itself."""
    from ..kinds import kind_class

    try:
        return kind_class(kind)
    except MotionSimError:
        if kind == "pmac":
            from ...sim.pmac import PmacController

            return PmacController
        if kind == "trio":
            from ...sim.trio import TrioController

            return TrioController
        raise


def host_rng(seed: int, name: str) -> random.Random:
    """A host's own generator: a function of the scenario seed and the host's name only."""
    return random.Random(f"motionsim:{seed}:{name}")


@dataclass
class RunResult:
    """A finished run: the controllers (with their logs), the hosts, the end time."""

    scenario: Scenario
    controllers: dict[str, Controller]
    hosts: dict[str, Any]
    t_end: float
    wall_s: float
    stopped_by: str = "duration"
    _events: dict[str, list[Event]] = field(default_factory=dict)

    def events_lost(self, controller: str) -> int:
        """Events that left the log's ring before the metrics read it (raise log_capacity)."""
        return self.controllers[controller].log.first_seq - 1

    def events(self, controller: str) -> list[Event]:
        if controller not in self._events:
            self._events[controller] = self.controllers[controller].log.events()
        return self._events[controller]

    def to_jsonl(self) -> str:
        """Every controller's events as JSON Lines, ordered by (t, controller, seq)."""
        return events_jsonl(list(self.controllers), self.events)

    def total_lines(self, controller: str, cs: int) -> int | None:
        """Lines the hosts had to send to ``controller`` / ``&cs`` (None: no host feeds it)."""
        total = None
        for h in self.hosts.values():
            if getattr(h, "controller", None) is self.controllers[controller] and getattr(
                h, "cs", None
            ) == cs:
                total = (total or 0) + len(h.lines)
        return total


def events_jsonl(controllers: list[str], events: Callable[[str], list[Event]]) -> str:
    """The events of ``controllers`` as JSON Lines, ordered by (t, controller, seq): the
    ``events.jsonl`` of a virtual and of a realtime run alike."""
    rows = []
    for ci, cid in enumerate(controllers):
        for e in events(cid):
            rows.append((e.t, ci, e.seq, e.to_dict(cid)))
    rows.sort(key=lambda r: (r[0], r[1], r[2]))
    return "".join(json.dumps(r[3], separators=(",", ":")) + "\n" for r in rows)


def _log_capacity(scn: Scenario) -> int:
    if scn.log_capacity is not None:
        return scn.log_capacity
    lines = 0
    for h in scn.hosts:
        if isinstance(h, TrioFeederSpec):
            lines += h.moves.count()
        else:
            lines += h.program.count()
    return min(50_000_000, max(200_000, 12 * lines + 100_000))


def build(scn: Scenario) -> tuple[dict[str, Controller], dict[str, Any]]:
    """Controllers set up at t = 0 and hosts started; errors name the scenario field."""
    from ...sim.hosts import (
        BlindFeeder,
        BreqInterruptHost,
        CpuMonitor,
        MovesBufferedFeeder,
        NaiveHost,
        NtypeFeeder,
        PrPollingHost,
    )

    controllers: dict[str, Controller] = {}
    cap = _log_capacity(scn)
    for cid, spec in scn.controllers.items():
        cls = controller_class(spec.kind)
        path: tuple[Any, ...] = ("controllers", cid, "config")
        try:
            try:
                ctl = cls(cid, spec.config, log_capacity=cap)
            except TypeError:
                ctl = cls(cid, spec.config)
            path = ("controllers", cid, "variables")
            for name, value in spec.variables.items():
                path = ("controllers", cid, "variables", name)
                ctl.set_variable(name, value)
            for i, rot in sorted(enumerate(spec.rotary), key=lambda p: -p[1].cs):
                path = ("controllers", cid, "rotary", i)
                ctl.define_rotary(rot.cs, rot.size_words)  # type: ignore[attr-defined]
            for i, plc in enumerate(spec.plcs):
                path = ("controllers", cid, "plcs", i)
                ctl.plcs.load(plc.plc, plc.text or "")  # type: ignore[attr-defined]
                if plc.enabled_at_start:
                    ctl.plcs.set_enabled((plc.plc,), True)  # type: ignore[attr-defined]
                elif plc.enable_at_ms is not None:
                    _at(ctl.env, plc.enable_at_ms / 1000,
                        _command(ctl, f"ENABLE PLC {plc.plc}"))  # fmt: skip
            for axis, params in spec.axes.items():
                path = ("controllers", cid, "axes", axis)
                ctl.set_axis(axis, **params)  # type: ignore[attr-defined]
            for name, text in spec.programs.items():
                path = ("controllers", cid, "programs", name)
                ctl.store_program(name, text)  # type: ignore[attr-defined]
            for i, run in enumerate(spec.run):
                path = ("controllers", cid, "run", i)
                ctl.run_program(run.program, process=run.process)  # type: ignore[attr-defined]
            for i, cmd in enumerate(spec.setup):
                path = ("controllers", cid, "setup", i)
                reply = ctl.terminal(cmd)
                if reply.done and reply.error:
                    raise MotionSimError(f"{cmd!r} answered {reply.error}")
        except MotionSimError as exc:
            err = scn.error_at(path, f"{exc.message}")
            err.details.update({k: v for k, v in exc.details.items() if k not in err.details})
            raise err from None
        controllers[cid] = ctl

    for cid, spec in scn.controllers.items():
        period = spec.sample_period_s() if spec.kind == "pmac" else None
        if period is not None:
            CpuMonitor(controllers[cid], period).start()

    hosts: dict[str, Any] = {}
    for i, (name, h) in enumerate(zip(scn.host_names(), scn.hosts, strict=True)):
        ctl = controllers[scn.host_controller(i)]
        rng = host_rng(scn.seed, name)
        if isinstance(h, TrioFeederSpec):
            cls_t = {
                "trio_blind": BlindFeeder,
                "trio_ntype": NtypeFeeder,
                "trio_moves_buffered": MovesBufferedFeeder,
            }[h.type]
            extra = {"max_buffered": h.max_buffered} if h.type == "trio_moves_buffered" else {}
            host: Any = cls_t(
                name,
                ctl,
                h.moves.to_moves(),
                process=h.process,
                poll_period_s=h.poll_period_ms / 1000,
                **extra,
            )
        else:
            common = {
                "write_latency": h.write_latency.to_delay(),
                "start_program": h.start_program,
                "write_via": h.write_via,
                "reply_timeout_s": h.reply_timeout_ms / 1000,
            }
            lines = h.program.to_lines()
            if isinstance(h, PrPollingSpec):
                host = PrPollingHost(
                    name, ctl, h.cs, lines, rng,
                    poll_period_s=h.poll_period_ms / 1000,
                    pr_latency=h.pr_latency.to_delay(),
                    lines_per_write=h.lines_per_write,
                    high_water=h.high_water,
                    low_water=h.low_water,
                    via_terminal=h.pr_via == "terminal",
                    **common,
                )  # fmt: skip
            elif isinstance(h, BreqInterruptSpec):
                host = BreqInterruptHost(
                    name, ctl, h.cs, lines, rng,
                    latency=h.latency.to_delay(),
                    lines_per_interrupt=h.lines_per_interrupt,
                    recheck_breq=h.recheck_breq,
                    prefill=h.prefill,
                    **common,
                )  # fmt: skip
            else:
                assert isinstance(h, NaiveSpec)
                host = NaiveHost(
                    name, ctl, h.cs, lines, rng, lines_per_write=h.lines_per_write, **common
                )
        hosts[name] = host
        host.start()

    for f in scn.faults:
        if isinstance(f, HostStallFault):
            host = hosts[f.host]
            _at(host.env, f.at_ms / 1000, _stall(host, (f.at_ms + f.duration_ms) / 1000))
        else:
            ctl = controllers[f.controller or next(iter(controllers))]
            if isinstance(f, TerminalFault):
                _at(ctl.env, f.at_ms / 1000, _command(ctl, f.command))
            elif isinstance(f, InjectFault):
                _at(ctl.env, f.at_ms / 1000, _quiet(faults_of(ctl).add, f.fault))
            else:
                assert isinstance(f, SetVariableFault)
                _at(ctl.env, f.at_ms / 1000, _quiet(ctl.set_variable, f.name, f.value))
    return controllers, hosts


def _command(ctl: Controller, text: str) -> Callable[[], Any]:
    """Send ``text`` to the terminal then; a card whose watchdog tripped answers nothing."""
    return _quiet(ctl.terminal, text)


def _quiet(fn: Callable[..., Any], *args: Any) -> Callable[[], Any]:
    """``fn(*args)`` then, ignoring a card whose watchdog tripped (it refuses everything)."""

    def call() -> None:
        with contextlib.suppress(Halted):
            fn(*args)

    return call


def _stall(host: Any, until: float) -> Callable[[], Any]:
    return lambda: host.stall(until)


def _at(env: Any, t: float, fn: Callable[[], Any]) -> None:
    def proc() -> Any:
        if t > env.now:
            yield env.timeout(t - env.now)
        fn()

    env.process(proc())


#: How many slices a run reports progress in (``progress`` callback of :func:`run`).
PROGRESS_SLICES = 200


def run(scn: Scenario, progress: Callable[[float, float], None] | None = None) -> RunResult:
    """Build and run ``scn`` in virtual time.

    ``progress(t, duration_s)`` is called as simulated time passes (a run without a stop
    event then goes forward in :data:`PROGRESS_SLICES` slices; every controller's events are
    processed in the same order either way, each controller being its own simulation).
    """
    wall0 = time.perf_counter()
    controllers, hosts = build(scn)
    until = float(scn.duration_s)
    stopped_by = "duration"
    if scn.stop_event is None:
        steps = PROGRESS_SLICES if progress is not None else 1
        for i in range(1, steps + 1):
            t = until if i == steps else until * i / steps
            for ctl in controllers.values():
                if ctl.env.now < t:
                    ctl.env.run(until=t)
            if progress is not None:
                progress(t, until)
        t_end = until
    else:
        pattern = dict(scn.stop_event)
        hit: list[tuple[str, float]] = []

        def watcher(cid: str) -> Callable[[Event], None]:
            def on(e: Event) -> None:
                if not hit and e.matches(pattern):
                    hit.append((cid, e.t))

            return on

        for cid, ctl in controllers.items():
            ctl.log.listen(watcher(cid))
        envs = [c.env for c in controllers.values()]
        report_every = until / PROGRESS_SLICES
        next_report = report_every
        while not hit:
            env = min(envs, key=lambda e: e.peek())
            if env.peek() > until:
                break
            env.step()
            if progress is not None and env.now >= next_report:
                progress(env.now, until)
                next_report = env.now + report_every
        t_end = hit[0][1] if hit else until
        if hit:
            stopped_by = f"stop_event on {hit[0][0]}"
        for env in envs:
            if env.now < t_end:
                env.run(until=t_end)
    return RunResult(scn, controllers, hosts, t_end, time.perf_counter() - wall0, stopped_by)


__all__ = ["PROGRESS_SLICES", "RunResult", "build", "controller_class", "host_rng", "run"]
