"""``E``: enable the motors of the addressed coordinate system (on-line, CS-specific).

Diamond's EPICS ``pmac`` driver sends ``&{cs}E`` before every trajectory scan's
``&{cs}B{prog}R`` ("make sure the axes are enabled", ``pmacHardwareTurbo::getCSEnableCommand``;
its change "A(bort) to E(nable) for coordinate system pre-move commands", pmac PR #37, and
"``&%de`` works for Turbo PMAC", commit 5e6b515). The Turbo SRM page for ``E`` was not
retrieved (spec §2.2) ``[BK]``: what is modelled is what the driver relies on, the
coordinate-system form of ``$`` / ``J/`` for every motor of the CS:

* each motor with an axis definition in the addressed CS that is killed or open loop has its
  loop closed at its present position (as ``$`` does for one motor, TSRM p271); a motor
  already in closed loop is left alone — a jog or a running program goes on ``[INF]``;
* no data reply; a CS with no motors answers nothing either ``[INF]``;
* while the CS runs a program all its motors are closed-loop (a kill aborts the program), so
  ``E`` then changes nothing and is not refused ``[INF]``.

With a buffer open ``E`` is still an on-line command: the motion-program ``E`` is not a
Turbo PMAC word ``[INF]``.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class EnableCS:
    """``E`` (run by its row in :mod:`motionsim.sim.pmac.host.commands`)."""


__all__ = ["EnableCS"]
