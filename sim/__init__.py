"""motionsim's simulation core: SimPy models of motion-controller program buffering.

Pure: simpy and the standard library only — no asyncio, no wall clock, no I/O, no web types.
"""

from sim.controller import Controller, Port, Reply
from sim.errors import (
    BufferFull,
    Conflict,
    Halted,
    InvalidValue,
    MotionSimError,
    NotFound,
    ParseError,
)
from sim.events import Event, EventLog, Gap

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
