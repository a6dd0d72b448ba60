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

**Software limits are enforced** (:mod:`motionsim.sim.trio.motion.limits`): a move that takes
an axis to FS_LIMIT / RS_LIMIT ramps down at DECEL and is cancelled (M216-367); the axis then
rests beyond the limit by the ramp's distance and AXISSTATUS reports it in the limit.

AXISSTATUS bits computed (bit numbers: spec §1.6 — 8 FE limit, 9 FS, 10 RS, 11 move
cancelling; 6 datuming and 1 following-error warning ``[BK]``):

* bit 1 (2): |FE| > FE_RANGE, with FE_RANGE above 0 (the warning range; FE from the
  following-error model of the axis, ``Axis.following_error``);
* bit 6 (64): a DATUM move is executing;
* bit 8 (256): the following error exceeded FE_LIMIT with SERVO on (latched in
  ``Axis.error_bits`` until DATUM(0) clears it, M216-367: "the following error bit is set in
  the AXISSTATUS register");
* bit 9 (512): DPOS >= FS_LIMIT; bit 10 (1024): DPOS <= RS_LIMIT ``[INF]`` (>= / <=);
* bit 11 (2048): the executing move is being cancelled (CANCEL / RAPIDSTOP decelerating).

The other bits (drive comms, hardware limits, feedhold) are never set: the simulation has no
drives with digital comms and no limit switches. A motion error (MOTION_ERROR, WDOG off) is
raised where AXISSTATUS meets ERRORMASK (:mod:`motionsim.sim.trio.card.system`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .basic_errors import BasicError
from .parameters import STORED, STORED_BY_NAME
from .scaling import encoder_count

if TYPE_CHECKING:
    from ..motion.axis import Axis

#: Power-up values of every stored axis parameter (the table of
#: :data:`motionsim.sim.trio.card.parameters.STORED`).
STORED_DEFAULTS: dict[str, float] = {p.name: p.power_up for p in STORED}

FE_WARNING = 1 << 1
DATUMING = 1 << 6
FE_LIMIT_BIT = 1 << 8
FS_LIMIT_BIT = 1 << 9
RS_LIMIT_BIT = 1 << 10
CANCELLING = 1 << 11


class StoredParams:
    """The stored parameters of one axis."""

    def __init__(self) -> None:
        self.values = dict(STORED_DEFAULTS)

    def read(self, name: str) -> float:
        return self.values[name]

    def write(self, name: str, value: float, units: float = 1.0) -> None:
        """Write ``name``; a value below the parameter's range is a BasicError, and the
        value is kept as the table's ``kind`` says (truncated, a switch reading 1, or whole
        encoder edges at the axis' ``units``: INT(value x UNITS) / UNITS)."""
        spec = STORED_BY_NAME[name]
        if spec.low is not None and value < spec.low:
            raise BasicError(f"Parameter out of range: {name}={value:g}")
        if spec.kind == "switch":
            value = 1.0 if value else 0.0
        elif spec.kind == "int":
            value = float(int(value))
        elif spec.kind == "edges":
            value = int(value * units) / units
        self.values[name] = float(value)

    def units_changed(self, old: float, new: float) -> None:
        """UNITS written: the parameters held in edges keep their count, so they read back
        rescaled (TKB-REP: REP_DIST is stored as INT(value x UNITS))."""
        for spec in STORED:
            if spec.kind == "edges":
                self.values[spec.name] = self.values[spec.name] * old / new


def axisstatus(axis: Axis, params: StoredParams) -> int:
    """AXISSTATUS of ``axis`` now, from the bits this simulation knows (module docstring)."""
    bits = axis.error_bits
    fe_range = params.read("FE_RANGE")
    if fe_range > 0.0 and abs(axis.following_error()) > fe_range:
        bits |= FE_WARNING
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


def computed(name: str, axis: Axis) -> float:
    """A read-only axis parameter computed from the motion (parameters.AXIS_COMPUTED):
    AXISSTATUS; MSPEED and VPSPEED = VP_SPEED (the demand speed, ``[INF]``); FE = DPOS - MPOS
    from the axis' following-error model (0 unless it has an ``fe_lag``); ENCODER the raw
    encoder count that gives MPOS through ENCODER_RATIO
    (:mod:`motionsim.sim.trio.card.scaling`)."""
    if name == "AXISSTATUS":
        return float(axisstatus(axis, axis.stored))
    if name == "FE":
        return axis.following_error()
    if name == "ENCODER":
        mpos = axis.position() - axis.following_error()
        return encoder_count(mpos, axis.units, axis.encoder_ratio)
    return axis.vp_speed()


__all__ = ["FE_LIMIT_BIT", "FE_WARNING", "STORED_DEFAULTS", "StoredParams", "axisstatus",
           "computed"]
