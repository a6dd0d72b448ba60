"""System and fieldbus functions with several arguments: ETHERCAT, ETHERNET, PEEK, PROFINET,
MODBUS, ETHERNETIP, CO_READ, CO_WRITE — as statements (``ETHERCAT(0, 0)``) and as values
(``IF ETHERCAT($22, 0, -1) ...``, ``ok = CO_READ(...)``).

One row of :data:`BUS_FUNCTIONS` per name: the argument counts accepted (the documented forms
take up to 16 numbers ``[INF]``) and the function that answers it. Each call logs a ``setup``
event (``command``, ``args``), as the other set-up commands do. As a value a call answers what
the function reads, else TRUE (-1) when it succeeded ``[BK]``: MC4 commands used as functions
return TRUE / FALSE.

**EtherCAT** is modelled as far as a start-up program polls it (:class:`EtherCat`): one
network (any slot number is that network ``[INF]``) of ``ethercat_slaves`` slaves (config;
default: one drive per axis ``[INF]``), operational at power-up ``[INF]``. The function numbers
and states come from Trio-controller host code (spec §11.7, a host tool's ``EthercatState``:
0 Init, 1 Pre-Operational, 2 Safe-Operational, 3 Operational) and start-up programs:

* ``ETHERCAT(0, slot[, mode])`` — (re)start the network: it scans its slaves and is in
  Operational at once (no bus start-up time is simulated ``[INF]``);
* ``ETHERCAT(1, slot)`` — stop it: Init;
* ``ETHERCAT(3, slot[, vr])`` — the number of slaves; ``ETHERCAT($21, slot, state[, ...])``
  — request a state 0..3; ``ETHERCAT($22, slot[, vr])`` — the state;
* the result of 3 and $22 goes to ``VR(vr)``; with no vr, or vr = -1, it is printed as a
  whole number (``ETHERCAT($22,0,-1)`` prints ``3``: a host reads it as an integer);
* ``ETHERCAT($64, axis, ...)`` — reset the fault of the drive of ``axis`` ``[BK]`` (real
  error handlers issue it for an EtherCAT axis, ATYPE 65, whose AXISSTATUS is not 0): a
  simulated drive has no fault of its own, so it succeeds and changes nothing (the
  controller's axis errors are cleared by DATUM(0), as on the card);
* any other function number is a run-time error naming it: not simulated.

**ETHERNET(rw, slot, function[, value ...])**: ``rw`` 0 reads (the statement prints it:
``ETHERNET(0,-1,0)`` → ``192.168.0.250``, M216-547; as a value it is the number read, TRUE for
an address), 1 writes, kept per function number (``ETHERNET(1,-1,10,502)`` Modbus port, §3.3);
2 sets a Modbus TCP mode on the MC2xx (``ETHERNET(2,slot,9,1)``: holding registers are TABLE
instead of VR, M224-550; read by :meth:`TrioController.modbus_registers`).

**PEEK, PROFINET, MODBUS, ETHERNETIP, CO_READ, CO_WRITE** parse in every argument form, and
when they run they are a run-time error "... is not simulated" naming the function: no memory
map, PROFINET / EtherNet/IP device, Modbus master or CANopen network is simulated.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .basic_errors import BasicError

if TYPE_CHECKING:
    from ..run.context import Context

#: TRUE, the value of a call that succeeded [BK].
TRUE = -1.0
#: EtherCAT states (host tool ``EthercatState``; spec §11.7: 3 = operational).
INIT, PRE_OP, SAFE_OP, OPERATIONAL = 0, 1, 2, 3
#: ETHERNET read values at power-up: function -> value (0 IP address, 2 subnet mask, M216-547;
#: 10 Modbus TCP port 502, M224-550).
ETHERNET_POWER_UP: dict[int, Any] = {0: "192.168.0.250", 2: "255.255.255.0", 10: 502.0}


class EtherCat:
    """The controller's EtherCAT network as a start-up program sees it."""

    def __init__(self, slaves: int) -> None:
        self.slaves = slaves
        self.state = OPERATIONAL


#: ``(context, arguments, the statement form?) -> the call's value``.
Answer = Callable[["Context", tuple[float, ...], bool], float]


