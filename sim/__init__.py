"""motionsim's simulation core: SimPy models of motion-controller program buffering.

Pure: simpy and the standard library only — no asyncio, no wall clock, no I/O, no web types.
"""

from .controller import Controller, Port, Reply
from .errors import (
    BufferFull,
    Conflict,
    Halted,
    InvalidValue,
    MotionSimError,
    NotFound,
    ParseError,
)
from .events import Event, EventLog, Gap

__all__ = [
    "BufferFull",
    "Conflict",
    "Controller",
    "Event",
    "EventLog",
    "Gap",
    "Halted",
    "InvalidValue",
    "MotionSimError",
    "NotFound",
    "ParseError",
    "Port",
    "Reply",
]
