"""Small host programs with retry logic, as host authors write them, for the fault-injection
tests: each sends a command, waits for its answer at most ``timeout_s`` (wall time), and on a
timeout, a reset or an ``ERRnnn`` reconnects (or not) and sends it again."""

from __future__ import annotations

import socket
import struct
import time
from dataclasses import dataclass, field

#: VR_DOWNLOAD, VR_PMAC_GETRESPONSE (PMAC Ethernet protocol, spec pmac.md §5.1).
_GETRESPONSE = struct.Struct(">BBHHH")


@dataclass
class Attempt:
    outcome: str  # "ok", "timeout", "reset", "closed", "error"
    reply: bytes = b""


@dataclass
class RetryingHost:
    """One command line at a time over a TCP protocol, retried up to ``tries`` times."""

    port: int
    protocol: str  # "pmac" (Ethernet GETRESPONSE) or "trio" (command line, prompt ``>>``)
    timeout_s: float = 0.5
    tries: int = 4
    retry_errors: bool = True
    log: list[Attempt] = field(default_factory=list)
    _sock: socket.socket | None = None

    def _connect(self) -> socket.socket:
        if self._sock is None:
            self._sock = socket.create_connection(("127.0.0.1", self.port), timeout=5)
        return self._sock

    def close(self) -> None:
        if self._sock is not None:
            self._sock.close()
            self._sock = None

    def _request(self, line: str) -> bytes:
        if self.protocol == "pmac":
            data = line.encode() + b"\0"
            return _GETRESPONSE.pack(0x40, 0xBF, 0, 0, len(data)) + data
        return line.encode() + b"\r\n"

    def _complete(self, got: bytes) -> bool:
        if self.protocol == "pmac":
            return got.endswith(b"\x06") or (b"\x07" in got and got.endswith(b"\r"))
        return got.endswith(b">>")

    def _once(self, line: str) -> Attempt:
        try:
            sock = self._connect()
            sock.sendall(self._request(line))
            got = b""
            deadline = time.monotonic() + self.timeout_s
            while not self._complete(got):
                left = deadline - time.monotonic()
                if left <= 0:
                    return Attempt("timeout", got)
                sock.settimeout(left)
                chunk = sock.recv(4096)
                if not chunk:
                    return Attempt("closed", got)
                got += chunk
        except TimeoutError:
            return Attempt("timeout", b"")
        except ConnectionResetError:
            return Attempt("reset", b"")
        if self.protocol == "pmac" and b"\x07ERR" in got:
            return Attempt("error", got)
        return Attempt("ok", got)

    def command(self, line: str) -> bytes:
        """The answer to ``line`` after as many tries as it took; raises after ``tries``."""
        for _ in range(self.tries):
            attempt = self._once(line)
            self.log.append(attempt)
            if attempt.outcome == "ok" or (attempt.outcome == "error" and not self.retry_errors):
                return attempt.reply
            if attempt.outcome != "error":
                self.close()  # the answer may still come on that connection: start afresh
        raise TimeoutError(f"{line!r}: no answer after {self.tries} tries")

    @property
    def outcomes(self) -> list[str]:
        return [a.outcome for a in self.log]