@dataclass(frozen=True, slots=True)
class BusFunction:
    """One system / fieldbus function: the argument counts it takes and its answer."""

    name: str
    low: int
    high: int
    run: Answer


def _hex(n: int) -> str:
    return f"${n:X}"


def _result(ctx: Context, value: float, args: tuple[float, ...], at: int, alone: bool) -> float:
    """A read's result: into ``VR(args[at])``, or printed as a whole number when that
    argument is -1 (or missing, in the statement form: ``alone``); the call's value is the
    result itself."""
    if len(args) > at and int(args[at]) != -1:
        ctx.set_vr(args[at], value)
    elif alone or len(args) > at:
        ctx.output(str(int(value)), True, None)
    return value


def _ethercat(ctx: Context, args: tuple[float, ...], alone: bool) -> float:
    fn = int(args[0])
    bus = ctx.ctrl.system.comms.ethercat
    if fn == 0:
        bus.state = OPERATIONAL
        return TRUE
    if fn == 1:
        bus.state = INIT
        return TRUE
    if fn == 3:
        return _result(ctx, float(bus.slaves), args, 2, alone)
    if fn == 0x21:
        if len(args) < 3 or int(args[2]) not in (INIT, PRE_OP, SAFE_OP, OPERATIONAL):
            raise BasicError("Parameter out of range: ETHERCAT($21, slot, state) needs a state "
                             "0..3")
        bus.state = int(args[2])
        return TRUE
    if fn == 0x22:
        return _result(ctx, float(bus.state), args, 2, alone)
    if fn == 0x64:
        ctx.axis_number(args[1])  # a drive fault reset [BK]: no simulated drive faults
        return TRUE
    raise BasicError(f"ETHERCAT function {_hex(fn)} is not simulated (simulated: 0, 1, 3, $21, "
                     "$22, $64)")


def _ethernet(ctx: Context, args: tuple[float, ...], alone: bool) -> float:
    rw, fn = int(args[0]), int(args[2])
    values = ctx.ctrl.system.comms.ethernet
    if rw == 0:
        v = values.get(fn, 0.0)
        if alone:
            ctx.output(v if isinstance(v, str) else ctx.number(v), True, None)
        return v if isinstance(v, float) else TRUE
    if rw in (1, 2):  # 2: the MC2xx Modbus mode settings, ETHERNET(2,slot,7|9,1) (§3.3)
        if len(args) < 4:
            raise BasicError(f"ETHERNET({rw}, slot, function, value...) needs a value")
        values[fn] = args[3] if len(args) == 4 else args[3:]
        return TRUE
    raise BasicError(f"Parameter out of range: ETHERNET read/write {args[0]:g}")


def _not_simulated(name: str, what: str) -> Answer:
    def run(ctx: Context, args: tuple[float, ...], alone: bool) -> float:
        raise BasicError(f"{name} is not simulated: no {what} is simulated")

    return run


BUS_FUNCTIONS: dict[str, BusFunction] = {f.name: f for f in (
    BusFunction("ETHERCAT", 2, 16, _ethercat),
    BusFunction("ETHERNET", 3, 16, _ethernet),
    BusFunction("PEEK", 1, 2, _not_simulated("PEEK", "controller memory map")),
    BusFunction("PROFINET", 1, 16, _not_simulated("PROFINET", "PROFINET device")),
    BusFunction("MODBUS", 1, 16, _not_simulated("MODBUS", "Modbus master connection")),
    BusFunction("ETHERNETIP", 1, 16, _not_simulated("ETHERNETIP", "EtherNet/IP adapter")),
    BusFunction("CO_READ", 1, 16, _not_simulated("CO_READ", "CANopen network")),
    BusFunction("CO_WRITE", 1, 16, _not_simulated("CO_WRITE", "CANopen network")),
)}


def call(ctx: Context, name: str, args: tuple[float, ...], alone: bool) -> float:
    """Run ``name`` for ``ctx``'s process (``alone``: the statement form, not a value), log
    it (a ``setup`` event) and give its value."""
    value = BUS_FUNCTIONS[name].run(ctx, args, alone)
    ctx.ctrl.log.emit("setup", command=name, args=list(args))
    return value


__all__ = ["BUS_FUNCTIONS", "ETHERNET_POWER_UP", "OPERATIONAL", "BusFunction", "EtherCat",
           "call"]
