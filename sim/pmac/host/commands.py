"""The Turbo PMAC on-line commands as one table: statement class -> how it runs.

The parser half of a command is its keyword row (:mod:`motionsim.sim.pmac.language.keywords`,
the word and the builder of its statement) or one of the parser's operator / letter forms
(``&n``, ``#n``, ``?``, ``R``, ``PC``...). This module is the other half: one
:class:`Command` row per statement class, with a direct reference to the handler that runs it
on the controller and the few facts the terminal and the PLC scan decide by:

* ``report`` — it changes no controller state, so it may answer before a malformed command
  later on the same line (TSRM p259: the card interprets left to right);
* ``with_plc_open`` — it still acts on-line while the port holds a PLC buffer open (a host
  driver's ``&1%`` / ``??`` / ``PR`` polls keep working while it enters a PLC) ``[INF]``;
* ``program_form`` — the command also has a motion-program form that is not simulated: with
  a motion buffer open it answers ``not_simulated`` instead of running at once.

Adding an on-line command is its keyword row, its statement class, and one row here with
its handler; neither the terminal's nor the PLC scan's code changes. A PLC statement of a
command family (``MSR``, a range assignment, ``#n->``, ``HOME{list}``) runs through the same
row (:func:`run`).

A handler takes the :class:`Call` (controller, the port or None inside a PLC, the addressed
``&n`` / ``#n`` state, the data lines answered so far) and the statement.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

from ...errors import Conflict, InvalidValue
from ..card import (
    card_commands,
    comp_tables,
    macro_station,
    memory_commands,
    mvar_defs,
    user_buffer,
)
from ..card.variables import N_CS, N_MOTORS, N_VARS, format_ivar, format_value
from ..kinematics import commands as kin
from ..language import axis_definitions as axdef
from ..language import card_words, list_words, ranges
from ..language import motor_statements as motor_st
from ..language import plc_statements as plc_st
from ..language import statements as st
from ..language.cs_enable import EnableCS
from . import list_commands, program_counter

if TYPE_CHECKING:
    from ...controller import Port
    from ..controller import PmacController

VERSION = "1.947  "
CARD_ID = "603382"
CPU = "DSP56321"
TYPE = "TURBO2"


class CommandError(Exception):
    """Stop executing the line; answer ``code``."""

    def __init__(self, code: str) -> None:
        super().__init__(code)
        self.code = code


@dataclass(slots=True)
class Call:
    """Where a command runs: the controller, the port (None inside a PLC program), the port's
    (or the PLC's) addressed ``cs`` / ``motor`` state, and the data lines answered so far."""

    ctl: PmacController
    port: Port | None
    state: dict[str, Any]
    out: list[str]


Handler = Callable[[Call, Any], None]


@dataclass(frozen=True, slots=True)
class Command:
    """One on-line command: its statement class and handler, and the terminal's facts about
    it (module docstring). ``report`` / ``program_form`` may be a function of the statement
    when only some of a class's statements are (``#n->`` the query; MSR / MSW)."""

    kind: type
    run: Handler
    report: bool | Callable[[Any], bool] = False
    with_plc_open: bool = False
    program_form: bool | Callable[[Any], bool] = False


def _hex_words(*words: int) -> str:
    return "".join(f"{w & 0xFFFFFF:06X}" for w in words)


def _need_port(c: Call) -> Port:
    if c.port is None:  # pragma: no cover - the PLC parser admits no port command
        raise CommandError("ERR003")
    return c.port


# -- addressing -----------------------------------------------------------------------------


def address_cs(c: Call, stmt: st.AddressCS) -> None:
    """``&n`` (``&`` alone reports the addressed CS)."""
    state, ctl = c.state, c.ctl
    if stmt.cs is None:
        c.out.append(str(state["cs"]))
        return
    if not 1 <= stmt.cs <= N_CS:
        raise CommandError("ERR003")
    changed = stmt.cs != state["cs"]
    state["cs"] = stmt.cs
    rot = ctl.coord_system(stmt.cs).rotary
    if changed and rot is not None and ctl.buffer_holder is c.port and ctl.rotary_open():
        # seed 000: a *change* of the addressed CS re-evaluates BREQ; ``&1`` with CS 1
        # already addressed changes nothing (no BREQ pulse per poll)
        rot.reevaluate()


def address_motor(c: Call, stmt: st.AddressMotor) -> None:
    """``#n`` (``#`` alone reports the addressed motor)."""
    if stmt.motor is None:
        c.out.append(str(c.state["motor"]))
        return
    if not 1 <= stmt.motor <= N_MOTORS:
        raise CommandError("ERR003")
    c.state["motor"] = stmt.motor


def motor_group(c: Call, stmt: motor_st.MotorGroup) -> None:
    """``##n``: the addressed group of eight motors."""
    if stmt.group is None:
        c.out.append(str(c.state.get("group", 0)))
        return
    if not 0 <= stmt.group < N_MOTORS // 8:
        raise CommandError("ERR003")
    c.state["group"] = stmt.group


def motor_command(c: Call, stmt: Any) -> None:
    """``J+``, ``HM``, ``K``, ``O``, ``$`` for the addressed motor."""
    c.ctl.motor_command(stmt, c.state["motor"])


def home_list(c: Call, stmt: motor_st.HomeList) -> None:
    """``HOME{list}``: each listed motor homes as ``#nHM`` would."""
    for n in stmt.motors:
        c.ctl.motor_command(motor_st.Home(stmt.zero), n)


# -- buffers and programs -------------------------------------------------------------------


def _cs(c: Call) -> Any:
    return c.ctl.coord_system(c.state["cs"])


def clear(c: Call, stmt: plc_st.Clear) -> None:
    """``CLEAR``: erase the open fixed buffer or, with the rotary buffers open on this port,
    the addressed CS's rotary lines not yet calculated (:meth:`RotaryBuffer.clear`)."""
    ctl = c.ctl
    if ctl.programs.editing(c.port) is not None:
        ctl.programs.clear()
        return
    if c.port is not None and ctl.buffer_holder is c.port and ctl.rotary_open():
        rot = _cs(c).rotary
        if rot is not None:
            rot.clear()
        return
    raise CommandError("ERR005")  # CLEAR needs an open buffer [INF]


# -- reports --------------------------------------------------------------------------------


def query(c: Call, stmt: st.Query) -> None:
    """``%``, ``PR``, ``??``, ``?``, ``???``, ``SIZE``, ``VER``, ``CID``, ``CPU``, ``TYPE``,
    ``VID``, ``P`` / ``V`` / ``F``."""
    ctl, what = c.ctl, stmt.what
    if what in ("P", "V", "F"):
        c.out.append(format_value(ctl.motor_report(c.state["motor"], what)))
        return
    if what == "?":
        c.out.append(_hex_words(*ctl.motor_status(c.state["motor"])))
        return
    cs = _cs(c)
    if what == "%":
        reply = format_value(cs.feed_override)
    elif what == "PR":
        reply = str(cs.rotary.lines_ahead if cs.rotary is not None else 0)
    elif what == "??":
        reply = _hex_words(*cs.status_words())
    elif what == "???":
        reply = _hex_words(ctl.background.global_status_word1(), 0)
    elif what == "SIZE":
        reply = str(ctl.size_words())
    else:
        fixed = {"VER": VERSION, "CID": CARD_ID, "CPU": CPU, "TYPE": TYPE, "VID": "1"}
        if what not in fixed:
            raise CommandError("ERR003")
        reply = fixed[what]
    c.out.append(reply)


def var_query(c: Call, stmt: st.VarQuery) -> None:
    """``I16``, ``P1..3``: I9 bit 0 (PSRM I9, spec §9.8): 0 reports the value only (``5``), 1
    the whole statement (``I16=5``); bit 1: address-type I-variables in hex (``$78400``)."""
    vars_ = c.ctl.vars
    i9 = int(vars_.I(9))
    numbers = stmt.numbers()
    if any(not 0 <= n < N_VARS for n in numbers):
        raise CommandError("ERR003")
    for n in numbers:
        raw = vars_.read(stmt.kind, n, c.state["cs"])
        value = format_ivar(n, raw, i9) if stmt.kind == "I" else format_value(raw)
        c.out.append(f"{stmt.kind}{n}={value}" if i9 & 1 else value)


def _variable_number(kind: str, index: float) -> int:
    """The number an on-line indirect reference ``P(expr)`` names: ERR003 outside 0..8191
    (spec §12.4), for a query and an assignment alike."""
    n = int(index)
    if not 0 <= n < N_VARS:
        raise InvalidValue(f"{kind}({n}): no such variable (0..8191)", pmac_error="ERR003")
    return n


def indirect_query(c: Call, stmt: ranges.IndirectQuery) -> None:
    """``{kind}({expr})``: the value of the variable whose number the expression gives."""
    vars_ = c.ctl.vars
    cs = c.state["cs"]
    n = _variable_number(stmt.kind, stmt.index(vars_, cs))
    raw = vars_.read(stmt.kind, n, cs)
    i9 = int(vars_.I(9))
    value = format_ivar(n, raw, i9) if stmt.kind == "I" else format_value(raw)
    c.out.append(f"{stmt.kind}{n}={value}" if i9 & 1 else value)


def m_definition_query(c: Call, stmt: st.MDefinitionQuery) -> None:
    """``M1->``: one definition per line; I9 bit 0 = 1: as a statement ``M1->Y:$78802,8``."""
    full = int(c.ctl.vars.I(9)) & 1
    mvars = c.ctl.vars.mvars
    for n in stmt.numbers():
        d = mvars.definition(n) if stmt.kind == "M" else mvars.l_definition(n)
        text = mvar_defs.report(d)
        c.out.append(f"{stmt.kind}{n}->{text}" if full else text)


# -- variables ------------------------------------------------------------------------------


def assign(c: Call, stmt: st.Assign) -> None:
    """``P1=5`` with buffers closed acts at once; a synchronous ``==`` needs a buffer; an
    indirect target outside 0..8191 is ERR003, as its query is (the value is not evaluated
    into a write)."""
    if stmt.synchronous:
        raise CommandError("ERR005")
    ctl, cs = c.ctl, c.state["cs"]
    n = _variable_number(stmt.target.kind, stmt.target.index(ctl.vars, cs))
    ctl.vars.write(stmt.target.kind, n, stmt.value(ctl.vars, cs), cs)


def range_assign(c: Call, stmt: ranges.RangeAssign) -> None:
    """``{kind}{numbers}={value}``: the same value to each."""
    vars_, cs = c.ctl.vars, c.state["cs"]
    v = stmt.value(vars_, cs)
    for n in stmt.numbers:
        vars_.write(stmt.kind, n, v, cs)


def var_default(c: Call, stmt: st.VarDefault) -> None:
    """``I{n}..{m}=*``: factory defaults."""
    for n in range(stmt.first, stmt.last + 1):
        c.ctl.vars.set_default(n)


def station(c: Call, stmt: macro_station.StationCommand) -> None:
    """``MS…``: a MACRO station command; its data line, if any."""
    reply = c.ctl.macro_stations.execute(stmt, c.ctl.vars, c.state["cs"])
    if reply is not None:
        c.out.append(reply)


def axis_definition(c: Call, stmt: axdef.AxisDefinition) -> None:
    """``#{motor}->{definition}``; ``#{motor}->`` alone reports the definition (``0`` when the
    motor is not in the addressed CS). A definition moves no motor: the axis position takes
    the change of offset (``Motor.offset_moved``, through the controller)."""
    ctl = c.ctl
    if not 1 <= stmt.motor <= N_MOTORS:
        raise InvalidValue(f"no motor {stmt.motor} (1..{N_MOTORS})", pmac_error="ERR003")
    cs = c.state["cs"]
    have = ctl.motors.get(stmt.motor)
    old = axdef.lookup(have[1]).offset if have is not None else 0.0
    if stmt.definition is None:
        c.out.append(have[1] if have is not None and have[0] == cs else "0")
        return
    if not stmt.definition.terms and not stmt.definition.inverse:
        if have is None or have[0] != cs:
            return
        del ctl.motors[stmt.motor]
    elif have is not None and have[0] != cs:
        raise Conflict(f"motor {stmt.motor} is defined in coordinate system {have[0]}",
                       pmac_error="ERR003")
    else:
        ctl.motors[stmt.motor] = (cs, stmt.definition.report())
    ctl.axis_offset_changed(stmt.motor, stmt.definition.offset - old)


def nothing(c: Call, stmt: Any) -> None:
    """Accepted and changes nothing (``DELETE TRACE``: no trace buffer is simulated)."""


def _of(method: str) -> Handler:
    """A handler calling ``ctl.{method}(cs)`` for the addressed CS."""
    return lambda c, stmt: getattr(c.ctl, method)(c.state["cs"])


#: Every on-line command, by statement class.
TABLE: Final[tuple[Command, ...]] = (
    Command(st.AddressCS, address_cs, report=True, with_plc_open=True),
    Command(st.AddressMotor, address_motor, report=True, with_plc_open=True),
    Command(motor_st.MotorGroup, motor_group),
    *(Command(t, motor_command) for t in motor_st.MOTOR_TYPES),
    Command(motor_st.HomeList, home_list),
    Command(axdef.AxisDefinition, axis_definition, report=lambda s: s.definition is None),
    Command(st.DefineRotary, lambda c, s: c.ctl.define_rotary(c.state["cs"], s.words)),
    Command(st.DeleteRotary, _of("delete_rotary")),
    Command(st.DefineGather, lambda c, s: c.ctl.define_gather(s.words)),
    Command(st.DeleteGather, lambda c, s: c.ctl.delete_gather()),
    Command(st.Gather, lambda c, s: c.ctl.start_gather(s.trigger)),
    Command(st.EndGather, lambda c, s: c.ctl.end_gather()),
    Command(st.DefineLookahead,
            lambda c, s: c.ctl.define_lookahead(c.state["cs"], s.segments, s.outputs)),
    Command(st.DeleteLookahead, _of("delete_lookahead")),
    Command(st.OpenRotary, lambda c, s: c.ctl.open_rotary(_need_port(c))),
    Command(st.OpenProgram, lambda c, s: c.ctl.open_program(s.n, _need_port(c))),
    Command(st.Close, lambda c, s: c.ctl.close_buffers(_need_port(c))),
    Command(st.ProgramPointer, lambda c, s: c.ctl.point_program(c.state["cs"], s.program)),
    Command(st.Run, lambda c, s: c.ctl.run(c.state["cs"], pointer=None), with_plc_open=True),
    Command(st.Step, lambda c, s: c.ctl.run(c.state["cs"], pointer=None, single_step=True),
            with_plc_open=True),
    Command(EnableCS, lambda c, s: c.ctl.enable_cs(c.state["cs"]), with_plc_open=True),
    Command(st.Quit, _of("quit"), with_plc_open=True),
    Command(st.MFlush, _of("mflush"), with_plc_open=True),
    Command(st.Hold, lambda c, s: _cs(c).hold(), with_plc_open=True),
    Command(st.StopAtEnd, lambda c, s: _cs(c).stop_at_end(), with_plc_open=True),
    Command(st.QuickStop, lambda c, s: _cs(c).quick_stop(), with_plc_open=True),
    Command(st.Abort, _of("abort"), with_plc_open=True),
    Command(st.Query, query, report=True, with_plc_open=True),
    Command(st.FeedOverride, lambda c, s: _cs(c).set_feed_override(s.percent),
            with_plc_open=True),
    Command(st.VarQuery, var_query, report=True, with_plc_open=True),
    Command(st.VarDefault, var_default),
    Command(st.MDefinitionQuery, m_definition_query, report=True, with_plc_open=True),
    Command(st.Assign, assign),
    Command(ranges.RangeAssign, range_assign),
    Command(ranges.IndirectQuery, indirect_query),
    Command(card_commands.Save, lambda c, s: card_commands.save(c.ctl)),
    Command(card_commands.Reset, lambda c, s: card_commands.schedule_reset(c.ctl, s.factory)),
    Command(list_words.ListBuffer,
            lambda c, s: c.out.extend(list_commands.run(s, c.ctl, _need_port(c))),
            report=True, with_plc_open=True),
    Command(mvar_defs.MDefine,
            lambda c, s: c.ctl.vars.mvars.define(s.first, s.last, s.definition, s.kind)),
    Command(st.ProgramCounter,
            lambda c, s: c.out.append(program_counter.report(s, c.ctl, c.state["cs"])),
            report=True, with_plc_open=True),
    Command(memory_commands.MemoryRead,
            lambda c, s: c.out.append(memory_commands.read(s, c.ctl.vars.mvars)),
            report=True, with_plc_open=True),
    Command(memory_commands.MemoryWrite,
            lambda c, s: memory_commands.write(s, c.ctl.vars.mvars)),
    Command(macro_station.StationCommand, station,
            program_form=lambda s: s.op in ("copy_in", "copy_out")),
    Command(plc_st.ClearAllPlcs, lambda c, s: c.ctl.plcs.clear_all()),
    Command(plc_st.OpenPlc, lambda c, s: c.ctl.plcs.open(s.n, _need_port(c), s.compiled)),
    Command(plc_st.EnablePlc,
            lambda c, s: c.ctl.plcs.set_enabled(s.numbers, s.enable, s.compiled)),
    Command(plc_st.DeletePlcc, lambda c, s: c.ctl.plcs.delete_compiled(s.numbers)),
    Command(plc_st.Clear, clear),
    Command(card_words.DeleteTrace, nothing),
    Command(comp_tables.DefineComp,
            lambda c, s: comp_tables.define(c.ctl, s, c.state["motor"], c.state)),
    Command(comp_tables.DeleteComp,
            lambda c, s: comp_tables.delete(c.ctl, c.state["motor"], c.state)),
    Command(user_buffer.DefineUbuffer, lambda c, s: user_buffer.define(c.ctl, s)),
    Command(user_buffer.DeleteAll, lambda c, s: user_buffer.delete_all(c.ctl)),
    Command(card_words.OpenKinematic, lambda c, s: kin.open_kinematic(c.ctl, s, _need_port(c))),
    Command(card_words.Pmatch, lambda c, s: kin.pmatch(c.ctl, c.state["cs"])),
    Command(card_words.Undefine, lambda c, s: kin.undefine(c.ctl, s, c.state["cs"])),
)


#: Statement class -> its row.
BY_KIND: Final[dict[type, Command]] = {row.kind: row for row in TABLE}
assert len(BY_KIND) == len(TABLE), "a statement class has two rows"


def _flag(value: bool | Callable[[Any], bool], stmt: Any) -> bool:
    return value(stmt) if callable(value) else value


def is_report(stmt: Any) -> bool:
    """Does ``stmt`` change nothing (may it answer before a malformed command)?"""
    row = BY_KIND.get(type(stmt))
    return row is not None and _flag(row.report, stmt)


def acts_with_plc_open(stmt: Any) -> bool:
    """Does ``stmt`` act on-line while the port holds a PLC buffer open?"""
    row = BY_KIND.get(type(stmt))
    return row is not None and row.with_plc_open


def has_program_form(stmt: Any) -> bool:
    """Has ``stmt`` a motion-program form that is not simulated?"""
    row = BY_KIND.get(type(stmt))
    return row is not None and _flag(row.program_form, stmt)


def run(call: Call, stmt: Any) -> None:
    """Run ``stmt`` on-line: its row's handler."""
    row = BY_KIND.get(type(stmt))
    if row is None:
        raise CommandError("ERR005" if isinstance(stmt, st.PROGRAM_TYPES) else "ERR003")
    row.run(call, stmt)


__all__ = [
    "BY_KIND", "CARD_ID", "CPU", "TABLE", "TYPE", "VERSION", "Call", "Command", "CommandError",
    "acts_with_plc_open", "has_program_form", "is_report", "run",
]  # fmt: skip
