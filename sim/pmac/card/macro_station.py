"""MACRO station (Type 1 auxiliary) commands, with no MACRO ring (TSRM p362-371; PSRM p267;
spec §12.8).

Real set-up files carry hundreds of ``MS`` lines; the simulator keeps, per node 0-63, a store
of the station's variables (``MI``/``I`` numbers 0-8191, default 0) and answers as a station
would, so they load ``[INF]`` (spec §12.8: no ring is simulated; the card's ERR008 time-out
answer is not used).

=============================================  ===============================================
``MS{node},{var}`` (``MACROSLAVE``)            the value, one data line
``MS{node},{var}={constant}``                  stored; no data
``MSR{node},{slave var},{local var}``          station variable -> local I/P/Q/M (0-4095)
(``MACROSLVREAD``)                             ``[INF]`` Q in the addressed CS
``MSW{node},{slave var},{local var}``          local variable -> station variable
(``MACROSLVWRITE``)
``MS$$${node}``, ``MS$$$***{node}``            station reset / re-initialise (``$$$***``
                                               clears its variables) ``[INF]``
``MSSAVE{node}``, ``MSCLRF{node}``             accepted, no data
``MSCONFIG{node}[={n}]``                       the configuration number (default 0)
``MSDATE{node}``, ``MSVER{node}``              firmware date / version of the station
=============================================  ===============================================

Blanks are allowed between the parts (``MS $$$0``, ``MS SAVE 4``, ``ms0, i910``). A station
variable is written ``I{n}`` or ``MI{n}``. MSR/MSW are also PLC and motion-program statements
(Diamond's PLCs use ``MSR0,i910,P100``).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ...errors import ParseError
from .variables import format_value

if TYPE_CHECKING:
    from .variables import Variables

N_NODES = 64
#: What ``MSVER`` / ``MSDATE`` answer: a MACRO station's firmware as in the manual's
#: examples (TSRM p368-371) ``[INF]``.
STATION_VERSION = "1.104"
STATION_DATE = "03/27/97"

_NODE = r"\s*(?P<node>\d+)"
_SVAR = r"\s*M?I\s*(?P<svar>\d+)"
_LVAR = r"\s*(?P<lkind>[IPQM])\s*(?P<lvar>\d+)"
#: What follows the ``M`` of an MS command (the tokenizer gives the parser ``M`` alone).
HEAD = re.compile(
    r"(?:ACROSLVREAD|S\s*R)" + _NODE + r"\s*," + _SVAR + r"\s*," + _LVAR
    + r"|(?:ACROSLVWRITE|S\s*W)(?P<wnode>\s*\d+)\s*," + r"\s*M?I\s*(?P<wsvar>\d+)\s*,"
    + r"\s*(?P<wlkind>[IPQM])\s*(?P<wlvar>\d+)"
    + r"|S\s*(?P<op>\$\$\$\*\*\*|\$\$\$|SAVE|CLRF|CONFIG|DATE|VER)(?P<onode>\s*\d+)"
    + r"(?:\s*=\s*(?P<cfg>\d+))?"
    + r"|(?:ACROSLAVE|S)(?P<rnode>\s*\d+)\s*,\s*M?I\s*(?P<rvar>\d+)"
    + r"(?:\s*=\s*(?P<value>-?(?:\d+\.?\d*|\.\d+)|\$[0-9A-Fa-f]+))?",
    re.IGNORECASE,
)


@dataclass(frozen=True, slots=True)
class StationCommand:
    """One MS command: ``op`` is ``read``, ``write``, ``copy_in`` (MSR), ``copy_out`` (MSW),
    or ``$$$``, ``$$$***``, ``SAVE``, ``CLRF``, ``CONFIG``, ``DATE``, ``VER``."""

    op: str
    node: int
    var: int = 0
    value: float | None = None
    local: tuple[str, int] | None = None


@dataclass
class MacroStations:
    """The station variables of nodes 0-63 (``{node: {var: value}}``) and their configs."""

    variables: dict[int, dict[int, float]] = field(default_factory=dict)
    configs: dict[int, int] = field(default_factory=dict)

    def execute(self, cmd: StationCommand, vars_: Variables, cs: int) -> str | None:
        """Run ``cmd``; the data line it answers, or None."""
        node = self.variables.setdefault(cmd.node, {})
        if cmd.op == "read":
            return format_value(node.get(cmd.var, 0.0))
        if cmd.op == "write":
            node[cmd.var] = float(cmd.value or 0.0)
        elif cmd.op == "copy_in":
            kind, n = cmd.local  # type: ignore[misc]
            vars_.write(kind, n, node.get(cmd.var, 0.0), cs)
        elif cmd.op == "copy_out":
            kind, n = cmd.local  # type: ignore[misc]
            node[cmd.var] = vars_.read(kind, n, cs)
        elif cmd.op == "$$$***":
            node.clear()
            self.configs.pop(cmd.node, None)
        elif cmd.op == "CONFIG":
            if cmd.value is None:
                return str(self.configs.get(cmd.node, 0))
            self.configs[cmd.node] = int(cmd.value)
        elif cmd.op == "DATE":
            return STATION_DATE
        elif cmd.op == "VER":
            return STATION_VERSION
        return None  # $$$, SAVE, CLRF: acknowledged


def _num(text: str) -> float:
    return float(int(text[1:], 16)) if text.startswith("$") else float(text)


def parse(match: re.Match[str], text: str) -> StationCommand:
    """The command :data:`HEAD` matched (right after the ``M``) in ``text``.

    Raises:
        ParseError: node out of 0..63, station variable out of 0..8191, local variable out of
            0..4095 (column of the number, ERR003).
    """
    g = match.groupdict()

    def check(name: str, limit: int, what: str) -> int:
        v = int(g[name])
        if v > limit:
            col = match.start(name) + 1 + (len(g[name]) - len(g[name].lstrip()))
            raise ParseError(f"MACRO {what} {v} out of 0..{limit}", column=col, text=text,
                             pmac_error="ERR003")
        return v

    if g["node"] is not None:
        return StationCommand("copy_in", check("node", N_NODES - 1, "node"),
                              check("svar", 8191, "station variable"),
                              local=(g["lkind"].upper(), check("lvar", 4095, "variable")))
    if g["wnode"] is not None:
        return StationCommand("copy_out", check("wnode", N_NODES - 1, "node"),
                              check("wsvar", 8191, "station variable"),
                              local=(g["wlkind"].upper(), check("wlvar", 4095, "variable")))
    if g["op"] is not None:
        cfg = None if g["cfg"] is None else float(g["cfg"])
        return StationCommand(g["op"].upper(), check("onode", N_NODES - 1, "node"), value=cfg)
    node = check("rnode", N_NODES - 1, "node")
    var = check("rvar", 8191, "station variable")
    if g["value"] is None:
        return StationCommand("read", node, var)
    return StationCommand("write", node, var, value=_num(g["value"]))


__all__ = ["HEAD", "MacroStations", "StationCommand", "parse"]
