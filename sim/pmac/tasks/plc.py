"""Turbo PMAC interpreted PLC programs 0-31: storage, entry, enable/disable, one scan.

What is modelled (seed 003; TUM p237, p253, p376; TSRM p39, p381, p422-424; spec §9.5):

* **Entry.** ``OPEN PLC n`` opens PLC ``n`` for entry on one port (ERR007 while any buffer is
  open); ``CLEAR`` erases it; each following line is parsed
  (:mod:`motionsim.sim.pmac.language.plc_parser`)
  and appended; ``CLOSE`` ends entry. A line that does not parse answers ERR003 and is not stored.
  The edit works on a copy: the PLC keeps its old program until a structurally complete
  ``CLOSE``; ``CLOSE`` with an unmatched ``IF`` / ``WHILE`` answers ERR009 ("program
  structural error") and the buffer stays open ``[INF]``. An ``ELSE``/``ENDIF``/``ENDWHILE``
  without its opener is refused on its own line with ERR009, as in a motion program: the
  structure is the one of :mod:`..buffers.flow` in its PLC context (no one-line forms,
  ``AND`` / ``OR`` condition lines), each statement one instruction (:func:`plc_instruction`).
* **Enable.** ``ENABLE PLC n`` / ``DISABLE PLC n`` (lists, ranges, also from inside a PLC)
  emit ``plc`` events. ``OPEN PLC n`` disables PLC ``n`` while it is edited; it runs again only
  after ``CLOSE`` and ``ENABLE`` (spec §9.5 ``[INF]``). I5 decides which classes may run: 1/3
  PLC 0 (foreground, every RTI), 2/3 PLCs 1-31 (background). Enabling a PLC that holds no
  program is accepted without error and changes nothing (no ``plc`` event): the manual's page
  for ENABLE PLC was not found, and a real card has nothing to run there ``[INF]``.
* **A scan** runs from where the last one stopped to the end of the program, or to an
  ``ENDWHILE`` whose ``WHILE`` condition was true (the next scan resumes at that ``WHILE``) —
  so ``WHILE (...) ENDWHILE`` waits without blocking the processor (seed 003). A scan
  reports how many statements it executed; :mod:`motionsim.sim.pmac.tasks.cpu` charges processor
  time for
  them.
* ``CMD"..."`` queues the text for the background command interpreter: it is executed as a
  host command line on a port of its own whose ``&n``/``#n`` addressing is not modal (every
  command starts at motor 1, CS 1, TSRM p422); it is not interpreted before the scan ends.
  ``SEND"..."`` sends a line to the host: it is recorded as the PLC's ``last_send`` and
  queued for the host port (:mod:`motionsim.sim.pmac.host.messages`).
* ``DISABLE PLC n`` inside PLC ``n`` lets the current scan run to its end (a scan is not
  interrupted by other background work, seed 003); the next scan of ``n`` starts at the top
  once it is enabled again ``[INF]``.
* Assignments to M-variables are the PLC's I/O (``mvar`` events).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ...controller import Port
from ...errors import Conflict, NotFound, ParseError
from ..buffers.flow import I_IF, I_JUMP, I_WHILE, PLC, STRUCTURAL, Structure
from ..language import plc_idioms as idioms
from ..language import plc_parser as pp
from ..language import plc_statements as plc_st
from ..language import statements as st

if TYPE_CHECKING:
    from ..controller import PmacController

#: The PLC's own instructions (its statements; the control flow is the shared
#: :mod:`..buffers.flow` form: ``I_IF`` / ``I_WHILE`` / ``I_JUMP``). ``n`` is the PLC line.
P_SET = 20  # (P_SET, n, kind, index_expr, value_expr)
P_CMD = 21  # (P_CMD, n, text)
P_SEND = 22  # (P_SEND, n, text, port)
P_ENABLE = 23  # (P_ENABLE, n, numbers, enable, compiled)
P_ADDRESS = 24  # (P_ADDRESS, n, "#" or "&", number, by_p: the number is P-variable number's)
P_RUN = 25  # (P_RUN, n, statement): a command-family statement, run by its on-line row


@dataclass(frozen=True, slots=True)
class PlcProgram:
    """A compiled PLC program: ``lines`` as entered, ``ops`` the instructions of its
    :class:`~..buffers.flow.Code` (jump targets resolved)."""

    lines: tuple[str, ...]
    ops: tuple[tuple[Any, ...], ...]


def plc_instruction(s: Any, n: int) -> list[Any]:
    """The instruction of one PLC statement that is not control flow (the PLC's ``leaf`` of
    the shared structure; PLCs have no moves)."""
    t = type(s)
    if t is st.Assign:
        return [P_SET, n, s.target.kind, s.target.index, s.value]
    if t is idioms.Command or (t is st.Message and s.kind == "CMD"):
        return [P_CMD, n, s.text]
    if t is idioms.SendText or t is st.Message:
        return [P_SEND, n, s.text, s.port]
    if t is idioms.Address:
        return [P_ADDRESS, n, s.kind, s.n, s.by_p]
    if t is plc_st.EnablePlc:
        return [P_ENABLE, n, s.numbers, s.enable, s.compiled]
    assert isinstance(s, pp.FAMILY_STATEMENTS), t  # parse_plc_line returns only these
    return [P_RUN, n, s]


def plc_structure() -> Structure:
    """An empty PLC program being built (the PLC context of the one structure)."""
    return Structure(context=PLC, leaf=plc_instruction)


def _program(structure: Structure, lines: Iterable[str]) -> PlcProgram:
    code = structure.finish()
    return PlcProgram(tuple(lines), tuple(tuple(i) for i in code.instrs))


def compile_plc(text: str) -> PlcProgram:
    """Parse and compile a whole PLC program text (one statement line per text line).

    Raises:
        ParseError: ``line`` (1-based), ``column``, ERR003 (ERR009 for an unmatched block).
    """
    b = plc_structure()
    lines = text.splitlines()
    kept: list[str] = []
    for i, line in enumerate(lines):
        try:
            stmts = pp.parse_plc_line(line)
            if any(isinstance(s, st.Close | plc_st.Clear) for s, _ in stmts):
                bad = next(c for s, c in stmts if isinstance(s, st.Close | plc_st.Clear))
                raise ParseError(
                    "OPEN/CLEAR/CLOSE do not belong in the program text",
                    column=bad,
                    text=line,
                    pmac_error="ERR003",
                )
            if line.strip():
                b.feed_statements(line, stmts)
        except ParseError as e:
            raise e.at(line=i + 1) from None
        if line.strip():
            kept.append(line)
    problem = b.unclosed()
    if problem is not None:
        raise ParseError(
            problem, line=max(1, len(lines)), column=1, text=lines[-1] if lines else "",
            pmac_error=STRUCTURAL,
        )
    return _program(b, kept)


class Plc:
    """One PLC program slot and its run state."""

    __slots__ = ("n", "program", "enabled", "pc", "scans", "last_scan_t", "last_statements",
                 "last_send", "cs", "motor", "mid_scan", "held", "so_far")

    def __init__(self, n: int) -> None:
        self.n = n
        self.program: PlcProgram | None = None
        self.enabled = False
        self.pc = 0
        self.scans = 0
        self.last_scan_t: float | None = None
        self.last_statements = 0
        self.last_send: str | None = None
        #: The program's own addressing (``ADDRESS&n`` / ``ADDRESS#n``), default &1 #1.
        self.cs = 1
        self.motor = 1
        #: A long scan worked through in slices (:data:`SCAN_SLICE`) is not over yet; the
        #: ``CMD"..."`` texts it issued so far wait in ``held`` for its end.
        self.mid_scan = False
        self.held: list[tuple[str, int, int]] = []
        self.so_far = 0  # statements of the sliced scan so far

    def to_dict(self, permitted: bool, editing: bool) -> dict[str, Any]:
        if editing:
            state = "open"
        elif self.enabled:
            state = "running" if permitted else "enabled"  # enabled but I5 forbids its class
        else:
            state = "disabled"
        return {
            "plc": self.n,
            "state": state,
            "enabled": self.enabled,
            "lines": len(self.program.lines) if self.program else 0,
            "scans": self.scans,
            "last_scan_t": self.last_scan_t,
            "last_scan_statements": self.last_statements,
            "last_send": self.last_send,
        }


class PlcTable:
    """PLC programs 0..31 of one controller, their entry and their scans."""

    def __init__(self, ctl: PmacController) -> None:
        self.ctl = ctl
        self.plcs = [Plc(n) for n in range(plc_st.N_PLCS)]
        #: Compiled PLCs 0..31 (``OPEN PLCC n``): the source a host downloads, run as compiled.
        self.compiled = [Plc(n) for n in range(plc_st.N_PLCS)]
        self._edit_table = self.plcs  # the table the open PLC belongs to
        self._edit: tuple[Port, int, Structure, list[str]] | None = None
        self._rr = 0  # background round robin: the last PLC scanned
        self._cmd_port = Port("plc-cmd")
        #: ``(compiled, n)`` of the PLC being scanned: its own DISABLE keeps what it issued.
        self._scanning: tuple[bool, int] | None = None

    # -- entry ----------------------------------------------------------------------------

    def editing(self, port: Port | None = None) -> int | None:
        """The PLC open for entry (on ``port`` if given), or None."""
        e = self._edit
        if e is None or (port is not None and e[0] is not port):
            return None
        return e[1]

    def open(self, n: int, port: Port, compiled: bool = False) -> None:
        """``OPEN PLC n`` (``OPEN PLCC n`` with ``compiled``)."""
        ctl = self.ctl
        if ctl.buffer_holder is not None:
            raise Conflict("another buffer is open: CLOSE first", pmac_error="ERR007")
        table = self.compiled if compiled else self.plcs
        plc = table[n]
        self.set_enabled((n,), False, compiled)
        self._edit_table = table
        b = plc_structure()
        lines: list[str] = []
        if plc.program is not None:
            for line in plc.program.lines:
                b.feed_statements(line, pp.parse_plc_line(line))
                lines.append(line)
        self._edit = (port, n, b, lines)
        ctl.buffer_holder = port

    def enter_line(self, text: str, port: Port) -> tuple[str, str | None, str | None]:
        """A terminal line while ``port`` holds a PLC open: store it, or CLEAR / CLOSE.

        Returns ``(reply, error, rest)``: ``rest`` is the text after a ``CLOSE`` (on-line
        commands again), else None.
        """
        assert self._edit is not None
        _, n, b, lines = self._edit
        try:
            stmts = pp.parse_plc_line(text)
        except ParseError as e:
            return "", e.pmac_error or "ERR003", None
        cleared = False
        body: list[tuple[Any, int]] = []
        start = 0  # where the stored text of this line begins (after a CLEAR)
        close: int | None = None  # the column of a CLOSE
        for stmt, col in stmts:
            if isinstance(stmt, plc_st.Clear):
                cleared, body, start = True, [], col - 1 + len("CLEAR")
            elif isinstance(stmt, st.Close):
                close = col
                break
            else:
                body.append((stmt, col))
        if cleared:
            b, lines = plc_structure(), []
        if body:
            try:
                b.copy().feed_statements(text, body)  # a refused line changes nothing
            except ParseError as e:
                return "", e.pmac_error or "ERR003", None
            b.feed_statements(text, body)
            lines.append(text[start : len(text) if close is None else close - 1].strip())
        self._edit = (port, n, b, lines)
        if close is None:
            return "", None, None
        if b.unclosed() is not None:  # CLOSE of an unmatched block: the PLC stays open
            return "", STRUCTURAL, None
        program = _program(b, lines)
        self._edit_table[n].program = program if program.ops else None
        self._edit_table[n].pc = 0
        self._edit = None
        self.ctl.buffer_holder = None
        return "", None, text[close - 1 + len("CLOSE") :]

    def abandon(self, port: Port) -> None:
        """The port went away with a PLC open: the edit is dropped, the old program kept."""
        if self._edit is not None and self._edit[0] is port:
            self._edit = None
            if self.ctl.buffer_holder is port:
                self.ctl.buffer_holder = None

    def load(self, n: int, text: str, program: Any = None) -> None:
        """Replace PLC ``n``'s program with ``text`` at once (REST); all or nothing.
        ``program``: ``compile_plc(text)`` already done (off the event loop), or None.

        Raises:
            NotFound: no PLC ``n``.
            Conflict: the PLC is open for entry on a port (ERR007).
            ParseError: line, column; nothing changed.
        """
        plc = self.plc(n)
        if self.editing() == n:
            raise Conflict(f"PLC {n} is open for entry", pmac_error="ERR007")
        program = compile_plc(text) if program is None else program
        plc.program = program if program.ops else None
        plc.pc = 0

    def clear_all(self) -> None:
        """``CLEAR ALL PLCS``: every PLC program buffer erased; an enabled PLC stops (its
        ``plc`` event says ``disabled``) as there is nothing left to scan ``[INF]``.

        Raises:
            Conflict: a PLC is open for entry (ERR007) ``[INF]``; nothing changed.
        """
        if self.editing() is not None:
            raise Conflict(f"PLC {self.editing()} is open for entry", pmac_error="ERR007")
        self.set_enabled([p.n for p in self.plcs], False)
        for plc in self.plcs:
            plc.program = None
            plc.pc = 0

    def delete_compiled(self, numbers: Iterable[int]) -> None:
        """``DELETE PLCC``: compiled PLCs ``numbers`` erased; an enabled one stops first.

        Raises:
            Conflict: one of them is open for entry (ERR007) ``[INF]``; nothing changed.
        """
        numbers = tuple(numbers)
        if self._edit is not None and self._edit_table is self.compiled \
                and self._edit[1] in numbers:
            raise Conflict(f"PLCC {self._edit[1]} is open for entry", pmac_error="ERR007")
        self.set_enabled(numbers, False, compiled=True)
        for n in numbers:
            plcc = self.compiled[n]
            plcc.program = None
            plcc.pc = 0

    def plc(self, n: int) -> Plc:
        if isinstance(n, bool) or not isinstance(n, int) or not 0 <= n < plc_st.N_PLCS:
            raise NotFound(f"no PLC {n!r} (0..{plc_st.N_PLCS - 1})")
        return self.plcs[n]

    # -- enable / disable -----------------------------------------------------------------

    def set_enabled(self, numbers: Iterable[int], enable: bool, compiled: bool = False) -> None:
        """``ENABLE PLC`` / ``DISABLE PLC``: ``plc`` events for PLCs whose state changes
        (``ENABLE PLCC`` / ``DISABLE PLCC``: the same with ``compiled=True`` in the event)."""
        changed = False
        table = self.compiled if compiled else self.plcs
        extra = {"compiled": True} if compiled else {}
        for n in numbers:
            self.plc(n)  # NotFound outside 0..31
            plc = table[n]
            if enable and (plc.program is None
                           or (self.editing() == n and self._edit_table is table)):
                continue
            if plc.enabled != enable:
                plc.enabled = enable
                if not enable:
                    plc.pc = 0
                    if (compiled, n) != self._scanning:  # a sliced scan ends with it
                        plc.mid_scan, plc.held = False, []
                changed = True
                self.ctl.log.emit("plc", plc=n, state="enabled" if enable else "disabled",
                                  **extra)
            if not enable and (compiled, n) != self._scanning:
                self.ctl.commands.end((compiled, n))  # its queued CMD work ends too
        if changed:
            self.ctl.background.poke()

    # -- what may run -----------------------------------------------------------------------

    def i5(self) -> int:
        return int(self.ctl.vars.I(5)) & 3

    def foreground(self) -> Plc | None:
        """PLC 0 if it is enabled and I5 permits foreground PLCs."""
        p = self.plcs[0]
        return p if p.enabled and self.i5() & 1 else None

    def any_background(self) -> bool:
        if not self.i5() & 2:
            return False
        return any(p.enabled for p in self.plcs[1:]) or any(p.enabled for p in self.compiled[1:])

    def foreground_compiled(self) -> Plc | None:
        """PLCC 0 if it is enabled and I5 permits foreground PLCs (it runs after PLC 0)."""
        p = self.compiled[0]
        return p if p.enabled and self.i5() & 1 else None

    def background_compiled(self) -> list[Plc]:
        """The enabled PLCCs 1-31, low to high: one scan of each between two interpreted-PLC
        scans (PUM-V p238; spec §9.5), if I5 permits."""
        if not self.i5() & 2:
            return []
        return [p for p in self.compiled[1:] if p.enabled]

    def next_background(self) -> Plc | None:
        """The next enabled PLC 1-31 in turn (one per background cycle), if I5 permits."""
        if not self.i5() & 2:
            return None
        plcs = self.plcs
        for k in range(1, plc_st.N_PLCS):
            n = (self._rr + k - 1) % (plc_st.N_PLCS - 1) + 1
            if plcs[n].enabled:
                self._rr = n
                return plcs[n]
        return None

    # -- one scan ---------------------------------------------------------------------------

    def scan(self, plc: Plc, budget: int | None = None) -> int:
        """Run one scan of ``plc`` now, or at most ``budget`` statements of it; returns the
        number of statements executed.

        A scan cut by its budget leaves ``plc.mid_scan`` set and goes on from there at the
        next call: the background task works a long scan through in slices, as the card's
        interrupts cut it (a scan still runs to its end before the next PLC's, seed 003);
        its ``CMD"..."`` texts are issued when the whole scan ends.
        """
        prog = plc.program
        source = (self.compiled[plc.n] is plc, plc.n)
        if prog is None:
            plc.mid_scan, plc.held = False, []
            return 0
        if not plc.mid_scan and self.ctl.commands.halted(source):
            return 0  # waiting for command-queue room
        self._scanning = source
        ops = prog.ops
        vars_ = self.ctl.vars
        pc = plc.pc
        end = len(ops)
        count = 0
        limit = -1 if budget is None else budget
        cut = False
        cmds: list[tuple[str, int, int]] = []
        while pc < end:
            if count == limit:
                cut = True
                break
            op = ops[pc]
            code = op[0]
            count += 1
            cs = plc.cs
            if code == P_SET:
                idx = op[3]
                k = int(idx.const if idx.const is not None else idx.fn(vars_, cs))
                vars_.write(op[2], k, op[4](vars_, cs), cs)
                pc += 1
            elif code in (I_IF, I_WHILE):
                pc = pc + 1 if op[2](vars_, cs) else op[3]
            elif code == I_JUMP:
                pc = op[2]
                if op[3]:  # ENDWHILE's jump back to its WHILE ends the scan (seed 003)
                    break
            elif code == P_CMD:
                cmds.append((op[2], cs, plc.motor))
                pc += 1
            elif code == P_SEND:
                self._send(plc, op[2], op[3])
                pc += 1
            elif code == P_ADDRESS:
                # ADDRESS&P{n} / ADDRESS#P{n}: the CS / motor is P{n}'s value now [BK]
                k = int(vars_.read("P", op[3])) if op[4] else op[3]
                if op[2] == "&":
                    plc.cs = k
                else:
                    plc.motor = k
                pc += 1
            elif code == P_RUN:
                self.ctl.run_statement(op[2], cs, plc.motor)
                pc += 1
            else:  # P_ENABLE
                self.set_enabled(op[2], op[3], op[4])  # its own DISABLE: the scan still ends
                pc += 1
        else:
            pc = 0
        self._scanning = None
        if not plc.enabled:  # its own DISABLE: the scan still ends; the next starts at the top
            cut = False
        else:
            plc.pc = pc
        if cut:
            plc.so_far = (plc.so_far if plc.mid_scan else 0) + count
            plc.mid_scan = True
            plc.held += cmds
            return count
        count_all = count
        if plc.mid_scan:
            plc.mid_scan = False
            count_all += plc.so_far
            cmds, plc.held = plc.held + cmds, []
        plc.scans += 1
        plc.last_scan_t = self.ctl.env.now
        plc.last_statements = count_all
        if cmds:
            self.ctl.issue_program_commands(source, cmds)
        return count

    def _send(self, plc: Plc, text: str, port: str) -> None:
        """``SEND{port}"text"``: the PLC's ``last_send``, a ``plc_send`` event and the line
        queued for the host port (:meth:`PmacController.send_message`)."""
        plc.last_send = text
        compiled = self.compiled[plc.n] is plc
        extra = {"compiled": True} if compiled else {}
        self.ctl.log.emit("plc_send", plc=plc.n, port=port or "host", text=text, **extra)
        self.ctl.send_message(f"plcc{plc.n}" if compiled else f"plc{plc.n}", port, text)

    def _item(self, p: Plc, i5: int, editing: int | None) -> dict[str, Any]:
        """``p``'s API shape: its state as I5, entry and the watchdog make it."""
        item = p.to_dict(bool(i5 & (1 if p.n == 0 else 2)), editing == p.n)
        if self.ctl.halted:
            item["state"] = "stopped"  # the watchdog tripped: nothing runs
        return item

    def _editing_in(self, table: list[Plc]) -> int | None:
        return self.editing() if self._edit_table is table else None

    def to_list(self, compiled: bool = False) -> list[dict[str, Any]]:
        """The PLCs holding a program, enabled or open (``compiled``: the PLCCs, each marked
        ``"compiled": True``)."""
        i5 = self.i5()
        table = self.compiled if compiled else self.plcs
        editing = self._editing_in(table)
        out = [
            self._item(p, i5, editing)
            for p in table
            if p.program is not None or p.enabled or editing == p.n
        ]
        if compiled:
            for item in out:
                item["compiled"] = True
        return out

    def describe(self, n: int) -> dict[str, Any]:
        """PLC ``n`` in the API's detail shape, with its program lines. Raises NotFound."""
        plc = self.plc(n)
        out = self._item(plc, self.i5(), self._editing_in(self.plcs))
        out["program"] = list(plc.program.lines) if plc.program is not None else []
        return out


__all__ = ["PlcProgram", "PlcTable", "compile_plc"]
