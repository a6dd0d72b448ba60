"""On-line commands for PLC programs (TSRM p271, p424; spec §9.5).

They are parsed by :mod:`motionsim.sim.pmac.language.parser` with the other on-line commands and
executed by
the terminal through :class:`motionsim.sim.pmac.tasks.plc.PlcTable`. The statements *inside* a PLC
program
are in :mod:`motionsim.sim.pmac.language.plc_parser`.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class OpenPlc:
    """``OPEN PLC n`` / ``OPEN PLCC n`` (0..31, ``compiled``): open PLC ``n`` for entry on
    this port (ERR007 if any buffer is already open)."""

    n: int
    compiled: bool = False


@dataclass(frozen=True, slots=True)
class EnablePlc:
    """``ENABLE PLC n[,n...]`` / ``ENABLE PLC n..m`` (``enable``) or the same with ``DISABLE``;
    ``compiled`` for ``PLCC``."""

    numbers: tuple[int, ...]
    enable: bool
    compiled: bool = False


@dataclass(frozen=True, slots=True)
class Clear:
    """``CLEAR``: erase the contents of the open PLC buffer."""


@dataclass(frozen=True, slots=True)
class ClearAllPlcs:
    """``CLEAR ALL PLCS``: erase every PLC program buffer (TSRM on-line commands ``[BK]``)."""


@dataclass(frozen=True, slots=True)
class DeletePlcc:
    """``DELETE PLCC n[,n...|..m]``, or ``DELETE PLCC`` alone for all: erase compiled PLCs
    (PUM-V p245: they stay until ``DELETE PLCC`` or a new compiled download). An erased PLCC
    that was enabled stops (its ``plc`` event says ``disabled``) ``[INF]``; an on-line command
    only, refused inside a PLC (``in_program``)."""

    numbers: tuple[int, ...]

    @property
    def in_program(self) -> bool:
        return False



N_PLCS = 32

__all__ = ["N_PLCS", "Clear", "ClearAllPlcs", "DeletePlcc", "EnablePlc", "OpenPlc"]
