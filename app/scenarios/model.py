"""Scenario files: what to simulate, validated before anything runs.

A scenario names the controllers and their configuration, what each host sends (a program:
inline lines, a file, or a generator such as "N linear moves of T ms on 4 axes"), the host
strategies with their latency distributions, faults, how long to run (or an event to stop on)
and the seed. Times in the file are milliseconds (``*_ms``) except ``duration_s``.

Everything is checked up front: unknown fields, wrong types and impossible values (a negative
latency, I16 above I17) are :class:`~motionsim.app.scenarios.errors.ScenarioError`s naming the
field and the line of the file, and nothing runs.

Assumption (manual silent): I16 > I17 is refused. BREQ is set again below I16 lines ahead and
held low from I17 up, so an I16 above I17 would re-raise BREQ while the buffer is "full".
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from ..faults import FaultSpec as InjectedFaultSpec
from .errors import ScenarioError, dotted
from .source import load_yaml, locate, read_text, value_line

NonNeg = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Pos = Annotated[float, Field(gt=0, allow_inf_nan=False)]

#: Default I16 / I17 of a Turbo PMAC (lines ahead; spec/pmac.md §1.2).
PMAC_DEFAULTS = {"i16": 5, "i17": 10}


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


# -- delays --------------------------------------------------------------------------------


class DelaySpec(Strict):
    """A latency distribution in ms: ``2`` (fixed), or ``{dist: normal, mean_ms: 2, sd_ms: 1}``.

    ``dist``: ``fixed`` (``ms``), ``uniform`` (``low_ms``, ``high_ms``), ``normal`` (``mean_ms``,
    ``sd_ms``; draws below 0 become 0), ``lognormal`` (``median_ms``, ``sigma``), ``empirical``
    (``samples_ms`` or ``file``: one value in ms per line, or the first column of a CSV).
    ``jitter_ms`` adds a uniform ±jitter to any of them.
    """

    dist: Literal["fixed", "uniform", "normal", "lognormal", "empirical"] = "fixed"
    ms: NonNeg | None = None
    low_ms: NonNeg | None = None
    high_ms: NonNeg | None = None
    mean_ms: NonNeg | None = None
    sd_ms: NonNeg | None = None
    median_ms: Pos | None = None
    sigma: NonNeg | None = None
    samples_ms: list[NonNeg] | None = None
    file: str | None = None
    jitter_ms: NonNeg = 0.0

    @model_validator(mode="before")
    @classmethod
    def _number_is_fixed(cls, v: Any) -> Any:
        if isinstance(v, int | float) and not isinstance(v, bool):
            return {"dist": "fixed", "ms": v}
        return v

    @model_validator(mode="after")
    def _fields_fit_dist(self, info: ValidationInfo) -> DelaySpec:
        need = {
            "fixed": ("ms",),
            "uniform": ("low_ms", "high_ms"),
            "normal": ("mean_ms", "sd_ms"),
            "lognormal": ("median_ms", "sigma"),
            "empirical": (),
        }[self.dist]
        allowed = set(need) | {"dist", "jitter_ms"}
        if self.dist == "empirical":
            allowed |= {"samples_ms", "file"}
        for name in need:
            if getattr(self, name) is None:
                raise ValueError(f"dist {self.dist!r} needs {name}")
        extra = [n for n in self.model_fields_set if n not in allowed]
        if extra:
            raise ValueError(f"{', '.join(sorted(extra))} not used by dist {self.dist!r}")
        if self.dist == "uniform" and self.high_ms < self.low_ms:  # type: ignore[operator]
            raise ValueError("high_ms must be >= low_ms")
        if self.dist == "empirical":
            if (self.samples_ms is None) == (self.file is None):
                raise ValueError("empirical needs exactly one of samples_ms, file")
            if self.file is not None:
                base = (info.context or {}).get("base_dir")
                samples = _read_samples(self.file, base)
                object.__setattr__(self, "samples_ms", samples)
        return self

    def to_delay(self) -> Any:
        """The :class:`motionsim.sim.hosts.Delay` (seconds) this spec describes."""
        from ...sim.hosts.distributions import Delay

        ms = 1e-3
        j = self.jitter_ms * ms
        if self.dist == "fixed":
            return Delay("fixed", self.ms * ms, jitter_s=j)  # type: ignore[operator]
        if self.dist == "uniform":
            return Delay("uniform", self.low_ms * ms, self.high_ms * ms, jitter_s=j)  # type: ignore[operator]
        if self.dist == "normal":
            return Delay("normal", self.mean_ms * ms, self.sd_ms * ms, jitter_s=j)  # type: ignore[operator]
        if self.dist == "lognormal":
            return Delay("lognormal", self.median_ms * ms, self.sigma, jitter_s=j)  # type: ignore[operator]
        return Delay("empirical", values=tuple(v * ms for v in self.samples_ms or ()), jitter_s=j)


def _read_file(what: str, name: str, base_dir: Path | None) -> tuple[str, Path]:
    """A file the scenario names (relative to the scenario's folder); unreadable is a
    ``ValueError`` saying which ``what`` file and why."""
    try:
        return read_text(name, base_dir)
    except OSError as exc:
        raise ValueError(f"cannot read {what} file {name!r}: {exc.strerror}") from None


def _read_samples(name: str, base_dir: Path | None) -> list[float]:
    text, path = _read_file("samples", name, base_dir)
    out: list[float] = []
    for i, raw in enumerate(text.splitlines(), 1):
        cell = raw.split(",")[0].strip()
        if not cell or cell.startswith("#"):
            continue
        try:
            v = float(cell)
        except ValueError:
            if not out:  # a CSV header
                continue
            raise ValueError(f"{path.name} line {i}: {cell!r} is not a number") from None
        if not v >= 0:
            raise ValueError(f"{path.name} line {i}: latency {v} must be >= 0")
        out.append(v)
    if not out:
        raise ValueError(f"{path.name}: no samples")
    return out


# -- programs ------------------------------------------------------------------------------

_AXES = "XYZABCUVW"


class GenerateSpec(Strict):
    """``moves`` LINEAR moves of ``move_ms`` each on ``axes`` axes (X Y Z A ...), ``step`` apart.

    The program starts with ``header`` (default ``LINEAR``, ``ABS``, ``TA{move_ms}``, ``TS0``,
    ``TM{move_ms}`` — TA no longer than TM, so each move takes TM).
    """

    moves: int = Field(ge=1, le=10_000_000)
    move_ms: Pos
    axes: int = Field(4, ge=1, le=len(_AXES))
    step: float = 1.0
    header: list[str] | None = None

    def lines(self) -> list[str]:
        t = _num(self.move_ms)
        head = self.header if self.header is not None else [
            "LINEAR", "ABS", f"TA{t}", "TS0", f"TM{t}"
        ]
        letters = _AXES[: self.axes]
        step = self.step
        if float(step).is_integer():
            istep = int(step)
            values = [str((k + 1) * istep) for k in range(self.moves)]
        else:
            values = [_num((k + 1) * step) for k in range(self.moves)]
        fmt = " ".join(f"{a}{{0}}" for a in letters)
        return [*head, *(fmt.format(v) for v in values)]

    def count(self) -> int:
        return self.moves + (5 if self.header is None else len(self.header))


def _num(x: float) -> str:
    return str(int(x)) if float(x).is_integer() else repr(float(x))


class ProgramSpec(Strict):
    """Exactly one of ``lines`` (inline), ``file`` (one line per line, ``;`` comments kept
    out), or ``generate``."""

    lines: list[str] | None = None
    file: str | None = None
    generate: GenerateSpec | None = None

    @model_validator(mode="after")
    def _one_source(self, info: ValidationInfo) -> ProgramSpec:
        given = [n for n in ("lines", "file", "generate") if getattr(self, n) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of lines, file, generate")
        if self.file is not None:
            text, _ = _read_file("program", self.file, (info.context or {}).get("base_dir"))
            object.__setattr__(self, "lines", _program_lines(text))
        return self

    def to_lines(self) -> list[str]:
        if self.generate is not None:
            return self.generate.lines()
        return list(self.lines or [])

    def count(self) -> int:
        """Number of lines, without generating them."""
        return self.generate.count() if self.generate is not None else len(self.lines or [])


def _program_lines(text: str) -> list[str]:
    out = []
    for raw in text.splitlines():
        line = raw.split(";", 1)[0].strip()
        if line:
            out.append(line)
    return out


# -- controllers ---------------------------------------------------------------------------


class RotarySpec(Strict):
    """``&cs DEFINE ROT size_words``."""

    cs: int = Field(1, ge=1, le=16)
    size_words: int = Field(ge=1)


class PlcSpec(Strict):
    """PMAC PLC program ``plc`` (0-31): ``text`` (one statement line per line, as entered
    between ``OPEN PLC n CLEAR`` and ``CLOSE``) or ``file``.

    ``enabled`` (default true) enables it at t = 0; ``enable_at_ms`` instead sends
    ``ENABLE PLC n`` to the card's command line at that time, as a host would (it takes
    effect when the background answers the command). PLC 0 runs every RTI when I5 is 1 or 3;
    PLCs 1-31 in the background when I5 is 2 or 3 (a PLC enabled where I5 forbids its class
    is refused here: it would never run).
    """

    plc: int = Field(ge=0, le=31)
    text: str | None = None
    file: str | None = None
    enabled: bool | None = None
    enable_at_ms: NonNeg | None = None

    @model_validator(mode="after")
    def _one_source(self, info: ValidationInfo) -> PlcSpec:
        if (self.text is None) == (self.file is None):
            raise ValueError("give exactly one of text, file")
        if self.enabled and self.enable_at_ms is not None:
            raise ValueError("enabled at t = 0 already: drop enable_at_ms or set enabled: false")
        if self.file is not None:
            text, _ = _read_file("PLC", self.file, (info.context or {}).get("base_dir"))
            object.__setattr__(self, "text", text)
        return self

    @property
    def enabled_at_start(self) -> bool:
        return self.enabled if self.enabled is not None else self.enable_at_ms is None


class RunSpec(Strict):
    """Run Trio program ``program`` (on ``process``, or the next free one)."""

    program: str
    process: int | None = Field(None, ge=1)


class ControllerSpec(Strict):
    """One controller: ``kind``, initial ``config`` (the kind's own keys, e.g. ``i16``) and set-up.

    PMAC: ``rotary`` buffers to define (highest CS first is done for you), ``plcs`` (PLC
    programs, :class:`PlcSpec`), ``cpu_sample_ms``: how often the run records the processor
    load (``status()["cpu"]``) as a ``cpu_sample`` event — default every 50 ms when the
    controller has PLCs, else never. Trio: ``axes``
    parameters (``{0: {speed: 10}}``), ``programs`` (name -> BASIC text) and ``run``.
    Both: ``variables`` (``P1``, ``VR(5)``) and ``setup`` terminal commands, at t = 0.
    Trio: ``expected_moves`` (``{0: 6, 1: 6}``) — what a BASIC program should complete.
    """

    kind: Literal["pmac", "trio"]
    config: dict[str, Any] = Field(default_factory=dict)
    rotary: list[RotarySpec] = Field(default_factory=list)
    plcs: list[PlcSpec] = Field(default_factory=list)
    cpu_sample_ms: Pos | None = None
    variables: dict[str, float] = Field(default_factory=dict)
    setup: list[str] = Field(default_factory=list)
    axes: dict[int, dict[str, float]] = Field(default_factory=dict)
    programs: dict[str, str] = Field(default_factory=dict)
    run: list[RunSpec] = Field(default_factory=list)
    #: Trio: moves each axis should complete (the summary shows done / expected and says
    #: when an axis fell short); feeder hosts' moves are counted without it.
    expected_moves: dict[int, Annotated[int, Field(ge=0)]] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _kind_fields(self) -> ControllerSpec:
        if self.kind == "pmac":
            for name in ("axes", "programs", "run"):
                if getattr(self, name):
                    raise ValueError(f"{name} is for kind trio, not pmac")
            cfg = {k.lower(): v for k, v in self.config.items()}
            for key in ("i16", "i17"):
                v = cfg.get(key, PMAC_DEFAULTS[key])
                if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                    raise ValueError(f"config.{key} must be an integer >= 0 (lines), got {v!r}")
            if cfg.get("i16", 5) > cfg.get("i17", 10):
                raise ValueError(
                    f"config.i16 = {cfg.get('i16', 5)} is above config.i17 = "
                    f"{cfg.get('i17', 10)}: BREQ would be re-raised while the buffer is full"
                )
            css = [r.cs for r in self.rotary]
            if len(css) != len(set(css)):
                raise ValueError("rotary: one buffer per coordinate system")
            nums = [p.plc for p in self.plcs]
            if len(nums) != len(set(nums)):
                raise ValueError("plcs: one entry per PLC number")
        else:
            for name in ("rotary", "plcs", "cpu_sample_ms"):
                if getattr(self, name):
                    raise ValueError(f"{name} is for kind pmac, not trio")
        return self

    def i5(self) -> int:
        """I5 at power-on (default 1: PLC 0 may run, PLCs 1-31 may not)."""
        cfg = {k.lower(): v for k, v in self.config.items()}
        return int(cfg.get("i5", 1)) & 3

    def sample_period_s(self) -> float | None:
        """How often to sample ``status()["cpu"]`` (None: never)."""
        if self.cpu_sample_ms is not None:
            return self.cpu_sample_ms / 1000
        return 0.05 if self.plcs else None

    def i16_i17(self) -> tuple[int, int]:
        cfg = {k.lower(): v for k, v in self.config.items()}
        return int(cfg.get("i16", 5)), int(cfg.get("i17", 10))


# -- hosts ---------------------------------------------------------------------------------


class _Host(Strict):
    name: str | None = None
    controller: str | None = None


class _PmacHost(_Host):
    """A PMAC rotary-buffer writer.

    ``write_via``: ``terminal`` writes as host software does — ``&cs OPEN ROT``, then one
    program line per command line on the host's own port, each answered at the end of a
    background cycle, one awaiting its answer at a time (so PLC 0 and the RTI's load show in
    the write latency, ``host_write.reply_s``; ``reply_timeout_ms`` before a
    ``host_timeout``); ``direct`` (default) stores each batch straight into the buffer, no
    command processing.

    ``direct`` stays the default because ``terminal`` changes a headline result of
    ``plc0_watchdog.yaml``: its hosts fill 500 lines before starting the program, which takes
    0.22 s line by line on an idle card (0.43 s behind the short PLC 0), so neither card
    finishes its 1500 moves of 2 ms in the 3 s run (1389 and 1333 executed; no starvation)
    and the PR poll counts differ. ``write_via_terminal.yaml`` shows the terminal path.
    """

    cs: int = Field(1, ge=1, le=16)
    program: ProgramSpec
    write_latency: DelaySpec = DelaySpec(ms=0)
    start_program: bool = True
    write_via: Literal["terminal", "direct"] = "direct"
    reply_timeout_ms: Pos = 1000.0


class PrPollingSpec(_PmacHost):
    """Polls ``PR`` every ``poll_period_ms``; refills from ``low_water`` to ``high_water``.

    ``pr_via``: ``terminal`` (default) sends ``&cs PR`` to the card's command line and waits
    for the reply, which the card gives at the end of a background cycle (so PLC 0 and the
    RTI's load show in the reply time; ``reply_timeout_ms`` before giving up on a poll);
    ``status`` reads the count directly, with no command processing.
    """

    type: Literal["pr_polling"]
    poll_period_ms: Pos
    pr_latency: DelaySpec = DelaySpec(ms=0)
    pr_via: Literal["terminal", "status"] = "terminal"
    lines_per_write: int = Field(1, ge=1)
    high_water: int = Field(1000, ge=1)
    low_water: int = Field(500, ge=0)

    @model_validator(mode="after")
    def _marks(self) -> PrPollingSpec:
        if self.low_water >= self.high_water:
            raise ValueError("low_water must be below high_water")
        return self


class BreqInterruptSpec(_PmacHost):
    """Answers each BREQ interrupt after ``latency``, ``lines_per_interrupt`` lines per write."""

    type: Literal["breq_interrupt"]
    latency: DelaySpec = DelaySpec(ms=0)
    lines_per_interrupt: int = Field(1, ge=1)
    recheck_breq: bool = True
    prefill: int | None = Field(None, ge=1)


class NaiveSpec(_PmacHost):
    """Sends back to back as fast as ``write_latency`` allows."""

    type: Literal["naive"]
    lines_per_write: int = Field(1, ge=1)


class MoveSpec(Strict):
    axis: int = Field(ge=0)
    type: str = "MOVE"
    args: list[float]


class MovesSpec(Strict):
    """Moves in program order: ``sequence`` of ``{axis, type, args}``, or ``per_axis``
    distances interleaved like TN20's loop (move n of each axis in turn)."""

    sequence: list[MoveSpec] | None = None
    per_axis: dict[int, list[float]] | None = None
    type: str = "MOVE"

    @model_validator(mode="after")
    def _one(self) -> MovesSpec:
        if (self.sequence is None) == (self.per_axis is None):
            raise ValueError("give exactly one of sequence, per_axis")
        return self

    def to_moves(self) -> list[Any]:
        from ...sim.hosts.trio import Move, interleave

        if self.per_axis is not None:
            return interleave(self.per_axis, self.type)
        return [Move(m.axis, m.type, tuple(m.args)) for m in self.sequence or []]

    def count(self) -> int:
        """Number of moves, without building them."""
        if self.per_axis is not None:
            return sum(len(v) for v in self.per_axis.values())
        return len(self.sequence or [])


class TrioFeederSpec(_Host):
    """A host issuing moves: ``trio_blind``, ``trio_ntype`` (TN20 fix) or
    ``trio_moves_buffered`` (waits until MOVES_BUFFERED < ``max_buffered``)."""

    type: Literal["trio_blind", "trio_ntype", "trio_moves_buffered"]
    moves: MovesSpec
    process: int | None = Field(None, ge=0)
    poll_period_ms: Pos = 1.0
    max_buffered: int = Field(2, ge=1)


HostSpec = Annotated[
    PrPollingSpec | BreqInterruptSpec | NaiveSpec | TrioFeederSpec, Field(discriminator="type")
]


# -- faults --------------------------------------------------------------------------------


class HostStallFault(Strict):
    """Host ``host`` does nothing from ``at_ms`` for ``duration_ms`` (a busy PC)."""

    type: Literal["host_stall"]
    host: str
    at_ms: NonNeg
    duration_ms: Pos


class TerminalFault(Strict):
    """Send ``command`` to ``controller``'s terminal at ``at_ms`` (e.g. ``&1 A``, ``I16=1``)."""

    type: Literal["terminal"]
    controller: str | None = None
    at_ms: NonNeg
    command: str


class SetVariableFault(Strict):
    """Write variable ``name`` = ``value`` on ``controller`` at ``at_ms``."""

    type: Literal["set_variable"]
    controller: str | None = None
    at_ms: NonNeg
    name: str
    value: float


class InjectFault(Strict):
    """Inject ``fault`` into ``controller`` at ``at_ms`` (:mod:`motionsim.app.faults`; in a
    scenario the hosts are simulated, so only the card's own faults apply: ``stall``,
    ``breq_lost``)."""

    type: Literal["inject"]
    controller: str | None = None
    at_ms: NonNeg = 0.0
    fault: InjectedFaultSpec


#: Injected faults a scenario's simulated hosts can meet (the others act on TCP replies).
SCENARIO_FAULT_KINDS = ("stall", "breq_lost")

FaultSpec = Annotated[
    HostStallFault | TerminalFault | SetVariableFault | InjectFault, Field(discriminator="type")
]


# -- the scenario --------------------------------------------------------------------------


class Scenario(Strict):
    """A what-if scenario. See ``examples/scenarios/`` for one of each kind."""

    name: str = "scenario"
    description: str = ""
    seed: int = 0
    duration_s: Pos = 10.0
    stop_event: dict[str, Any] | None = None
    controllers: dict[str, ControllerSpec] = Field(min_length=1)
    hosts: list[HostSpec] = Field(default_factory=list)
    faults: list[FaultSpec] = Field(default_factory=list)
    params: dict[str, str] = Field(default_factory=dict)
    metric: str = "time_starved_s"
    #: events held per controller (default: sized from the program); metrics need them all
    log_capacity: int | None = Field(None, ge=1000, le=100_000_000)

    _lines: dict[tuple[Any, ...], int] = PrivateAttr(default_factory=dict)
    _file: str | None = PrivateAttr(None)
    _base_dir: Path | None = PrivateAttr(None)
    _raw: Any = PrivateAttr(None)

    @property
    def file(self) -> str | None:
        return self._file

    @property
    def base_dir(self) -> Path | None:
        return self._base_dir

    @property
    def raw(self) -> Any:
        """The data as read from the file (sweeps override values in a copy of it)."""
        return self._raw

    def error_at(self, path: tuple[Any, ...], message: str) -> ScenarioError:
        """A :class:`ScenarioError` for ``path`` (keys / indices), with its file line."""
        fpath, line = locate(self._raw, path, self._lines)
        return ScenarioError(message, file=self._file, line=line, field=dotted(fpath))

    @field_validator("controllers")
    @classmethod
    def _ids(cls, v: dict[str, ControllerSpec]) -> dict[str, ControllerSpec]:
        for cid in v:
            if not re.fullmatch(r"[A-Za-z0-9_.-]+", cid):
                raise ValueError(f"controller id {cid!r}: letters, digits, _ . - only")
        return v

    @field_validator("stop_event")
    @classmethod
    def _stop_event(cls, v: dict[str, Any] | None) -> dict[str, Any] | None:
        if v is not None and not isinstance(v.get("type"), str):
            raise ValueError("stop_event needs a type")
        return v

    def host_names(self) -> list[str]:
        return [h.name or f"{h.type}{i}" for i, h in enumerate(self.hosts)]

    def host_controller(self, i: int) -> str:
        return self.hosts[i].controller or next(iter(self.controllers))


def _cross_checks(s: Scenario) -> list[tuple[tuple[Any, ...], str]]:
    """Checks between fields: references to controllers and hosts, kinds matching hosts."""
    problems: list[tuple[tuple[Any, ...], str]] = []
    ids = list(s.controllers)
    names = s.host_names()
    if len(set(names)) != len(names):
        problems.append((("hosts",), "host names must be unique"))
    for i, h in enumerate(s.hosts):
        if h.controller is None and len(ids) > 1:
            problems.append((("hosts", i), "name the controller (there are several)"))
            continue
        cid = s.host_controller(i)
        if cid not in s.controllers:
            problems.append((("hosts", i, "controller"), f"no controller {cid!r}"))
            continue
        kind = s.controllers[cid].kind
        want = "trio" if h.type.startswith("trio_") else "pmac"
        if kind != want:
            problems.append(
                (("hosts", i, "type"), f"host type {h.type!r} needs a {want} controller")
            )
        elif want == "pmac":
            css = {r.cs for r in s.controllers[cid].rotary}
            if h.cs not in css:  # type: ignore[union-attr]
                problems.append(
                    (("hosts", i, "cs"), f"controller {cid!r} has no rotary buffer for &{h.cs}")  # type: ignore[union-attr]
                )
    for i, f in enumerate(s.faults):
        if isinstance(f, HostStallFault):
            if f.host not in names:
                problems.append((("faults", i, "host"), f"no host {f.host!r}"))
        elif isinstance(f, InjectFault) and f.fault.kind not in SCENARIO_FAULT_KINDS:
            problems.append((("faults", i, "fault", "kind"),
                             f"{f.fault.kind} acts on TCP replies; a scenario's hosts are "
                             f"simulated: use {' or '.join(SCENARIO_FAULT_KINDS)}"))
        elif isinstance(f, InjectFault) and _kind_of(s, f.controller) not in (None, "pmac"):
            problems.append((("faults", i, "fault", "kind"),
                             f"{f.fault.kind} needs a pmac controller"))
        elif f.controller is not None and f.controller not in s.controllers:
            problems.append((("faults", i, "controller"), f"no controller {f.controller!r}"))
        elif f.controller is None and len(ids) > 1:
            problems.append((("faults", i), "name the controller (there are several)"))
    return problems


def _kind_of(s: Scenario, controller: str | None) -> str | None:
    """The kind of ``controller`` (the only one if None); None if there is no such one."""
    ids = list(s.controllers)
    cid = controller if controller is not None else (ids[0] if len(ids) == 1 else None)
    spec = s.controllers.get(cid) if cid is not None else None
    return spec.kind if spec is not None else None


def _plc_checks(
    s: Scenario, lines: dict[tuple[Any, ...], int]
) -> list[tuple[tuple[Any, ...], str, int | None]]:
    """Each PLC program compiles (errors at the file line of the bad PLC line), and I5 lets
    every enabled PLC run."""
    from ...sim.errors import ParseError
    from ...sim.pmac.tasks.plc import compile_plc

    out: list[tuple[tuple[Any, ...], str, int | None]] = []
    for cid, spec in s.controllers.items():
        i5 = spec.i5()
        for i, p in enumerate(spec.plcs):
            path: tuple[Any, ...] = ("controllers", cid, "plcs", i)
            try:
                compile_plc(p.text or "")
            except ParseError as e:
                where = f"{p.file} line {e.line}" if p.file else f"PLC {p.plc} line {e.line}"
                msg = f"{where}, column {e.column}: {e.message}"
                if e.text:
                    msg += f" in {e.text.strip()!r}"
                if p.file is not None:
                    out.append(((*path, "file"), msg, lines.get((*path, "file"))))
                else:
                    first = value_line(lines, (*path, "text"))
                    line = first + (e.line or 1) - 1 if first is not None else None
                    out.append(((*path, "text"), msg, line))
                continue
            permitted = i5 & (1 if p.plc == 0 else 2)
            if (p.enabled_at_start or p.enable_at_ms is not None) and not permitted:
                what = "PLC 0 (foreground)" if p.plc == 0 else f"PLC {p.plc} (background)"
                need = "1 or 3" if p.plc == 0 else "2 or 3"
                out.append((
                    (*path, "enabled" if p.enabled is not None else "plc"),
                    f"{what} is enabled but I5 = {i5} does not let it run "
                    f"(set config.i5 to {need}, or enabled: false)",
                    None,
                ))  # fmt: skip
    return out


def parse_scenario(
    data: Any,
    *,
    lines: dict[tuple[Any, ...], int] | None = None,
    file: str | None = None,
    base_dir: Path | None = None,
) -> Scenario:
    """Validate already-loaded data; errors name field and line (when ``lines`` is given)."""
    lines = lines or {}
    try:
        scn = Scenario.model_validate(data, context={"base_dir": base_dir})
    except ValidationError as exc:
        errors = []
        for e in exc.errors():
            path, line = locate(data, e["loc"], lines)
            msg = e["msg"].removeprefix("Value error, ")
            path, line = _refine(path, line, msg, lines)
            errors.append({"field": dotted(path), "line": line, "message": msg})
        first = errors[0]
        raise ScenarioError(
            first["message"], file=file, line=first["line"], field=first["field"], errors=errors
        ) from None
    problems = [(p, m, None) for p, m in _cross_checks(scn)] + _plc_checks(scn, lines)
    if problems:
        errors = []
        for path, msg, exact in problems:
            _, line = locate(data, path, lines)
            errors.append({"field": dotted(path), "line": exact or line, "message": msg})
        first = errors[0]
        raise ScenarioError(
            first["message"], file=file, line=first["line"], field=first["field"], errors=errors
        )
    scn._lines, scn._file, scn._base_dir, scn._raw = lines, file, base_dir, data
    return scn


def _refine(
    path: tuple[Any, ...], line: int | None, msg: str, lines: dict[tuple[Any, ...], int]
) -> tuple[tuple[Any, ...], int | None]:
    """A model-level message that starts with a field (``config.i16 = 12 ...``) points there."""
    m = re.match(r"([A-Za-z_][\w.]*)\b", msg)
    if m and "." in m.group(1):
        sub = (*path, *m.group(1).split("."))
        if sub in lines:
            return sub, lines[sub]
    return path, line


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a scenario file (YAML)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise ScenarioError(f"cannot read scenario: {exc.strerror}", file=str(p)) from None
    data, lines = load_yaml(text, str(p))
    return parse_scenario(data, lines=lines, file=str(p), base_dir=p.parent)


def loads_scenario(
    text: str, *, file: str = "<scenario>", base_dir: Path | None = None
) -> Scenario:
    """Validate scenario YAML given as text."""
    data, lines = load_yaml(text, file)
    return parse_scenario(data, lines=lines, file=file, base_dir=base_dir)


__all__ = [
    "BreqInterruptSpec",
    "ControllerSpec",
    "DelaySpec",
    "GenerateSpec",
    "NaiveSpec",
    "PlcSpec",
    "PrPollingSpec",
    "ProgramSpec",
    "Scenario",
    "TrioFeederSpec",
    "load_scenario",
    "loads_scenario",
    "parse_scenario",
]
