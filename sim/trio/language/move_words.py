"""The motion commands of Trio BASIC and the arguments each takes: the language's half of a move.

``MOVE_ARGS`` is every command that enters the buffers with the argument counts it accepts
(the parser checks them; the REST move endpoint too). ``LINKED`` adds, for the moves linked to
another axis or to the TABLE (CONNECT, CAM, CAMBOX, MOVELINK; TRM chapter 8, spec §10.3), the
index of the link-axis argument, which :mod:`motionsim.sim.trio.motion.linked` reads when it
binds the move.
"""

from __future__ import annotations

#: Linked moves: argument count range, index of the link-axis argument (or None).
LINKED: dict[str, tuple[int, int, int | None]] = {
    "CAM": (4, 4, None),
    "CAMBOX": (5, 8, 4),
    "CONNECT": (2, 2, 1),
    "MOVELINK": (5, 8, 4),
}

#: Motion commands that enter the buffers, with the argument counts they accept.
MOVE_ARGS: dict[str, tuple[int, int]] = {
    "MOVE": (1, 8),
    "MOVEABS": (1, 8),
    "MOVECIRC": (5, 5),
    "MHELICAL": (6, 6),
    "FORWARD": (0, 0),
    "REVERSE": (0, 0),
    "DATUM": (1, 1),
    "MOVESP": (1, 8),
    "MOVEABSSP": (1, 8),
    "MOVECIRCSP": (5, 5),
    "MHELICALSP": (6, 6),
    "MOVEMODIFY": (1, 1),
    **{kind: (lo, hi) for kind, (lo, hi, _link) in LINKED.items()},
}

__all__ = ["LINKED", "MOVE_ARGS"]
