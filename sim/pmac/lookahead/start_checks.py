"""May a coordinate system start motion? The card's refusals of ``R``, ``S`` and the other
commands that start a CS's motion (the REST run, ``CMD"R"`` from a PLC — they all reach
:meth:`motionsim.sim.pmac.controller.PmacController.run`).

The Turbo PMAC error table (TSRM I6, PSRM p25-26; spec §2.2, §11.10) gives one code per reason
a CS cannot start, and the checks run in the table's order, one motor after the other
(motor number order) for each ``[INF]`` (the manual does not say which of two reasons wins):

* ERR011 "previous move not completed": a motor of the CS is still making an on-line move of
  its own — a jog, a jog-to-position or a homing search (its jog / home command is under
  way, even during its Ixx92 calculation delay);
* ERR012 "a motor in the coordinate system is open-loop": open loop (``O``) or killed (``K``,
  CTRL-K);
* ERR013 "a motor in the coordinate system is not activated": Ixx00 = 0;
* ERR014 "no motors in the coordinate system": no motor has an axis definition in the CS
  (``#n->X``, ``#n->I``) — only when ``strict_cs_motors`` (below) asks for it.

A refused start changes nothing: no program pointer, no run, no event; a jog in progress goes
on and can be stopped (``J/``), since the CS never started.

``[INF]`` ERR014: the simulator's own programs and scenarios have always run coordinate
systems with no motors (their axes move with nothing attached, a virtual machine), so the
check is the controller config key ``strict_cs_motors`` — true makes a motorless CS refuse to
start as the card does. The default stays false so that existing scenarios keep their logs.
The manual's order itself does not stand in the way of applying it always: a CS with no motors
has no motor for ERR011-ERR013 to name, so ERR014 is the only refusal it can meet, as last in
the table (issue 37 review); only the motorless scenarios, tests and golden logs do.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from ...errors import Conflict
from ..card.variables import ixx

if TYPE_CHECKING:
    from ..card.variables import Variables
    from ..motor.motors import Motor


def check_start(cs: int, motors: Iterable[Motor], vars_: Variables, strict: bool) -> None:
    """Raise the card's refusal for starting CS ``cs`` whose motors are ``motors``.

    Raises:
        Conflict: ERR011, ERR012, ERR013 or ERR014 (module docstring), naming the motor.
    """
    motors = sorted(motors, key=lambda m: m.n)
    for m in motors:
        if m.command is not None:
            raise Conflict(f"motor {m.n} of CS {cs} is still making its {m.command} move: "
                           "previous move not completed", pmac_error="ERR011")
    for m in motors:
        if m.loop != "closed_loop":
            what = "killed" if m.loop == "killed" else "open loop"
            raise Conflict(f"motor {m.n} of CS {cs} is {what}: close its loop first (J/, $)",
                           pmac_error="ERR012")
    for m in motors:
        if vars_.I(ixx(m.n, 0)) == 0:
            raise Conflict(f"motor {m.n} of CS {cs} is not activated (I{m.n}00=0)",
                           pmac_error="ERR013")
    if strict and not motors:
        raise Conflict(f"no motors in CS {cs}", pmac_error="ERR014")


__all__ = ["check_start"]
