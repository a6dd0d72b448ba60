"""Turbo PMAC interpreted PLC programs 0-31: storage, entry, enable/disable, one scan.

What is modelled (seed 003; TUM p237, p253, p376; TSRM p39, p381, p422-424; spec §9.5):

* **Entry.** ``OPEN PLC n`` opens PLC ``n`` for entry on one port (ERR007 while any buffer is
  open); ``CLEAR`` erases it; each following line is parsed
  (:mod:`motionsim.sim.pmac.language.plc_parser`)
  and appended; ``CLOSE`` ends entry. A line that does not parse answers ERR003 and is not stored.
  The edit works on a copy: the PLC keeps its old program until a structurally complete
  ``CLOSE``; ``CLOSE`` with an unmatched ``IF`` / ``WHILE`` answers ERR009 ("program
  structural error") and the buffer stays open ``[INF]``. An ``ELSE``/``ENDIF``/``ENDWHILE``
  without its opener is refused on its own line (ERR003).
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
from ..buffers.flow import STRUCTURAL
from ..language import flow_statements as fl
from ..language import plc_idioms as idioms
from ..language import plc_parser as pp
from ..language import plc_statements as plc_st
from ..language import statements as st
from ..language.conditions import any_of_all

if TYPE_CHECKING:
    from ..controller import PmacController

# Operation codes of a compiled PLC program.
OP_SET = 0  # (OP_SET, kind, index_expr, value_expr)
OP_IF = 1  # (OP_IF, cond, pc_if_false)
OP_JUMP = 2  # (OP_JUMP, pc)                      (ELSE: skip the else branch)
OP_WHILE = 3  # (OP_WHILE, cond, pc_after_endwhile)
OP_ENDWHILE = 4  # (OP_ENDWHILE, pc_of_while)     ends the scan
OP_CMD = 5  # (OP_CMD, text)
OP_SEND = 6  # (OP_SEND, text)
OP_ENABLE = 7  # (OP_ENABLE, numbers, enable, compiled)
OP_ADDRESS = 8  # (OP_ADDRESS, "#" or "&", n)
OP_RUN = 9  # (OP_RUN, statement): a command-family statement, run by its on-line row


class StructureError(Exception):
    """Unmatched IF / WHILE at CLOSE."""


@dataclass(frozen=True, slots=True)
class PlcProgram:
    """A compiled PLC program: ``lines`` as entered, ``ops`` with resolved jump targets."""

    lines: tuple[str, ...]
    ops: tuple[tuple[Any, ...], ...]


class _Builder:
    """Turns a PLC's statements into ops, resolving IF/ELSE/ENDIF and WHILE/ENDWHILE jumps.

    PLC rules (PUM p162; PSRM p313, p357): no one-line forms, so the block an ``IF`` /
    ``WHILE`` / ``ELSE`` opens runs on over the following statements and lines until its
    ``ENDIF`` / ``ENDWHILE``; ``AND`` / ``OR`` lines extend the condition of an ``IF`` /
    ``WHILE`` that ended the line above. A structural error (``ENDIF`` with no open ``IF``,
    ...) is ERR009, the card's "program structural error" (PSRM p25-26, the I6 table), as in
    a motion program (:data:`motionsim.sim.pmac.buffers.flow.STRUCTURAL`).
    """

    def __init__(self) -> None:
        self.ops: list[list[Any]] = []
        self.stack: list[tuple[str, int, int | None]] = []  # (kind, pc, else_pc)
        #: OR-groups of AND-ed conditions of the IF/WHILE that ``AND``/``OR`` lines may extend.
        self.cond_at: int | None = None
        self.groups: list[list[Any]] = []

    def copy(self) -> _Builder:
        b = _Builder()
        b.ops = [list(op) for op in self.ops]
        b.stack = list(self.stack)
        b.cond_at = self.cond_at
        b.groups = [list(g) for g in self.groups]
        return b

    def _extend(self, s: fl.CondLine, col: int, text: str) -> None:
        """``AND (...)`` / ``OR (...)`` line: extend the condition of the IF/WHILE above."""
        if self.cond_at is None:
            raise ParseError(
                f"{s.op} line without an IF or WHILE just above", column=col, text=text,
                pmac_error="ERR003",
            )
        if s.op == "AND":
            self.groups[-1].append(s.cond)
        else:
            self.groups.append([s.cond])
        self.ops[self.cond_at][1] = any_of_all(self.groups)

    def add_line(self, text: str, stmts: list[tuple[Any, int]]) -> None:
        for stmt, col in stmts:
            self.add(stmt, col, text)

    def _structural(self, message: str, col: int, text: str) -> ParseError:
        return ParseError(message, column=col, text=text, pmac_error=STRUCTURAL)

    def add(self, s: Any, col: int, text: str) -> None:
        ops, stack = self.ops, self.stack
        t = type(s)
        if t is fl.CondLine:
            self._extend(s, col, text)
            return
        if t is fl.If or t is fl.While:
            self.cond_at = None if s.inline else len(ops)
            self.groups = [[s.cond]]
        else:
            self.cond_at = None
        if t is st.Assign:
            ops.append([OP_SET, s.target.kind, s.target.index, s.value])
        elif t is fl.If:
            stack.append(("IF", len(ops), None))
            ops.append([OP_IF, s.cond, None])
        elif t is fl.Else:
            if not stack or stack[-1][0] != "IF" or stack[-1][2] is not None:
                raise self._structural("ELSE without IF", col, text)
            kind, pc, _ = stack.pop()
            stack.append((kind, pc, len(ops)))
            ops.append([OP_JUMP, None])
            ops[pc][2] = len(ops)
        elif t is fl.EndIf:
            if not stack or stack[-1][0] != "IF":
                raise self._structural("ENDIF without IF", col, text)
            _, pc, else_pc = stack.pop()
            if else_pc is None:
                ops[pc][2] = len(ops)
            else:
                ops[else_pc][1] = len(ops)
        elif t is fl.While:
            stack.append(("WHILE", len(ops), None))
            ops.append([OP_WHILE, s.cond, None])
        elif t is fl.EndWhile:
            if not stack or stack[-1][0] != "WHILE":
                raise self._structural("ENDWHILE without WHILE", col, text)
            _, pc, _ = stack.pop()
            ops.append([OP_ENDWHILE, pc])
            ops[pc][2] = len(ops)
        elif t is idioms.Command or (t is st.Message and s.kind == "CMD"):
            ops.append([OP_CMD, s.text])
        elif t is idioms.SendText or t is st.Message:
            ops.append([OP_SEND, s.text, s.port])
        elif t is idioms.Address:
            ops.append([OP_ADDRESS, s.kind, s.n])
        elif t is plc_st.EnablePlc:
            ops.append([OP_ENABLE, s.numbers, s.enable, s.compiled])
        elif isinstance(s, pp.FAMILY_STATEMENTS):
            ops.append([OP_RUN, s])
        else:  # pragma: no cover - parse_plc_line returns only the types above
            raise ParseError("not a PLC statement", column=col, text=text, pmac_error="ERR003")

    def program(self, lines: Iterable[str]) -> PlcProgram:
        if self.stack:
            kind = self.stack[-1][0]
            raise StructureError(f"{kind} without END{kind}")
        return PlcProgram(tuple(lines), tuple(tuple(op) for op in self.ops))


def compile_plc(text: str) -> PlcProgram:
    """Parse and compile a whole PLC program text (one statement line per text line).

    Raises:
        ParseError: ``line`` (1-based), ``column``, ERR003 (ERR009 for an unmatched block).
    """
    b = _Builder()
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
            b.add_line(line, stmts)
        except ParseError as e:
            raise e.at(line=i + 1) from None
        if line.strip():
            kept.append(line)
    try:
        return b.program(kept)
    except StructureError as e:
        raise ParseError(
            str(e), line=max(1, len(lines)), column=1, text=lines[-1] if lines else "",
            pmac_error=STRUCTURAL,
        ) from None


class Plc:
    """One PLC program slot and its run state."""

    __slots__ = ("n", "program", "enabled", "pc", "scans", "last_scan_t", "last_statements",
                 "last_send", "cs", "motor")

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
        self._edit: tuple[Port, int, _Builder, list[str]] | None = None
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
        b = _Builder()
        lines: list[str] = []
        if plc.program is not None:
            for line in plc.program.lines:
                b.add_line(line, pp.parse_plc_line(line))
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
        trial = b.copy()
        body: list[tuple[Any, int]] = []
        start = 0  # where the stored text of this line begins (after a CLEAR)

        def add_body(end: int) -> None:
            nonlocal lines
            if body:
                trial.add_line(text, body)
                lines = [*lines, text[start:end].strip()]

        for stmt, col in stmts:
            if isinstance(stmt, plc_st.Clear):
                trial = _Builder()
                lines = []
                body = []
                start = col - 1 + len("CLEAR")
            elif isinstance(stmt, st.Close):
                try:
                    add_body(col - 1)
                    program = trial.program(lines)
                except ParseError as e:
                    return "", e.pmac_error or "ERR003", None
                except StructureError:
                    self._edit = (port, n, trial, lines)
                    return "", STRUCTURAL, None
                self._edit_table[n].program = program if program.ops else None
                self._edit_table[n].pc = 0
                self._edit = None
                self.ctl.buffer_holder = None
                return "", None, text[col - 1 + len("CLOSE") :]
            else:
                body.append((stmt, col))
        try:
            add_body(len(text))
        except ParseError as e:
            return "", e.pmac_error or "ERR003", None
        self._edit = (port, n, trial, lines)
        return "", None, None

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

    def scan(self, plc: Plc) -> int:
        """Run one scan of ``plc`` now; returns the number of statements executed."""
        prog = plc.program
        source = (self.compiled[plc.n] is plc, plc.n)
        if prog is None or self.ctl.commands.halted(source):  # waiting for command-queue room
            return 0
        self._scanning = source
        ops = prog.ops
        vars_ = self.ctl.vars
        pc = plc.pc
        end = len(ops)
        count = 0
        cmds: list[tuple[str, int, int]] = []
        while pc < end:
            op = ops[pc]
            code = op[0]
            count += 1
            cs = plc.cs
            if code == OP_SET:
                idx = op[2]
                k = int(idx.const if idx.const is not None else idx.fn(vars_, cs))
                vars_.write(op[1], k, op[3](vars_, cs), cs)
                pc += 1
            elif code == OP_IF:
                pc = pc + 1 if op[1](vars_, cs) else op[2]
            elif code == OP_JUMP:
                pc = op[1]
            elif code == OP_WHILE:
                pc = pc + 1 if op[1](vars_, cs) else op[2]
            elif code == OP_ENDWHILE:
                pc = op[1]
                break
            elif code == OP_CMD:
                cmds.append((op[1], cs, plc.motor))
                pc += 1
            elif code == OP_SEND:
                self._send(plc, op[1], op[2])
                pc += 1
            elif code == OP_ADDRESS:
                if op[1] == "&":
                    plc.cs = op[2]
                else:
                    plc.motor = op[2]
                pc += 1
            elif code == OP_RUN:
                self.ctl.run_statement(op[1], cs, plc.motor)
                pc += 1
            else:  # OP_ENABLE
                self.set_enabled(op[1], op[2], op[3])  # its own DISABLE: the scan still ends
                pc += 1
        else:
            pc = 0
        if plc.enabled:
            plc.pc = pc
        plc.scans += 1
        plc.last_scan_t = self.ctl.env.now
        plc.last_statements = count
        self._scanning = None
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
