"""Controller generations: what differs between the Trio models the simulator can be.

Config ``model`` of a Trio controller (default ``"mc2xx"``):

* ``series2`` — MC2, MC204, MC216 with system software >= 1.40, the cards of TN20-16:
  32-bit float word ``[BK]``, 24-bit HEX, 14 processes (MC216);
* ``mc2xx`` — MC202, Euro205, MC206, MC216, MC224 (TRM 6.x): 32-bit float ``[INF]``, 24-bit
  HEX, 7 processes (MC206);
* ``mc4xx`` — MC4xx (MC403, MC405, MC464), firmware 2.x (Trajexia TJ2 is its twin ``[BK]``):
  64-bit float, 53-bit HEX, 22 processes, VR(0..63999), TABLE(0..499999);
* ``mc6xx`` — MC6xx (MC664, MC6N), the same firmware 2.x language and buffers as ``mc4xx``,
  22 processes, VR(0..65535), TABLE(0..511999).

Sources (spec §10.9, §7): the 32-bit word — single precision, exact integers to 2^24, HEX in
24-bit two's complement (``HEX(-10)`` -> ``FFFFF6``) — is TJ1P-27 (Trajexia TJ1, the MC2xx
generation's OEM twin); the 64-bit word — double precision, exact integers to 2^53, HEX in 53
bits (``1FFFFFFFFFFFF6``) — is TJ2P-19. MC2xx values cross the wire as 32-bit IEEE floats
(IEEE_IN / IEEE_OUT, M206-334). Process counts: M206-184 (MC206 7, MC216 14), TJ2H-39 (22).

The default is ``mc2xx``: the buffering modelled (one NTYPE, one process buffer, PMOVE) is
the TRM 6.x MC2xx description (M206-320), the process count default 7 is the MC206's, and
TN20's series-2 cards are its direct predecessors with the same buffers.

Sizes: the config's ``processes``, ``vr_count`` and ``table_size`` default to the model's and
stay settable. MC2xx generation: VR(0..1023) (TJ1P-26, the TJ1 twin: 1024 VRs) and a TABLE of
16 384 ``[INF]`` (the simulator's size before per-model sizes; the MC2xx TRM pages were not
reached). MC4xx: VR(0..63999) and TABLE(0..499999) (TJ2P-16: "64 000" VRs, "500 000" TABLE
entries on the TJ2, the MC4xx's OEM twin). MC6xx: the MC664 / MC6N manuals were not reached;
VR 65 536 and TABLE 512 000 are the sizes Trio's own host library (TrioPC .NET) allocates for
the controllers it serves (spec §2.2, TPCNET), taken as the largest model's ``[INF]``; 22
processes as the MC4xx ``[BK]``. ``mc4`` marks the firmware 2.x family: the MC4 language
(:mod:`motionsim.sim.trio.language`), 64 look-ahead buffers per axis, CAMBOX's offset start.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

from ...errors import InvalidValue


@dataclass(frozen=True, slots=True)
class Model:
    """One generation's number format."""

    name: str
    word_bits: int  # 32: single precision, 64: double
    hex_bits: int  # width of HEX()'s two's complement
    processes: int  # user processes of the model's typical board
    control: int  # CONTROL: the controller type number
    version: float  # VERSION: the system software version
    free: float  # FREE: program memory free, in the model's units
    vr_count: int = 1024  # VR(0..vr_count - 1)
    table_size: int = 16384  # TABLE(0..table_size - 1)
    mc4: bool = False  # the firmware 2.x family (MC4xx / MC6xx): its language and buffers


#: CONTROL / VERSION / FREE per model. VERSION: TN20-16 is for series-2 cards with system
#: software >= 1.40; the TRM 6th edition (rev 6.4) covers MC206 / MC224 from 1.62; the MC4xx
#: help pages copied on GitHub (spec §10.13 CAMBOX-MD) name firmware 2.0253. CONTROL: the board
#: number (MC216 -> 216, MC206 -> 206, MC464 -> 464, MC664 -> 664) ``[BK]``; FREE: ``>>PRINT
#: FREE`` answers ``47104.0000`` on the MC224 of M224-291, used for every model and constant
#: (storing programs does not lower it here, ``[INF]``).
MODELS: dict[str, Model] = {
    "series2": Model("series2", 32, 24, 14, 216, 1.40, 47104.0),
    "mc2xx": Model("mc2xx", 32, 24, 7, 206, 1.62, 47104.0),
    "mc4xx": Model("mc4xx", 64, 53, 22, 464, 2.0253, 47104.0, 64_000, 500_000, True),
    "mc6xx": Model("mc6xx", 64, 53, 22, 664, 2.0253, 47104.0, 65_536, 512_000, True),
}
DEFAULT_MODEL = "mc2xx"


def model(name: object) -> Model:
    """The model called ``name`` (config ``model``); InvalidValue naming the known ones."""
    if not isinstance(name, str) or name.lower() not in MODELS:
        known = ", ".join(MODELS)
        raise InvalidValue(f"model must be one of {known}, got {name!r}", field="model")
    return MODELS[name.lower()]


#: The largest magnitude each word holds (float32, float64).
WORD_MAX: dict[int, float] = {32: 3.4028234663852886e38, 64: 1.7976931348623157e308}
#: Position counters in whole encoder edges: 32-bit on MC2xx, 53 exact bits on MC4 ``[INF]``.
EDGES_MAX: dict[int, float] = {32: float(2**31), 64: float(2**53)}


def out_of_word(value: float, m: Model) -> bool:
    """Whether the model's number format cannot hold ``value`` (NaN, inf, or beyond its
    largest float: a VR or TABLE store of it is refused, not kept as ``inf``)."""
    lim = WORD_MAX[m.word_bits]
    return not -lim <= value <= lim


def to_word(value: float, m: Model) -> float:
    """``value`` as the model's word holds it (float32 rounding on 32-bit models)."""
    if m.word_bits == 64:
        return value
    try:
        return struct.unpack("<f", struct.pack("<f", value))[0]
    except OverflowError:
        return value


def format_number(value: float, m: Model, decimals: int = 4, width: int = 0) -> str:
    """PRINT of a number: fixed point, 4 decimals by default (``255.0000``, TJ1P-27,
    M224-291); ``[d]`` / ``[w,d]`` give decimals and a minimum width ``[BK]``."""
    v = to_word(value, m)
    text = f"{v:.{decimals}f}"
    if text.startswith("-") and float(text) == 0.0:
        text = text[1:]  # no "-0.0000"
    return text.rjust(width)


def hex_text(value: float, m: Model) -> str:
    """HEX(x): the integer part of ``x`` in the model's two's complement, upper case, no
    decimals (TJ1P-27: ``HEX(-10)`` -> ``FFFFF6``; TJ2P-19: 53 bits on 64-bit models)."""
    n = int(value)
    return format(n & ((1 << m.hex_bits) - 1), "X")


__all__ = ["DEFAULT_MODEL", "EDGES_MAX", "MODELS", "WORD_MAX", "Model", "format_number",
           "hex_text", "model", "out_of_word", "to_word"]
