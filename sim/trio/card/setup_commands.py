"""Set-up commands a start-up program issues: ADDAX, ENCODER_RATIO, STEP_RATIO, INVERT_IN,
SETCOM, UNIT_CLEAR, TRIGGER (ETHERNET and ETHERCAT, also values, are
:mod:`motionsim.sim.trio.card.fieldbus`'s).

A command is one row of :data:`COMMANDS` — its argument counts and the function that runs it
— so the parser accepts exactly these forms and a new command is one row. Each logs a
``setup`` event (``command``, ``args``, ``axis``) when it runs. Facts (spec §11.5, §11.7):

* ``ADDAX(axis)`` — the demand-position changes of ``axis`` are added, in encoder edges, to
  the base axis' own moves until ``ADDAX(-1)`` (M216-203, TRM p. 8-13; TJ2P-38):
  :mod:`motionsim.sim.trio.addax`;
* ``ENCODER_RATIO(den, num)`` — MPOS = num/den × encoder edges, 0..16777215 each (TJCJ-159):
  the simulated servo loop still makes MPOS follow DPOS, so the ratio shows in the raw
  ``ENCODER`` count (:mod:`motionsim.sim.trio.card.scaling`); ``STEP_RATIO(den, num)`` the same for
  the step output (``STEP_RATIO(-1,1)`` reverses it, real start-up code) — stored, there is no
  step output to read;
* ``INVERT_IN(n, ON|OFF)`` — input n reads inverted (IN and the datum input see the same
  inverted value ``[BK]``);
* ``SETCOM(baud, data, stop, parity, port[, mode])`` — RS-232 default 9600, 7, 2, even
  (M206-252, TRM p. 8-62); kept per port, no serial line is simulated;
* ``UNIT_CLEAR`` — clears unit (drive, bus) errors: there are none ``[BK]``;
* ``TRIGGER[(mode)]`` — starts the capture SCOPE armed, one shot (0) or automatic (1)
  (:mod:`motionsim.sim.trio.run.scope`); nothing while SCOPE is off.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .basic_errors import BasicError
from .fieldbus import ETHERNET_POWER_UP, EtherCat

if TYPE_CHECKING:
    from ..run.context import Context

Run = Callable[["Context", tuple[float, ...], int], None]

#: ENCODER_RATIO / STEP_RATIO: largest numerator and denominator (TJCJ-159).
RATIO_MAX = 16_777_215


@dataclass(frozen=True, slots=True)
class Command:
    """One set-up command: the argument counts it takes and what it does."""

    name: str
    low: int
    high: int
    run: Run
    axis_command: bool = False  # acts on the base axis (takes ``AXIS(n)``)


def _ratio(ctx: Context, name: str, args: tuple[float, ...], n: int,
           negative_ok: bool) -> tuple[float, float]:
    den, num = args
    for v in (den, num):
        if v != int(v) or abs(v) > RATIO_MAX or (v < 0 and not negative_ok):
            raise BasicError(f"Parameter out of range: {name}({den:g},{num:g})")
    if den == 0 or num == 0:
        raise BasicError(f"Parameter out of range: {name}({den:g},{num:g})")
    return den, num


def _addax(ctx: Context, args: tuple[float, ...], n: int) -> None:
    other = int(args[0])
    if other != args[0]:
        raise BasicError(f"Parameter out of range: ADDAX({args[0]:g})")
    axes = ctx.ctrl.axes
    if other == -1:
        axes[n].add_axis(None)
        return
    link = axes[ctx.axis_number(other)]
    try:
        axes[n].add_axis(link)
    except ValueError as exc:
        raise BasicError(str(exc)) from None


def _encoder_ratio(ctx: Context, args: tuple[float, ...], n: int) -> None:
    ctx.ctrl.axes[n].encoder_ratio = _ratio(ctx, "ENCODER_RATIO", args, n, False)


def _step_ratio(ctx: Context, args: tuple[float, ...], n: int) -> None:
    ctx.ctrl.axes[n].step_ratio = _ratio(ctx, "STEP_RATIO", args, n, True)


def _invert_in(ctx: Context, args: tuple[float, ...], _n: int) -> None:
    io = ctx.ctrl.io
    io.invert(io.channel(args[0], "INVERT_IN"), args[1] != 0.0)


#: SETCOM argument ranges: data bits 7/8, stop bits 1/2, parity 0 none / 1 odd / 2 even.
_SETCOM_CHOICES = ((1, (7, 8)), (2, (1, 2)), (3, (0, 1, 2)))


def _setcom(ctx: Context, args: tuple[float, ...], _n: int) -> None:
    if args[0] <= 0:
        raise BasicError(f"Parameter out of range: SETCOM baud rate {args[0]:g}")
    for i, allowed in _SETCOM_CHOICES:
        if int(args[i]) not in allowed:
            raise BasicError(f"Parameter out of range: SETCOM argument {i + 1} = {args[i]:g}")
    ctx.ctrl.system.comms.setcom[int(args[4])] = args


def _log_only(ctx: Context, args: tuple[float, ...], _n: int) -> None:
    """UNIT_CLEAR: nothing to clear (logged by the caller)."""


def _trigger(ctx: Context, args: tuple[float, ...], _n: int) -> None:
    ctx.ctrl.scope.trigger(args[0] if args else 0.0)


COMMANDS: dict[str, Command] = {c.name: c for c in (
    Command("ADDAX", 1, 1, _addax, axis_command=True),
    Command("ENCODER_RATIO", 2, 2, _encoder_ratio, axis_command=True),
    Command("STEP_RATIO", 2, 2, _step_ratio, axis_command=True),
    Command("INVERT_IN", 2, 2, _invert_in),
    Command("SETCOM", 5, 6, _setcom),
    Command("UNIT_CLEAR", 0, 0, _log_only),
    Command("TRIGGER", 0, 1, _trigger),
)}


class Comms:
    """What the communication set-up commands wrote (per controller, power-up values), and
    the EtherCAT network of ``slaves`` slaves (:mod:`~.fieldbus`)."""

    def __init__(self, slaves: int = 0) -> None:
        self.setcom: dict[int, tuple[float, ...]] = {}
        self.ethernet: dict[int, Any] = dict(ETHERNET_POWER_UP)
        self.ethercat = EtherCat(slaves)


def run_command(ctx: Context, name: str, args: tuple[float, ...], axis: float | None) -> None:
    """Run the set-up command ``name`` for ``ctx``'s process (``axis``: its AXIS(n))."""
    cmd = COMMANDS[name]
    n = ctx.base_axis(axis) if cmd.axis_command else -1
    cmd.run(ctx, args, n)
    fields: dict[str, Any] = {"command": name, "args": list(args)}
    if cmd.axis_command:
        fields["axis"] = n
    ctx.ctrl.log.emit("setup", **fields)


__all__ = ["COMMANDS", "Command", "Comms", "run_command"]
