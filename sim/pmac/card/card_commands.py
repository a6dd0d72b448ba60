"""``SAVE``, ``$$$`` and ``$$$***``: the card's flash memory and its resets.

* ``SAVE`` copies the active setup to flash (TUM p243): here the I-variables, the M-variable
  definitions, the P-variables, the axis definitions and the PLC programs. It is acknowledged
  with the plain ACK ``[INF]`` (over Ethernet a real card may answer a lone NUL, which
  dls-pmaclib also accepts; spec §11.9).
* ``$$$`` resets the card as at power-on: everything not saved is lost (rotary buffers, gather,
  lookahead, programs running), and the saved setup is loaded back; PLC programs that were
  saved are loaded enabled, so I5 decides which run, as at power-up ``[BK]``.
* ``$$$***`` re-initialises: factory defaults (:mod:`motionsim.sim.pmac.card.factory`) into active
  memory, buffers cleared; the saved copy stays in flash but is not used (TUM p243).

The reset happens at the end of the background cycle that answered the command (its reply,
the ACK, goes out first) ``[INF]``; a ``reset`` event is logged as for a REST reset.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ...simpy_adapter import wake_at

if TYPE_CHECKING:
    from ..controller import PmacController


@dataclass(frozen=True, slots=True)
class Save:
    """``SAVE``."""


@dataclass(frozen=True, slots=True)
class Reset:
    """``$$$`` (``factory`` False) or ``$$$***`` (``factory`` True)."""

    factory: bool


@dataclass
class Flash:
    """What ``SAVE`` stored (None: nothing saved since the card was made)."""

    setup: dict[str, Any] | None = None


def save(ctl: PmacController) -> None:
    """``SAVE``: snapshot the setup into the controller's flash."""
    v = ctl.vars
    ctl.flash.setup = {
        "i": dict(v.i),
        "p": dict(v.p),
        "mdefs": dict(v.mvars.defs),
        "motors": dict(ctl.motors),
        "plcs": {p.n: p.program for p in ctl.plcs.plcs if p.program is not None},
        "plccs": {p.n: p.program for p in ctl.plcs.compiled if p.program is not None},
    }


def schedule_reset(ctl: PmacController, factory: bool) -> None:
    """``$$$`` / ``$$$***``: reset once the command's background cycle has ended."""
    wake_at(ctl.env, ctl.env.now, lambda _ev: _reset(ctl, factory))


def _reset(ctl: PmacController, factory: bool) -> None:
    ctl.reset()
    setup = ctl.flash.setup
    if factory or setup is None:
        return
    v = ctl.vars
    v.i.update(setup["i"])
    v.version += 1
    v.p.update(setup["p"])
    v.mvars.defs.update(setup["mdefs"])
    ctl.motors.update(setup["motors"])
    for program_n, program in setup["plcs"].items():
        ctl.plcs.plc(program_n).program = program
    ctl.plcs.set_enabled(list(setup["plcs"]), True)
    # compiled PLCs need SAVE too and run again after a reset (PUM-V p245) [INF] enabled
    for program_n, program in setup.get("plccs", {}).items():
        ctl.plcs.compiled[program_n].program = program
    ctl.plcs.set_enabled(list(setup.get("plccs", {})), True, compiled=True)
    ctl.background.poke()


__all__ = ["Flash", "Reset", "Save", "save", "schedule_reset"]
