"""Run a trajectory scan the way the EPICS ``pmac`` driver does, against a PMAC served by
``motionsim serve`` (PMAC Ethernet port), with a motion program already on the card — our own
(``scan_program.pmc`` beside this script) or Diamond's (docs/pmac_trajectory_scan.md).

    python examples/pmac/trajectory_scan_host.py [--host 127.0.0.1] [--port 1025]
           [--load FILE] [--points 1200] [--point-ms 40]

``--load FILE`` first sends FILE's lines (already preprocessed: no ``#define``/``#include``)
with dls-pmaclib's ``sendSeries``. The host (``scan_host.py`` beside this script) reads the
buffer length and addresses, fills half A with ``WL:`` writes, starts ``&1B1R``, fills the idle
half as the program moves on, polls M4034/M4039/M4040/M4038 and prints the result.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # scan_host.py beside it, in a copy too

from dls_pmaclib.dls_pmacremote import PmacEthernetInterface  # noqa: E402
from scan_host import ScanHost, points  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--host", default="127.0.0.1")
    ap.add_argument("--port", type=int, default=1025)
    ap.add_argument("--load")
    ap.add_argument("--points", type=int, default=1200)
    ap.add_argument("--point-ms", type=float, default=40.0,
                    help="time per point: a half-buffer lasts length x this; the host must "
                    "refill the other half within it over the network (10 ms points leave a "
                    "host on a busy machine too little time)")
    args = ap.parse_args()
    pmac = PmacEthernetInterface()
    pmac.setConnectionParams(args.host, args.port)
    if pmac.connect() is not None:
        sys.exit(f"cannot connect to {args.host}:{args.port}")

    def ask(line: str) -> str:
        reply, ok = pmac.sendCommand(line)
        if not ok or "ERR" in reply:
            print(f"{line!r} -> {reply!r}")
        return reply.rstrip("\r\x06").replace("\r\x06", "")

    ask("&1 #1->1000X #2->1000Y")
    if args.load:
        lines = [ln.strip() for ln in Path(args.load).read_text().splitlines() if ln.strip()]
        for ok, _n, cmd, reply in pmac.sendSeries(list(enumerate(lines, start=1))):
            if not ok:
                print(f"refused: {cmd!r} -> {reply!r}")
    host = ScanHost(ask=ask)
    host.setup()
    print(f"buffer length {host.length}, halves at ${host.adr[0]:X} / ${host.adr[1]:X}, "
          f"program version {host.version:g}")
    pts = points(args.points, time_us=round(args.point_ms * 1000))
    host.start(pts)
    status = total = 1
    while status == 1:
        time.sleep(0.05)
        status, index, current, total = host.poll()
        print(f"\rstatus {status} half {'AB'[current]} index {index:4d} points {total:5d}",
              end="", flush=True)
    print(f"\nerror M4048 = {ask('M4048')}, fills {len(host.log)}, "
          f"X = {ask('&1Q77')} (last point {pts[-1].pos['X']:.9f})")
    pmac.disconnect()
    if total != len(pts):
        sys.exit(f"scan ended after {total} of {len(pts)} points (status {status}): the "
                 "program reached a half the host had not refilled yet — a slower "
                 "--point-ms gives the host more time per half")
    print(f"scan complete: {total} points")


if __name__ == "__main__":
    main()
