"""Sans-I/O codec of the Trio Motion Coordinator command line over TCP (telnet, port 23).

The command line is channel 0, served by process 0 (spec trio.md §0.10–0.11, §3.1, §9.9): the
host types a line, the controller answers on the next line(s) and prints the prompt ``>>``
again (``>>PRINT FREE`` / ``47104.0000`` / ``>>``). A move that cannot be buffered locks the
command line: the prompt does not come back until the move is buffered — the server simply
does not ask this codec for the next line until the reply is complete.

What this codec does with the bytes (``[BK]``/``[INF]`` where the manuals found are silent):

* input lines end with CR, LF, CR LF or CR NUL (telnet NVT); an empty line just gives a new
  prompt; backspace / DEL removes the last character; ESC discards the line being typed;
* typed characters are echoed as they are read (a terminal shows the text after ``>>``), line
  ends echoed as CR LF; output lines end CR LF;
* no prompt is sent on connect: as with ``telnet 192.168.0.250`` the host presses Return and
  gets ``>>`` (a client that wants the prompt first sends an empty line);
* telnet option negotiation is answered so that telnet clients work: ``DO ECHO`` / ``DO SGA``
  are accepted (the controller echoes and never sends GA), every other option is refused;
  subnegotiations are skipped. A plain socket client never sees an IAC byte;
* a line longer than :data:`MAX_LINE` characters is cut there (the rest is dropped unechoed).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

from ..wire import NEED_DATA, NeedData

PROMPT: Final = b">>"
EOL: Final = b"\r\n"
#: Longest command line kept ``[INF]``.
MAX_LINE: Final = 1024

IAC, DONT, DO, WONT, WILL, SB, SE = 255, 254, 253, 252, 251, 250, 240
OPT_ECHO, OPT_SGA = 1, 3
_BS, _DEL, _ESC, _CR, _LF, _NUL = 0x08, 0x7F, 0x1B, 0x0D, 0x0A, 0x00


@dataclass(frozen=True, slots=True)
class Line:
    """One command line typed by the host (without its line end)."""

    text: str


class TrioTerminalCodec:
    """One telnet session's line discipline.

    Use: ``receive_data(chunk)`` as bytes arrive (``b""`` at end of stream); ``next_line()``
    until :data:`NEED_DATA`, sending ``data_to_send()`` (echo, telnet answers) after each call;
    answer each line with ``reply(text, error)`` (ends with the prompt).

    Args:
        echo: echo typed characters (the controller does).
    """

    def __init__(self, echo: bool = True) -> None:
        self.echo = echo
        self._raw = bytearray()
        self._pos = 0
        self._line = bytearray()
        self._out = bytearray()
        self._eof = False
        self._last_cr = False
        self._state = 0  # 0 data, 1 after IAC, 2 after IAC WILL/WONT/DO/DONT, 3 in SB, 4 SB+IAC
        self._verb = 0

    def receive_data(self, data: bytes) -> None:
        """Bytes from the host; ``b""`` means the host closed its side."""
        if data:
            self._raw += data
        else:
            self._eof = True

    @property
    def eof(self) -> bool:
        return self._eof

    def data_to_send(self) -> bytes:
        """Echo and telnet negotiation produced since the last call."""
        out = bytes(self._out)
        self._out.clear()
        return out

    def next_line(self) -> Line | NeedData:
        """The next complete line, or :data:`NEED_DATA` (bytes after it stay unread — and
        unechoed — until the next call)."""
        raw = self._raw
        while self._pos < len(raw):
            b = raw[self._pos]
            self._pos += 1
            line = self._byte(b)
            if line is not None:
                self._compact()
                return line
        self._compact()
        return NEED_DATA

    def _compact(self) -> None:
        if self._pos:
            del self._raw[: self._pos]
            self._pos = 0

    def _byte(self, b: int) -> Line | None:
        state = self._state
        if state == 1:  # after IAC
            if b == IAC:
                self._state = 0
                return self._char(b)
            if b in (WILL, WONT, DO, DONT):
                self._verb, self._state = b, 2
            elif b == SB:
                self._state = 3
            else:
                self._state = 0  # NOP, GA, AYT, ... ignored
            return None
        if state == 2:
            self._negotiate(self._verb, b)
            self._state = 0
            return None
        if state == 3:
            if b == IAC:
                self._state = 4
            return None
        if state == 4:
            self._state = 0 if b == SE else 3
            return None
        if b == IAC:
            self._state = 1
            return None
        return self._char(b)

    def _negotiate(self, verb: int, option: int) -> None:
        if verb == DO:
            answer = WILL if option in (OPT_ECHO, OPT_SGA) else WONT
        elif verb == WILL:
            answer = DO if option == OPT_SGA else DONT
        else:
            return  # WONT / DONT need no answer (we never asked)
        self._out += bytes([IAC, answer, option])

    def _char(self, b: int) -> Line | None:
        last_cr, self._last_cr = self._last_cr, False
        if b == _CR:
            self._last_cr = True
            return self._end_line()
        if b == _LF:
            return None if last_cr else self._end_line()
        if b == _NUL:
            return None
        if b in (_BS, _DEL):
            if self._line:
                self._line.pop()
                if self.echo:
                    self._out += b"\b \b"
            return None
        if b == _ESC:
            self._line.clear()
            if self.echo:
                self._out += EOL
            return None
        if len(self._line) >= MAX_LINE:
            return None
        self._line.append(b)
        if self.echo:
            self._out.append(b)
        return None

    def _end_line(self) -> Line:
        text = self._line.decode("latin-1")
        self._line.clear()
        if self.echo:
            self._out += EOL
        return Line(text)

    # -- output --------------------------------------------------------------------------

    @staticmethod
    def reply(text: str = "", error: str | None = None, prompt: bool = True) -> bytes:
        """The controller's answer to one line: its output lines, the error line, ``>>``."""
        out = bytearray()
        for chunk in (text, error):
            chunk = (chunk or "").rstrip("\r\n")
            if chunk:
                for ln in chunk.replace("\r\n", "\n").replace("\r", "\n").split("\n"):
                    out += ln.encode("latin-1", "replace") + EOL
        if prompt:
            out += PROMPT
        return bytes(out)


__all__ = ["EOL", "MAX_LINE", "NEED_DATA", "PROMPT", "Line", "TrioTerminalCodec"]
