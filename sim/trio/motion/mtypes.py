"""MTYPE / NTYPE codes: what an axis' move buffers report for the move they hold.

0 = idle; 1 MOVE, 2 MOVEABS, 4 MOVECIRC, 10 FORWARD are confirmed by TN20 and the Trajexia
manual (TJ2P-20); the others come from two independent third-party enums that agree on 0..31
and with every confirmed code (spec §1.5, §10.1). TN20 sends the reader to chapter 8 of the
TRM for the list; that page was not reachable.
"""

from __future__ import annotations

IDLE = 0

MTYPE: dict[str, int] = {
    "MOVE": 1,
    "MOVEABS": 2,
    "MHELICAL": 3,
    "MOVECIRC": 4,
    "MOVEMODIFY": 5,
    "MOVESP": 6,
    "MOVEABSSP": 7,
    "MOVECIRCSP": 8,
    "MHELICALSP": 9,
    "FORWARD": 10,
    "REVERSE": 11,
    "DATUM": 12,
    "CAM": 13,
    "CAMBOX": 20,
    "CONNECT": 21,
    "MOVELINK": 22,
}

#: The SP moves: same geometry as the move named, run at FORCE_SPEED (spec §10.2 ``[BK]``).
SP_GEOMETRY = {"MOVESP": "MOVE", "MOVEABSSP": "MOVEABS", "MOVECIRCSP": "MOVECIRC",
               "MHELICALSP": "MHELICAL"}

#: Axes a motion command drives when it is not one per argument (MOVE / MOVEABS are).
_FIXED_GROUP = {
    "MOVECIRC": 2, "MHELICAL": 3, "MOVECIRCSP": 2, "MHELICALSP": 3, "FORWARD": 1, "REVERSE": 1,
    "DATUM": 1, "MOVEMODIFY": 1, "CAM": 1, "CAMBOX": 1, "CONNECT": 1, "MOVELINK": 1,
}


def axes_driven(kind: str, n_args: int) -> int:
    """How many axes the motion command ``kind`` with ``n_args`` arguments drives."""
    return _FIXED_GROUP.get(kind, n_args)


__all__ = ["IDLE", "MTYPE", "SP_GEOMETRY", "axes_driven"]
