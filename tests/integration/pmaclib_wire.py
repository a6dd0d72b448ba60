"""Lines sent one by one over the PMAC Ethernet port by Diamond's dls-pmaclib, in a process of
its own, as a beamline download does."""

from __future__ import annotations

import json
import subprocess
import sys

CLIENT = r"""
import json, sys
from dls_pmaclib.dls_pmacremote import PmacEthernetInterface

p = PmacEthernetInterface(verbose=False, timeout=5.0)
p.setConnectionParams("127.0.0.1", int(sys.argv[1]))
p.connect()
print(json.dumps([p.sendCommand(cmd) for cmd in json.loads(sys.argv[2])]))
p.disconnect()
"""


def send(port: int, lines: list[str], timeout_s: float = 300) -> list[list]:
    """dls-pmaclib's ``sendCommand`` reply for each line: ``[text, success]``."""
    client = subprocess.run([sys.executable, "-c", CLIENT, str(port), json.dumps(lines)],
                            capture_output=True, text=True, timeout=timeout_s)
    assert client.returncode == 0, client.stderr
    return json.loads(client.stdout)


def download(port: int, lines: list[str], timeout_s: float = 300) -> None:
    """Send ``lines``; none may be refused. dls-pmaclib's success flag is only the
    transport's: a refused line answers BEL ERRnnn."""
    replies = send(port, lines, timeout_s)
    refused = [(line, r) for line, r in zip(lines, replies, strict=True)
               if not r[1] or "\x07" in r[0] or "ERR" in r[0]]
    assert refused == []
