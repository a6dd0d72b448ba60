"""I-variable value rules seen by a real client: dls-pmaclib over the PMAC Ethernet protocol.

TUM p243 (a value outside a limited range rolls over, no error) and TSRM p57 (a write
locked by I41 is ignored, no error), sent by ``PmacEthernetInterface.sendCommand`` to a
``motionsim serve`` subprocess on loopback. The manual's own ``I3=5`` would give I3 = 1,
``<LF>``-framed replies the client does not read, so the check uses ``I3=6`` -> 2, the
``<ACK>`` framing it keeps using.
"""

from __future__ import annotations

import json
import subprocess
import sys

from tests.integration.test_clients_pmac import free_port, motionsim_serve

CLIENT = r"""
import json, sys
from dls_pmaclib.dls_pmacremote import PmacEthernetInterface
p = PmacEthernetInterface(verbose=False, timeout=5.0)
p.setConnectionParams("127.0.0.1", int(sys.argv[1]))
out = {"connect": p.connect()}
for key, cmd in [("set", "I3=6"), ("i3", "I3"), ("neg", "I59=-1 I59"), ("lock", "I41=1"),
                 ("locked_set", "I130=5"), ("i130", "I130"), ("unlock", "I41=0 I130=5 I130")]:
    out[key] = p.sendCommand(cmd)
p.disconnect()
print(json.dumps(out))
"""


def test_pmaclib_sees_i3_6_answer_2_and_an_i41_locked_write_ignored() -> None:
    port = free_port()
    with motionsim_serve("--pmac-port", str(port), "--trio-port", "0"):
        run = subprocess.run([sys.executable, "-c", CLIENT, str(port)],
                             capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    assert out["connect"] is None
    assert out["set"] == ["\x06", True]  # no error: the value rolls over
    assert out["i3"] == ["2\r\x06", True]
    assert out["neg"] == ["3\r\x06", True]
    assert out["lock"] == ["\x06", True]
    assert out["locked_set"] == ["\x06", True]  # ignored, still acknowledged
    assert out["i130"] == ["2000\r\x06", True]  # Ixx30 factory default
    assert out["unlock"] == ["5\r\x06", True]
