"""The object words of the Turbo PMAC commands: the second word of ``OPEN PROG``,
``DEFINE GATHER``, ``LIST PLC``... with the abbreviations the manuals and real programs write
(spec §12.1: ``ROT``, ``GAT``, ``PROG``, ``INV``...).

Apart from the keyword table (:mod:`.keywords`) because the table's builders read them: the
table refers to its builders directly, so they cannot import it back.
"""

from __future__ import annotations

from typing import Final

#: Object word (long form) -> its abbreviations.
SPELLINGS: Final[dict[str, tuple[str, ...]]] = {
    "ROTARY": ("ROT",), "GATHER": ("GAT",), "LOOKAHEAD": ("LOOK",), "PROGRAM": ("PROG",),
    "PLC": (), "PLCC": (), "FORWARD": ("FWD",), "INVERSE": ("INV",), "BINARY": (),
    "CCBUF": (), "COMP": (), "TCOMP": (), "BLCOMP": (), "UBUFFER": ("UBUF",), "TEMPS": (),
    "LDS": (), "LINK": (), "ALL": (), "TRACE": (), "SERVO": (),
    "TRIGGER": (),
}  # fmt: skip

#: Object spelling -> its long form.
OBJECTS: Final[dict[str, str]] = {
    s: name for name, short in SPELLINGS.items() for s in (name, *short)
}

__all__ = ["OBJECTS", "SPELLINGS"]
