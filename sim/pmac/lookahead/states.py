"""Program states of a coordinate system and their legal transitions.

``program`` events: idle → running ⇄ waiting → stopped | aborted; running again only through
``R`` / ``S``. ``waiting`` is still running in the controller's sense: the rotary buffer ran
out of lines and the next line arriving is calculated and started without a new ``R``.
"""

from __future__ import annotations

IDLE, RUNNING, WAITING, STOPPED, ABORTED = "idle", "running", "waiting", "stopped", "aborted"

#: Legal program-state transitions.
TRANSITIONS: dict[str, frozenset[str]] = {
    IDLE: frozenset({RUNNING}),
    RUNNING: frozenset({WAITING, STOPPED, ABORTED}),
    WAITING: frozenset({RUNNING, STOPPED, ABORTED}),
    STOPPED: frozenset({RUNNING, ABORTED}),
    ABORTED: frozenset({RUNNING}),
}

__all__ = ["ABORTED", "IDLE", "RUNNING", "STOPPED", "TRANSITIONS", "WAITING"]
