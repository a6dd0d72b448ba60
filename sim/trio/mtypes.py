"""MTYPE / NTYPE codes: what an axis' move buffers report for the move they hold.

0 = idle; 1 MOVE, 2 MOVEABS, 4 MOVECIRC, 10 FORWARD are confirmed by TN20 and the Trajexia
manual; 3 MHELICAL, 11 REVERSE, 12 DATUM come from a third-party enum consistent with them
(spec §1.5).
"""

from __future__ import annotations

IDLE = 0

MTYPE: dict[str, int] = {
    "MOVE": 1,
    "MOVEABS": 2,
    "MHELICAL": 3,
    "MOVECIRC": 4,
    "FORWARD": 10,
    "REVERSE": 11,
    "DATUM": 12,
}

#: Axes a motion command drives when it is not one per argument (MOVE / MOVEABS are).
_FIXED_GROUP = {"MOVECIRC": 2, "MHELICAL": 3, "FORWARD": 1, "REVERSE": 1, "DATUM": 1}


def axes_driven(kind: str, n_args: int) -> int:
    """How many axes the motion command ``kind`` with ``n_args`` arguments drives."""
    return _FIXED_GROUP.get(kind, n_args)


__all__ = ["IDLE", "MTYPE", "axes_driven"]
