"""The Turbo PMAC command line of one host port: on-line commands versus buffered lines.

A command line is parsed whole first (a parse error answers ERR003 and changes nothing), then
executed left to right (TSRM p259; spec §2.3, §3):

* with this port holding the rotary buffers open, program statements are stored — the run of
  program statements between two on-line commands is one program line, stored in the rotary
  buffer of the CS addressed at that moment (``&1 X10 &2 X30`` stores ``X10`` in CS 1 and
  ``X30`` in CS 2). ``R``, ``Q``, ``A``, ``&n``, ``#n``, queries, ``CLOSE`` still act on-line;
* with buffers closed, assignments act at once; other program statements answer ERR005
  ("not allowed unless a buffer is open", e.g. ``X1000``);
* only one port may hold the buffers open: ``OPEN ROT`` from another port answers ERR007.

Replies: each data-producing command contributes one data line; the reply is the lines joined
with ``"\\r"`` (no handshake characters — the protocol adapters add them). On an error the rest
of the line is discarded and ``error`` is the code, after the data already produced
``[INF, spec §2.3]``.

Error codes used (spec §2.2): ERR001 (``B``/``DELETE ROT`` while the CS runs), ERR003 (bad
text, bad number, DEFINE ROT ordering, ``OPEN ROT`` with no rotary buffer ``[INF]``), ERR005,
ERR006 (a line that does not fit, or no rotary buffer in the addressed CS while open
``[INF]``), ERR007, ERR015 (``R``/``S`` without ``B0`` or without a rotary buffer).
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, Any

from motionsim.sim.controller import Port
from motionsim.sim.errors import MotionSimError, NotSimulated, ParseError
from motionsim.sim.pmac.buffers import program_counter
from motionsim.sim.pmac.buffers.program import compile_statements
from motionsim.sim.pmac.card import card_commands, memory_commands, mvar_defs
from motionsim.sim.pmac.card.variables import N_CS, N_MOTORS, format_ivar, format_value
from motionsim.sim.pmac.host import list_commands, not_simulated
from motionsim.sim.pmac.host.control_chars import ControlCharacters, split_controls
from motionsim.sim.pmac.language import motor_statements as motor_st
from motionsim.sim.pmac.language import plc_statements as plc_st
from motionsim.sim.pmac.language import statements as st
from motionsim.sim.pmac.language.parser import parse_line

if TYPE_CHECKING:
    from motionsim.sim.pmac.controller import PmacController

_OPEN_PLC = re.compile(r"OPEN\s*PLCC?\s*\d+", re.IGNORECASE)

VERSION = "1.947  "
CARD_ID = "603382"
CPU = "DSP56321"
TYPE = "TURBO2"


#: On-line commands that still act on-line while the port holds a PLC buffer open.
_ONLINE_IN_PLC = (
    st.AddressCS, st.AddressMotor, st.Query, st.VarQuery, st.MDefinitionQuery, st.FeedOverride,
    st.Run, st.Step, st.Quit, st.Hold, st.Abort, st.MFlush, list_commands.ListBuffer,
    program_counter.ProgramCounter, memory_commands.MemoryRead,
)  # fmt: skip


class CommandError(Exception):
    """Stop executing the line; answer ``code``."""

    def __init__(self, code: str) -> None:
        super().__init__(code)
        self.code = code


#: What may run before a malformed command on the same line: it changes no controller state.
_REPORTS = (st.Query, st.VarQuery, st.MDefinitionQuery, st.AddressCS, st.AddressMotor,
            list_commands.ListBuffer, program_counter.ProgramCounter,
            memory_commands.MemoryRead)


def _is_report(stmt: Any) -> bool:
    if isinstance(stmt, st.AxisDefinition):
        return stmt.definition is None
    return isinstance(stmt, _REPORTS)


#: Parsed lines by ``(text, open)``: a host driver sends the same poll line every cycle
#: (the EPICS driver's 40-item status request), and parsing is most of its cost. Statements
#: are immutable, so a cached parse is the same as a new one.
_PARSE_CACHE: dict[tuple[str, bool], list[tuple[Any, int, int]]] = {}
_PARSE_CACHE_SIZE = 512


def _parsed(text: str, open_: bool) -> list[tuple[Any, int, int]]:
    key = (text, open_)
    got = _PARSE_CACHE.get(key)
    if got is None:
        got = parse_line(text, open_=open_)
        if len(_PARSE_CACHE) >= _PARSE_CACHE_SIZE:
            _PARSE_CACHE.clear()
        _PARSE_CACHE[key] = got
    return got


def _where(e: ParseError) -> str:
    column = e.details.get("column")
    return f"{e.message} (column {column})" if column else e.message


def _hex_words(*words: int) -> str:
    return "".join(f"{w & 0xFFFFFF:06X}" for w in words)


class Terminal:
    """Executes command lines for :class:`motionsim.sim.pmac.controller.PmacController` ports."""

    def __init__(self, ctl: PmacController) -> None:
        self.ctl = ctl
        self._controls = ControlCharacters(ctl)
        #: ``(kind, message)`` explaining the last line's error for people (REST), or None:
        #: kind ``"not_simulated"``, ``"parse_error"`` or a core error code.
        self.detail: tuple[str, str] | None = None

    def execute(self, text: str, port: Port) -> tuple[str, str | None]:
        """Run one command line; returns ``(reply, error)`` (and sets :attr:`detail`).

        Control characters in it act first, in order (:mod:`motionsim.sim.pmac.host.control_chars`);
        an unknown one answers its error and the rest of the line is not run.
        """
        self.detail = None
        controls, text = split_controls(text)
        if controls:
            out: list[str] = []
            for ch in controls:
                reply, error = self._controls.act(ch, port)
                if reply:
                    out.append(reply)
                if error is not None:
                    return "\r".join(out), error
            if text.strip():
                more, error = self.execute(text, port)
                if more:
                    out.append(more)
                return "\r".join(out), error
            return "\r".join(out), None
        ctl = self.ctl
        if ctl.plcs.editing(port) is not None:
            # OPEN PLC: lines go into the PLC; what follows a CLOSE is on-line again.
            reply, error, rest = ctl.plcs.enter_line(text, port)
            if error == "ERR003" and self._online_only(text):
                return self._run(text, port, open_=False)  # not PLC text: on-line commands
            if error is None and rest and rest.strip():
                more, error = self.execute(rest, port)
                reply = "\r".join(x for x in (reply, more) if x)
            return reply, error
        m = _OPEN_PLC.search(text)
        if m is not None and text[m.end() :].strip():
            # ``OPEN PLC 1 CLEAR ...``: the rest of the line is already PLC text.
            reply, error = self.execute(text[: m.end()], port)
            if error is not None or ctl.plcs.editing(port) is None:
                return reply, error
            more, error = self.execute(text[m.end() :], port)
            return "\r".join(x for x in (reply, more) if x), error
        return self._run(text, port, open_=ctl.buffer_holder is port)

    @staticmethod
    def _online_only(text: str) -> bool:
        """Is ``text`` made only of on-line commands that have no PLC-program form (queries,
        ``&n``, ``#n``, ``%n``, ``R``/``S``/``Q``/``A``/``H``)? With a buffer open the card
        stores what it can and executes the rest on-line (seed 000) ``[INF]`` for PLC buffers:
        so the ``&1%`` / ``??`` / ``PR`` polls of a host driver keep working while it enters a
        PLC."""
        try:
            stmts = parse_line(text, open_=False)
        except ParseError:
            return False
        return bool(stmts) and all(isinstance(item[0], _ONLINE_IN_PLC) for item in stmts)

    def _run(self, text: str, port: Port, open_: bool) -> tuple[str, str | None]:
        """Parse the line, then execute it left to right.

        A line that fails to parse answers the reports (queries, listings, ``&n``/``#n``)
        before the blank-delimited command that fails, then its ERR003 (the card interprets
        left to right, TSRM p259; spec §2.3 ``[INF]``): ``I10 nonsense`` answers I10's value,
        then the error. A malformed line changes nothing: if anything before the failing
        command would act (``P1=5 P2=(3``) nothing runs ``[INF]`` — a real card may already
        have acted on it, a simulator keeps bad input harmless. A buffer this line opened is
        closed again when the line ends in an error.
        """
        self.detail = None
        try:
            stmts = _parsed(text, open_)
            failed: ParseError | None = None
        except ParseError as e:
            stmts, failed = self._before(text, open_, e), e
        reply, error = self._execute(text, stmts, port)
        if error is not None and not open_ and self.ctl.buffer_holder is port:
            # [INF] a line that opened a buffer and then failed (``OPEN ROT CLEAR CLOSE``)
            # leaves it closed, as its CLOSE meant: later lines are not stored by surprise
            self.ctl.close_buffers(port)
        if error is None and failed is not None:
            error = failed.pmac_error or "ERR003"
            name = failed.details.get("not_simulated") or not_simulated.which(
                text, failed.details.get("column", 1), getattr(failed, "statement_start", None))
            if name is not None:
                self.detail = ("not_simulated", not_simulated.message(name))
            else:
                self.detail = ("parse_error", _where(failed))
        return reply, error

    @staticmethod
    def _before(text: str, open_: bool, e: ParseError) -> list[tuple[Any, int, int]]:
        """The statements before the blank-delimited command where parsing failed (none if
        they do not parse)."""
        cut = not_simulated.command_start(text, e.details.get("column", 1))
        while cut > 0:
            try:
                before = parse_line(text[:cut], open_=open_)
                return before if all(_is_report(item[0]) for item in before) else []
            except ParseError as again:
                new = not_simulated.command_start(text[:cut], again.details.get("column", 1))
                if new >= cut:
                    break
                cut = new
        return []

    def _execute(
        self, text: str, stmts: list[tuple[Any, int, int]], port: Port
    ) -> tuple[str, str | None]:
        ctl = self.ctl
        out: list[str] = []
        group: list[tuple[Any, int, int]] = []
        try:
            for item in stmts:
                stmt = item[0]
                if isinstance(stmt, st.PROGRAM_TYPES):
                    if ctl.buffer_holder is port:
                        group.append(item)
                        continue
                    if isinstance(stmt, st.Assign) and not stmt.synchronous:
                        self._assign_now(stmt, port)
                        continue
                    if getattr(stmt, "run_online", None) is None:
                        raise CommandError("ERR005")
                elif ctl.buffer_holder is port and getattr(stmt, "program_form", False):
                    raise NotSimulated(f"{type(stmt).__name__} in a motion program",
                                       pmac_error="ERR003")
                self._store(text, group, port)
                self._online(stmt, port, out)
            self._store(text, group, port)
        except CommandError as e:
            return "\r".join(out), e.code
        except MotionSimError as e:
            self.detail = (e.code, e.message)
            return "\r".join(out), e.pmac_error or "ERR003"
        return "\r".join(out), None

    # -- buffered lines -------------------------------------------------------------------

    def _store(self, text: str, group: list[tuple[Any, int, int]], port: Port) -> None:
        if not group:
            return
        line_text = text[group[0][1] : group[-1][2]]
        stmts = [g[0] for g in group]
        group.clear()
        if self.ctl.programs.editing(port) is not None:
            self.ctl.store_program_line(compile_statements(line_text, stmts))
            return
        cs = self.ctl.coord_system(port.state["cs"])
        if cs.rotary is None:
            raise CommandError("ERR006")
        line = compile_statements(line_text, stmts)
        self.ctl.store_line(cs, line)

    def _assign_now(self, stmt: st.Assign, port: Port) -> None:
        ctl = self.ctl
        cs = port.state["cs"]
        n = int(stmt.target.index(ctl.vars, cs))
        ctl.vars.write(stmt.target.kind, n, stmt.value(ctl.vars, cs), cs)

    # -- on-line commands -----------------------------------------------------------------

    def _online(self, stmt: Any, port: Port, out: list[str]) -> None:
        ctl = self.ctl
        state = port.state
        run = getattr(stmt, "run_online", None)
        if run is not None:  # a command family that runs itself (MACRO stations, ranges...)
            run(ctl, state, out)
            return
        t = type(stmt)
        if t is st.AddressCS:
            if stmt.cs is None:
                out.append(str(state["cs"]))
                return
            if not 1 <= stmt.cs <= N_CS:
                raise CommandError("ERR003")
            changed = stmt.cs != state["cs"]
            state["cs"] = stmt.cs
            rot = ctl.coord_system(stmt.cs).rotary
            if changed and rot is not None and ctl.buffer_holder is port and ctl.rotary_open():
                # seed 000: a *change* of the addressed CS re-evaluates BREQ; ``&1`` with CS 1
                # already addressed changes nothing (no BREQ pulse per poll)
                rot.reevaluate()
        elif t is st.AddressMotor:
            if stmt.motor is None:
                out.append(str(state["motor"]))
                return
            if not 1 <= stmt.motor <= N_MOTORS:
                raise CommandError("ERR003")
            state["motor"] = stmt.motor
        elif isinstance(stmt, motor_st.MOTOR_TYPES):
            ctl.motor_command(stmt, state["motor"])
        elif t is motor_st.MotorGroup:
            if stmt.group is None:
                out.append(str(state.get("group", 0)))
                return
            if not 0 <= stmt.group < N_MOTORS // 8:
                raise CommandError("ERR003")
            state["group"] = stmt.group
        elif t is st.DefineRotary:
            ctl.define_rotary(state["cs"], stmt.words)
        elif t is st.DeleteRotary:
            ctl.delete_rotary(state["cs"])
        elif t is st.DefineGather:
            ctl.define_gather(stmt.words)
        elif t is st.DeleteGather:
            ctl.delete_gather()
        elif t is st.DefineLookahead:
            ctl.define_lookahead(state["cs"], stmt.segments, stmt.outputs)
        elif t is st.DeleteLookahead:
            ctl.delete_lookahead(state["cs"])
        elif t is st.OpenRotary:
            ctl.open_rotary(port)
        elif t is st.OpenProgram:
            ctl.open_program(stmt.n, port)
        elif t is st.Close:
            ctl.close_buffers(port)
        elif t is st.ProgramPointer:
            ctl.point_program(state["cs"], stmt.program)
        elif t is st.Run:
            ctl.run(state["cs"], pointer=None)
        elif t is st.Step:
            ctl.run(state["cs"], pointer=None, single_step=True)
        elif t is st.Quit:
            ctl.quit(state["cs"])
        elif t is st.MFlush:
            ctl.mflush(state["cs"])
        elif t is st.Hold:
            ctl.coord_system(state["cs"]).hold()
        elif t is st.Abort:
            ctl.abort(state["cs"])
        elif t is st.Query:
            out.append(self._query(stmt.what, port))
        elif t is st.FeedOverride:
            ctl.coord_system(state["cs"]).set_feed_override(stmt.percent)
        elif t is st.VarQuery:
            # I9 bit 0 (PSRM I9, spec §9.8): 0 reports the value only (``5``), 1 the whole
            # statement (``I16=5``); bit 1: address-type I-variables in hex (``$78400``).
            i9 = int(ctl.vars.I(9))
            numbers = stmt.numbers()
            if any(not 0 <= n < 8192 for n in numbers):
                raise CommandError("ERR003")
            for n in numbers:
                raw = ctl.vars.read(stmt.kind, n, state["cs"])
                value = format_ivar(n, raw, i9) if stmt.kind == "I" else format_value(raw)
                out.append(f"{stmt.kind}{n}={value}" if i9 & 1 else value)
        elif t is st.VarDefault:
            for n in range(stmt.first, stmt.last + 1):
                ctl.vars.set_default(n)
        elif t is card_commands.Save:
            card_commands.save(ctl)
        elif t is card_commands.Reset:
            card_commands.schedule_reset(ctl, stmt.factory)
        elif t is list_commands.ListBuffer:
            out.extend(list_commands.run(stmt, ctl, port))
        elif t is mvar_defs.MDefine:
            ctl.vars.mvars.define(stmt.first, stmt.last, stmt.definition)
        elif t is st.MDefinitionQuery:
            # one definition per line; I9 bit 0 = 1: as a statement ``M1->Y:$78802,8``
            full = int(ctl.vars.I(9)) & 1
            for n in stmt.numbers():
                text = mvar_defs.report(ctl.vars.mvars.definition(n))
                out.append(f"M{n}->{text}" if full else text)
        elif t is program_counter.ProgramCounter:
            out.append(program_counter.report(stmt, ctl, state["cs"]))
        elif t is memory_commands.MemoryRead:
            out.append(memory_commands.read(stmt, ctl.vars.mvars))
        elif t is memory_commands.MemoryWrite:
            memory_commands.write(stmt, ctl.vars.mvars)
        elif t is plc_st.ClearAllPlcs:
            ctl.plcs.clear_all()
        elif t is plc_st.OpenPlc:
            ctl.plcs.open(stmt.n, port, stmt.compiled)
            return
        elif t is plc_st.EnablePlc:
            ctl.plcs.set_enabled(stmt.numbers, stmt.enable, stmt.compiled)
        elif t is plc_st.Clear:
            if ctl.programs.editing(port) is None:
                raise CommandError("ERR005")  # CLEAR needs an open buffer [INF]
            ctl.programs.clear()
        elif hasattr(stmt, "online"):  # commands that carry their action (card_words)
            stmt.online(ctl, port, out)
        else:  # pragma: no cover - every parsed statement type is handled above
            raise CommandError("ERR003")

    def _query(self, what: str, port: Port) -> str:
        ctl = self.ctl
        cs_n = port.state["cs"]
        cs = ctl.coord_system(cs_n)
        if what == "%":
            return format_value(cs.feed_override)
        if what == "PR":
            return str(cs.rotary.lines_ahead if cs.rotary is not None else 0)
        if what == "??":
            return _hex_words(*cs.status_words())
        if what == "?":
            return _hex_words(*ctl.motor_status(port.state["motor"]))
        if what == "???":
            return _hex_words(ctl.background.global_status_word1(), 0)
        if what == "SIZE":
            return str(ctl.size_words())
        if what == "VER":
            return VERSION
        if what == "CID":
            return CARD_ID
        if what == "CPU":
            return CPU
        if what == "TYPE":
            return TYPE
        if what == "VID":
            return "1"
        if what in ("P", "V", "F"):
            return format_value(ctl.motor_report(port.state["motor"], what))
        raise CommandError("ERR003")


__all__ = ["CommandError", "Terminal"]
