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

from ...controller import Port
from ...errors import MotionSimError, NotSimulated, ParseError
from ..buffers.program import compile_statements
from ..card import comp_tables
from ..language import statements as st
from ..language.parser import parse_line
from ..language.plc_parser import parse_plc_line
from . import commands, not_simulated
from .commands import CommandError
from .control_chars import ControlCharacters, split_controls

if TYPE_CHECKING:
    from ..controller import PmacController

_OPEN_PLC = re.compile(r"OPEN\s*PLCC?\s*\d+", re.IGNORECASE)

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
        if comp_tables.FILLING in port.state:  # DEFINE COMP: these are its entries
            try:
                comp_tables.fill(ctl, port.state, text)
            except MotionSimError as e:
                self.detail = (e.code, e.message)
                return "", e.pmac_error or "ERR003"
            return "", None
        if ctl.plcs.editing(port) is not None:
            # OPEN PLC: lines go into the PLC; what follows a CLOSE is on-line again.
            reply, error, rest = ctl.plcs.enter_line(text, port)
            if error == "ERR003" and self._online_only(text):
                return self._run(text, port, open_=False)  # not PLC text: on-line commands
            if error is not None and self.detail is None:
                self.detail = self._plc_detail(text)
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
    def _plc_detail(text: str) -> tuple[str, str] | None:
        """Why a PLC line was refused, for people (the PLC entry answers only the code)."""
        try:
            parse_plc_line(text)
        except ParseError as e:
            name = e.details.get("not_simulated") or not_simulated.which(
                text, e.details.get("column", 1), getattr(e, "statement_start", None))
            if name is not None:
                return "not_simulated", not_simulated.message(name)
            return "parse_error", _where(e)
        return None

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
        return bool(stmts) and all(commands.acts_with_plc_open(item[0]) for item in stmts)

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
                return before if all(commands.is_report(item[0]) for item in before) else []
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
        call = commands.Call(ctl, port, port.state, out)
        try:
            for item in stmts:
                stmt = item[0]
                if isinstance(stmt, st.PROGRAM_TYPES):
                    if ctl.buffer_holder is port:
                        group.append(item)
                        continue
                elif ctl.buffer_holder is port and commands.has_program_form(stmt):
                    raise NotSimulated(f"{type(stmt).__name__} in a motion program",
                                       pmac_error="ERR003")
                self._store(text, group, port)
                commands.run(call, stmt)
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


__all__ = ["CommandError", "Terminal"]
