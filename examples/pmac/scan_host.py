"""A host doing what the EPICS driver's trajectory scan does (pmacController.cpp @ 3d2e73f,
spec §12.7): read the buffer length and the two half-buffer addresses (M4037, M4041, M4042)
and the program version (M4049); write a half-buffer with ``WL:`` long words — time+user words
``$<u><tttttt>`` (us) at the half's base, each axis's positions at base + (axis+1)·length and
velocities at base + (axis+10)·length, as 48-bit floats in the card's layout — then its fill
level (M4044 / M4045); set the axes mask (M4036), zero the other half's fill and the point
count (``M4045=0 M4038=0``), enable the CS's motors (``&{cs}E``), start ``&{cs}B{prog}R``;
while it runs poll status (M4034), index (M4039), current half (M4040), points done (M4038)
and fill the half not in use as soon as the program has moved on from it; abort with
``M4035=1``."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from motionsim.sim.pmac.card.pmac_float import encode

AXES = "ABCUVWXYZ"
PER_LINE = 10  # values per WL: command (the driver sends them in several lines too)


@dataclass
class Point:
    time_us: int
    user: int
    pos: dict[str, float]
    vel: dict[str, float]


def points(n: int, time_us: int = 10_000) -> list[Point]:
    """A smooth X/Y path: X a sine, Y a ramp, with their exact velocities (units/s)."""
    out = []
    for k in range(n):
        t = (k + 1) * time_us / 1e6
        out.append(Point(time_us, 0, {"X": 2 * math.sin(t * 3), "Y": 0.5 * t},
                         {"X": 6 * math.cos(t * 3), "Y": 0.5}))
    return out


@dataclass
class ScanHost:
    """``ask(line) -> reply`` is the host's terminal (a port of the card)."""

    ask: Callable[[str], str]
    axes: str = "XY"
    cs: int = 1
    prog: int = 1
    sent: int = 0
    log: list[tuple[str, int]] = field(default_factory=list)

    def setup(self) -> None:
        self.length = int(float(self.ask("M4037")))
        self.adr = (int(float(self.ask("M4041"))), int(float(self.ask("M4042"))))
        self.version = float(self.ask("M4049"))

    def _write(self, base: int, values: list[str]) -> None:
        for k in range(0, len(values), PER_LINE):
            self.ask(f"WL:${base + k:X}," + ",".join(values[k:k + PER_LINE]))

    def fill(self, half: int, pts: list[Point]) -> None:
        base = self.adr[half]
        self._write(base, [f"${p.user:01X}{p.time_us:06X}" for p in pts])
        for a in self.axes:
            i = AXES.index(a)
            self._write(base + (i + 1) * self.length, [f"${encode(p.pos[a]):X}" for p in pts])
            self._write(base + (i + 10) * self.length, [f"${encode(p.vel[a]):X}" for p in pts])
        self.ask(f"M{4044 + half}={len(pts)}")
        self.log.append(("fill", half))

    def start(self, pts: list[Point]) -> None:
        self.pts = pts
        self.fill(0, pts[: self.length])
        self.sent = min(len(pts), self.length)
        mask = sum(1 << AXES.index(a) for a in self.axes)
        self.ask(f"M4036={mask}")
        self.ask("M4045=0 M4038=0")
        self.ask(f"&{self.cs}E")  # "make sure axes are enabled" (getCSEnableCommand)
        self.ask(f"&{self.cs}B{self.prog}R")

    def poll(self) -> tuple[int, int, int, int]:
        """One poll; fills the half not in use when it is empty and points remain."""
        status, index, current, total = (int(float(x)) for x in
                                         self.ask("M4034 M4039 M4040 M4038").split("\r"))
        other = 1 - current
        if status == 1 and self.sent < len(self.pts):
            fill = int(float(self.ask(f"M{4044 + other}")))
            if fill == 0:
                chunk = self.pts[self.sent: self.sent + self.length]
                self.fill(other, chunk)
                self.sent += len(chunk)
        return status, index, current, total

    def abort(self) -> None:
        self.ask("M4035=1")
