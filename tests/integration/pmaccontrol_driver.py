"""Drive dls-pmac-control's main window headless (``QT_QPA_PLATFORM=offscreen``) against a PMAC
at 127.0.0.1:PORT and print what it showed, as JSON, on stdout.

Run as a script by ``test_pmac_tools.py``: ``python pmaccontrol_driver.py PORT``. It uses the
tool's own window class and slots unmodified (``Controlform.remoteConnect``, the poll thread
``CommsThread.updateThread``, ``jogPos``); only the button presses are calls.
"""

from __future__ import annotations

import json
import os
import resource
import sys
import time
from optparse import Values

from dls_pmac_control.__main__ import Controlform
from PyQt5.QtWidgets import QApplication


def _cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def main() -> None:
    port = sys.argv[1]
    options = Values({
        "verbose": False, "protocol": "tcpip", "server": "127.0.0.1", "port": port,
        "defaultAxis": 1, "macroAxisStartIndex": 0, "nAxes": None, "timeout": 3.0,
        "username": "root", "password": "deltatau",
    })
    app = QApplication(sys.argv[:1])
    win = Controlform(options)

    def pump(seconds: float) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            app.processEvents()
            time.sleep(0.01)

    def pump_until(done, max_s: float = 30.0) -> None:
        """Pump until ``done()`` holds (at most ``max_s``): a loaded machine only takes
        longer, it cannot make the GUI miss what it shows."""
        end = time.monotonic() + max_s
        while not done() and time.monotonic() < end:
            app.processEvents()
            time.sleep(0.01)

    def table() -> list[list[str | None]]:
        t = win.table
        return [[t.item(r, c).text() if t.item(r, c) is not None else None
                 for c in range(3)] for r in range(t.rowCount())]

    win.remoteConnect()
    pump_until(lambda: win.table.rowCount() == 8 and all(None not in row for row in table()))
    pump(0.5)
    out: dict = {"title": win.windowTitle(), "rows": win.table.rowCount(), "before": table()}
    wall0, cpu0 = time.monotonic(), _cpu_s()
    pump(2.0)
    out["cpu_share"] = (_cpu_s() - cpu0) / (time.monotonic() - wall0)
    win.lneJogDist.setText("1000")
    win.jogPos()
    pump_until(lambda: table()[0][0] == "1000.0")
    pump(0.5)  # the next polls: the position stays where the jog ended
    out["after"] = table()
    out["shell"] = win.txtShell.toPlainText()
    win.killMotor()
    out["shell_kill"] = win.txtShell.toPlainText()
    print(json.dumps(out), flush=True)
    win.die()
    pump(0.3)
    os._exit(0)


if __name__ == "__main__":
    main()
