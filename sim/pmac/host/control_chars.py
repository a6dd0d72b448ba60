"""Control characters: one-byte commands the Turbo PMAC acts on at once (PUM-V p28, p34).

A control character acts the moment it arrives, even in the middle of a typed line; the
partial line is kept until its ``<CR>`` (so ``"#1\\x02J+"`` reports the motor status words and
then runs ``#1J+``). Several in one line act in order, before the line's own commands.

Reports (TSRM p260, p263, p270; PUM-V p34; spec §11.9), each one line of values separated by
one space ``[INF]`` (the manuals found do not give the separator or line count):

* CTRL-B ($02): ``?`` status words (12 hex digits) of the 8 motors of the port's ``##`` group
  (``##0`` = motors 1-8, the default … ``##3`` = 25-32);
* CTRL-C ($03): ``??`` status words (18 hex digits) of all 16 coordinate systems;
* CTRL-F ($06): following errors of the 8 ``##`` motors;
* CTRL-G ($07): the global status words, as ``???`` ``[INF]`` (the EPICS driver lists ^G
  among the report characters);
* CTRL-P ($10): positions of the 8 ``##`` motors, counts rounded to 1/32 count;
* CTRL-V ($16): velocities of the 8 ``##`` motors, counts per servo cycle (as ``V``).

Actions (TUM p217, p319; TSRM p260, p424; PSRM p175):

* CTRL-A ($01): abort all programs and moves (programs as ``A``, jogs decelerate at Ixx15)
  and close open loops; CTRL-K ($0B): kill all motors (programs aborted, lookahead and queued
  synchronous writes lost); CTRL-Q ($11): quit all programs (``Q`` in every CS); CTRL-D
  ($04): disable all PLC programs (compiled ones too ``[INF]``); CTRL-O ($0F): feed hold all
  coordinate systems; CTRL-U ($15): ``OPEN ROT``; CTRL-X ($18): flush this port's output —
  the protocol adapters own the queue, here it does nothing.

Any other control character answers ERR003 ``[INF]`` (the manuals list no answer for it) and
changes nothing. TAB, CR, LF and NUL are white space / line ends, not commands.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...controller import Port
from ..card.variables import N_CS, N_MOTORS, format_value

if TYPE_CHECKING:
    from ..controller import PmacController

#: Characters that are text, not control commands.
_TEXT = frozenset("\t\r\n\x00")


def is_control(ch: str) -> bool:
    """A control-character command (below $20 and not TAB/CR/LF/NUL)."""
    return ch < " " and ch not in _TEXT


def split_controls(text: str) -> tuple[list[str], str]:
    """``(control characters in order, the line without them)``."""
    controls = [ch for ch in text if is_control(ch)]
    if not controls:
        return [], text
    return controls, "".join(ch for ch in text if not is_control(ch))


def _hex(words: tuple[int, ...]) -> str:
    return "".join(f"{w & 0xFFFFFF:06X}" for w in words)


class ControlCharacters:
    """Acts on control characters for the ports of one controller."""

    def __init__(self, ctl: PmacController) -> None:
        self.ctl = ctl

    def _group(self, port: Port) -> range:
        first = 8 * int(port.state.get("group", 0)) + 1
        return range(first, min(first + 8, N_MOTORS + 1))

    def act(self, ch: str, port: Port) -> tuple[str, str | None]:
        """One control character: ``(reply line or "", error code or None)``."""
        ctl = self.ctl
        code = ord(ch)
        if code == 0x02:
            return " ".join(_hex(ctl.motor_status(n)) for n in self._group(port)), None
        if code == 0x03:
            cs = ctl.coord_systems
            return " ".join(_hex(cs[n].status_words()) for n in range(1, N_CS + 1)), None
        if code in (0x06, 0x10, 0x16):
            what = {0x06: "F", 0x10: "P", 0x16: "V"}[code]
            values = []
            for n in self._group(port):
                if what == "P":
                    values.append(format_value(round(ctl.motor_position(n) * 32) / 32))
                else:
                    values.append(format_value(ctl.motor_report(n, what)))
            return " ".join(values), None
        if code == 0x07:
            return _hex((ctl.background.global_status_word1(), 0)), None
        if code == 0x01:
            for n in ctl.coord_systems:
                ctl.abort(n)
            ctl.motor_table.abort_all()
            return "", None
        if code == 0x0B:
            ctl.kill_all()
            return "", None
        if code == 0x11:
            for n in ctl.coord_systems:
                ctl.quit(n)
            return "", None
        if code == 0x04:
            every = tuple(range(len(ctl.plcs.plcs)))
            ctl.plcs.set_enabled(every, False)
            ctl.plcs.set_enabled(every, False, compiled=True)  # "all PLC programs" [INF]
            return "", None
        if code == 0x0F:
            for c in ctl.coord_systems.values():
                c.hold()
            return "", None
        if code == 0x15:
            ctl.open_rotary(port)
            return "", None
        if code == 0x18:
            return "", None
        return "", "ERR003"


__all__ = ["ControlCharacters", "is_control", "split_controls"]
