"""What a controller's programs may DIM: the model's program data memory, per controller.

An MC4 ``DIM`` reserves controller memory for a typed local, an array or a string; the card's
memory is finite, and one controller's programs share it (a simulated controller cannot take
another's, whatever its programs DIM). No manual figure was reachable (spec §11.4: DIM's
semantics are ``[BK]``), so the figures are ours ``[INF]``:

* every process' DIMmed data together holds at most :data:`DATA_BYTES` bytes per controller;
  a number (INTEGER, FLOAT, BOOLEAN: 64-bit on MC4) takes 8 bytes, a ``STRING(n)`` ``n``
  bytes; an array ``DIM a(k)`` ``k`` times its element;
* one ``STRING(n)`` holds at most :data:`MAX_STRING` characters.

A DIM that can never fit (or a longer string) is refused when the program is stored (a syntax
error naming the limit, nothing stored); a DIM that fits alone but not beside what the other
running processes hold stops its program at run time with a BASIC error naming the free and
total bytes. A process' data is given back when it stops.
"""

from __future__ import annotations

from typing import Final

#: Bytes of DIMmed data one controller's running processes may hold together ``[INF]``.
DATA_BYTES: Final = 1 << 20
#: Characters one STRING(n) may hold ``[INF]``.
MAX_STRING: Final = 65_535
#: Bytes of one number (INTEGER / FLOAT / BOOLEAN are 64-bit on MC4).
NUMBER_BYTES: Final = 8


def dim_bytes(type_: str, size: int | None, length: int) -> int:
    """Bytes a ``DIM`` of ``type_`` (an array of ``size``, strings of ``length``) reserves."""
    element = length if type_ == "STRING" else NUMBER_BYTES
    return element * (size or 1)


def too_big(type_: str, size: int | None, length: int) -> str | None:
    """Why such a DIM can never be held (the message, with the limit), or None."""
    if type_ == "STRING" and length > MAX_STRING:
        return f"STRING({length}) is longer than the {MAX_STRING} characters a string holds"
    need = dim_bytes(type_, size, length)
    if need > DATA_BYTES:
        return (f"DIM needs {need} bytes: more than the {DATA_BYTES} bytes of program data "
                "memory")
    return None


def out_of_memory(name: str, need: int, free: int) -> str:
    """The run-time BASIC error of a DIM that does not fit beside the other processes' data."""
    return (f"Out of memory: DIM {name} needs {need} bytes, {max(free, 0)} of {DATA_BYTES} "
            "bytes of program data memory free")


__all__ = ["DATA_BYTES", "MAX_STRING", "NUMBER_BYTES", "dim_bytes", "out_of_memory", "too_big"]
