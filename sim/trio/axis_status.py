"""Axis parameters a Trio program sets up at start-up but the motion model only stores, and
AXISSTATUS as far as the simulation knows the axis' state.

Stored per axis, read and written as ``NAME [AXIS(n)]`` (spec §10.11 "axis parameters",
§1.6), power-up values ``[BK]`` (the TRM pages were not reachable):

========== ============= ==========================================================
name        power-up      meaning (what the simulator does with it)
========== ============= ==========================================================
FS_LIMIT    200000000     forward software limit, user units (AXISSTATUS bit 9)
RS_LIMIT    -200000000    reverse software limit (AXISSTATUS bit 10)
ERRORMASK   268           AXISSTATUS bits that are a motion error (2, 3 and 8)
FE_LIMIT    2000          following-error limit (no following error is modelled)
FE_RANGE    0             following-error warning range (stored)
AXIS_ENABLE 1             drive enable, with WDOG (stored) ``[BK]`` MC4xx name
SERVO       0             position loop on / off (stored; the demand moves either way)
JOGSPEED    0             jog speed (stored; no jog inputs are modelled)
FASTDEC     0             fast deceleration at a limit (stored)
ATYPE       0             axis type, 0 = virtual ``[INF]`` (stored)
========== ============= ==========================================================

**Limits are stored, not enforced**: the real controller ramps an axis that reaches FS_LIMIT /
RS_LIMIT down and cancels the move (M216-367); here the move goes on and AXISSTATUS reports
the axis beyond the limit.

AXISSTATUS bits computed (bit numbers: spec §1.6 — 8 FE limit, 9 FS, 10 RS, 11 move
cancelling; 6 datuming ``[BK]``):

* bit 6 (64): a DATUM move is executing;
* bit 9 (512): DPOS >= FS_LIMIT; bit 10 (1024): DPOS <= RS_LIMIT ``[INF]`` (>= / <=);
* bit 11 (2048): the executing move is being cancelled (CANCEL / RAPIDSTOP decelerating).

The other bits (following error, drive comms, hardware limits, feedhold) are never set: the
simulation has no drives, encoders or limit switches. MOTION_ERROR is therefore 0.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionsim.sim.trio.basic_errors import BasicError

if TYPE_CHECKING:
    from motionsim.sim.trio.axis import Axis

STORED_DEFAULTS: dict[str, float] = {
    "FS_LIMIT": 200_000_000.0,
    "RS_LIMIT": -200_000_000.0,
    "ERRORMASK": 268.0,
    "FE_LIMIT": 2000.0,
    "FE_RANGE": 0.0,
    "AXIS_ENABLE": 1.0,
    "SERVO": 0.0,
    "JOGSPEED": 0.0,
    "FASTDEC": 0.0,
    "ATYPE": 0.0,
}

#: Switches: any non-zero value reads back 1 (ON).
_SWITCHES = frozenset({"AXIS_ENABLE", "SERVO"})
#: Parameters that take no negative value.
_NON_NEGATIVE = frozenset({"ERRORMASK", "FE_LIMIT", "FE_RANGE", "JOGSPEED", "FASTDEC", "ATYPE"})

DATUMING = 1 << 6
FS_LIMIT_BIT = 1 << 9
RS_LIMIT_BIT = 1 << 10
CANCELLING = 1 << 11


class StoredParams:
    """The stored parameters of one axis."""

    def __init__(self) -> None:
        self.values = dict(STORED_DEFAULTS)

    def read(self, name: str) -> float:
        return self.values[name]

    def write(self, name: str, value: float) -> None:
        if name in _NON_NEGATIVE and value < 0:
            raise BasicError(f"Parameter out of range: {name}={value:g}")
        if name in _SWITCHES:
            value = 1.0 if value else 0.0
        elif name in ("ERRORMASK", "ATYPE"):
            value = float(int(value))
        self.values[name] = float(value)


def axisstatus(axis: Axis, params: StoredParams) -> int:
    """AXISSTATUS of ``axis`` now, from the bits this simulation knows (module docstring)."""
    bits = 0
    m = axis.mtype
    if m is not None:
        if m.kind == "DATUM":
            bits |= DATUMING
        if m.cancelled:
            bits |= CANCELLING
    dpos = axis.position()
    if dpos >= params.read("FS_LIMIT"):
        bits |= FS_LIMIT_BIT
    if dpos <= params.read("RS_LIMIT"):
        bits |= RS_LIMIT_BIT
    return bits


__all__ = ["STORED_DEFAULTS", "StoredParams", "axisstatus"]
