"""The mapping table: card memory addresses that show simulated state.

An M-variable pointed at one of these addresses reads (and where marked, writes) the
simulator's state instead of plain memory. Addresses from the Turbo SRM's status-word tables
(TSRM p281–287; spec pmac.md §3, §9.4) and Delta Tau's suggested M-variable definitions,
checked against public definition files that carry them (``M161->D:$000088``,
``M162->D:$00008B``, ``M166->X:$00009D,0,24,S``, ``M145->Y:$0000C0,10,1``; motor xx at
``+$80·(xx−1)``):

| address (motor xx, CS x) | M-variable | what |
|---|---|---|
| ``X:$0000B0 + $80·(xx−1)`` | Mxx30..39 bits | motor status word 1 (``#xx?`` digits 1–6) |
| ``Y:$0000C0 + $80·(xx−1)`` | Mxx40..49 | motor status word 2 (Mxx45: bit 10, home complete) |
| ``D:$000088 + $80·(xx−1)`` | Mxx61 | commanded position, 1/(Ixx08·32) counts |
| ``D:$00008B + $80·(xx−1)`` | Mxx62 | actual position, 1/(Ixx08·32) counts (writable) |
| ``D:$000091 + $80·(xx−1)`` | | following error, 1/(Ixx08·32) counts (0: the loop tracks exactly) |
| ``X:$00009D + $80·(xx−1)`` | Mxx66 | actual velocity, 1/(Ixx09·32) counts per servo cycle |
| ``L:$0000D7 + $80·(xx−1)`` | Mxx72 | variable jog target or distance, counts (``J=*``) |
| ``X:$002040 + $100·(x−1)`` | Msx80.. bits | CS status word 1 (``&x??`` digits 1–6) |
| ``Y:$00203F + $100·(x−1)`` | | CS status word 2 (digits 7–12) |
| ``Y:$002040 + $100·(x−1)`` | | CS status word 3 (digits 13–18) |

The following-error register (motor base + $11, a 48-bit fixed-point word) is where
Delta Tau's gathering tools point a gather source for "motor following error", beside
commanded position (+$08), actual position (+$0B) and unfiltered actual velocity (+$1D, X)
(dls-pmac-control ``gatherchannel.py``, spec pmac.md §11.8); data gathering
(:mod:`motionsim.sim.pmac.tasks.gather`) reads these registers through card memory.

Timing registers (the standard Geo Brick M-variable file's definitions; a CPU-load PLC reads
M70..M73 and computes duty cycles from them), in DSP clock cycles / 2 at ``CPU_HZ``:

| address | M-variable | what | simulated |
|---|---|---|---|
| ``X:$000000`` (24-bit, S) | M100 | servo cycle counter | servo cycles since power-on, mod 2**24 |
| ``X:$FFFF8C`` | M70 | time between phase interrupts | phase period (servo period / (I7002+1)) |
| ``X:$000037`` | M71 | time of the phase tasks | 0 (phase tasks are not modelled) |
| ``Y:$000037`` | M72 | time of the servo tasks | servo share × servo period |
| ``X:$00000B`` | M73 | time of the RTI tasks | RTI share × RTI period |
| ``X:$000025`` | M80 | minimum watchdog timer count | 0 (not modelled) |

``CPU_HZ`` is 240 MHz, a DSP56321's clock ``[INF]``.

Everything else (the Geo Brick's general-purpose I/O at ``Y:$078800``/``Y:$078802``, user
memory, DPRAM; :mod:`.memory_map`) is plain memory: written values stay and read back.
Writing Mxx62 sets the motor's position through the controller's ``set_motor_position``
where it has one
(``[INF]``: following error 0, so actual = commanded); status words are read-only.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

if TYPE_CHECKING:
    from ..controller import PmacController


class Card(Protocol):
    """What the mapping table reads from the controller."""

    def motor_status(self, motor: int) -> tuple[int, int]: ...
    def motor_report(self, motor: int, what: str) -> float: ...
    def cs_status(self, cs: int) -> tuple[int, int, int]: ...
    def ivar(self, n: int) -> float: ...
    def servo_count(self) -> int: ...
    def task_shares(self) -> tuple[float, float, float]: ...


@dataclass(frozen=True, slots=True)
class Register:
    """One mapped register: ``read()`` gives the raw integer (24-bit word or 48-bit long);
    ``write(raw)`` is None for a read-only register."""

    read: Callable[[], int]
    write: Callable[[int], None] | None = None


CPU_HZ = 240e6
N_MOTORS = 32
N_CS = 16
MOTOR_STEP = 0x80
CS_STEP = 0x100


#: Offsets of the motor registers from the motor's base ``$80·(xx−1)`` (table above).
COMMANDED_POSITION = 0x88
ACTUAL_POSITION = 0x8B
FOLLOWING_ERROR = 0x91
ACTUAL_VELOCITY = 0x9D
#: ``X:$000000``, the servo cycle counter.
SERVO_COUNTER = 0x000000

#: ``(space, offset)`` -> what :func:`motor_register` names it.
_MOTOR_REGISTERS = {("D", COMMANDED_POSITION): "P", ("D", ACTUAL_POSITION): "P",
                    ("D", FOLLOWING_ERROR): "F", ("X", ACTUAL_VELOCITY): "V"}


def motor_register(space: str, address: int) -> tuple[int, str] | None:
    """``(motor, what)`` when ``space:address`` is a motor's position (``P``, commanded or
    actual: the same value, following error 0), following-error (``F``) or velocity (``V``)
    register of the table, in the units :func:`position_raw` / :func:`velocity_raw` give;
    None otherwise. Data gathering (:mod:`motionsim.sim.pmac.tasks.gather_readers`) reads
    these from the trajectory at each sample's instant instead of through the table."""
    for (sp, offset), what in _MOTOR_REGISTERS.items():
        motor, rest = divmod(address - offset, MOTOR_STEP)
        if sp == space and rest == 0 and 0 <= motor < N_MOTORS:
            return motor + 1, what
    return None


def report_at(position: Callable[[float], float], what: str, t: float, period_s: float) -> float:
    """A motor's ``P`` / ``V`` / ``F`` report at ``t`` from its position function (counts):
    ``P`` the position to 1/10 count, ``V`` counts per servo cycle averaged over the last
    cycle (0 at t = 0), ``F`` the following error, 0 (the loop tracks perfectly ``[INF]``).
    The controller's reports (:meth:`PmacController.motor_report`) and data gathering's
    batch reads (:mod:`motionsim.sim.pmac.tasks.gather_readers`) both call this."""
    if what == "F":
        return 0.0
    p1 = position(t)
    if what == "P":
        return round(p1, 1)
    p0 = position(max(0.0, t - period_s))
    return round(p1 - p0, 3) if t > 0 else 0.0


def position_raw(counts_report: float, ixx08: float) -> int:
    """A position register's raw value: the ``P`` report (counts to 1/10) in 1/(Ixx08·32)
    counts."""
    return round(counts_report * ixx08 * 32)


def velocity_raw(velocity_report: float, ixx09: float) -> int:
    """The velocity register's raw value: the ``V`` report (counts per servo cycle) in
    1/(Ixx09·32) counts per cycle."""
    return round(velocity_report * ixx09 * 32)


def variable_jog_address(motor: int) -> int:
    """Where motor ``motor``'s variable jog register (Mxx72, a 48-bit float) sits."""
    return 0xD7 + MOTOR_STEP * (motor - 1)


def table(card: Card, set_position: Callable[[int, float], None] | None) -> dict[
    tuple[str, int], Register
]:
    """``{(space, address): Register}`` with space ``X``, ``Y`` or ``D`` (48-bit longs)."""
    out: dict[tuple[str, int], Register] = {}
    for xx in range(1, N_MOTORS + 1):
        base = MOTOR_STEP * (xx - 1)
        out[("X", 0xB0 + base)] = Register(lambda xx=xx: card.motor_status(xx)[0])
        out[("Y", 0xC0 + base)] = Register(lambda xx=xx: card.motor_status(xx)[1])

        def position(xx: int = xx) -> int:
            return position_raw(card.motor_report(xx, "P"), card.ivar(100 * xx + 8))

        def set_actual(raw: int, xx: int = xx) -> None:
            if set_position is not None:
                set_position(xx, raw / (card.ivar(100 * xx + 8) * 32))

        def velocity(xx: int = xx) -> int:
            return velocity_raw(card.motor_report(xx, "V"), card.ivar(100 * xx + 9))

        def following_error(xx: int = xx) -> int:
            return position_raw(card.motor_report(xx, "F"), card.ivar(100 * xx + 8))

        out[("D", COMMANDED_POSITION + base)] = Register(position)
        out[("D", ACTUAL_POSITION + base)] = Register(position, set_actual)
        out[("D", FOLLOWING_ERROR + base)] = Register(following_error)
        out[("X", ACTUAL_VELOCITY + base)] = Register(velocity)
    _timing(card, out)
    for x in range(1, N_CS + 1):
        base = CS_STEP * (x - 1)
        out[("X", 0x2040 + base)] = Register(lambda x=x: card.cs_status(x)[0])
        out[("Y", 0x203F + base)] = Register(lambda x=x: card.cs_status(x)[1])
        out[("Y", 0x2040 + base)] = Register(lambda x=x: card.cs_status(x)[2])
    return out


def _timing(card: Card, out: dict[tuple[str, int], Register]) -> None:
    """The servo counter and the task-time registers (table in the module docstring)."""

    def half_cycles(seconds: float) -> int:
        return min(0xFFFFFF, round(seconds * CPU_HZ / 2))

    def phase_period() -> float:
        return card.task_shares()[2] / (card.ivar(7002) + 1)

    out[("X", SERVO_COUNTER)] = Register(lambda: card.servo_count() & 0xFFFFFF)
    out[("X", 0xFFFF8C)] = Register(lambda: half_cycles(phase_period()))
    out[("X", 0x000037)] = Register(lambda: 0)
    out[("Y", 0x000037)] = Register(
        lambda: half_cycles(card.task_shares()[0] * card.task_shares()[2]))
    out[("X", 0x00000B)] = Register(
        lambda: half_cycles(card.task_shares()[1] * card.task_shares()[2] * (card.ivar(8) + 1)))
    out[("X", 0x000025)] = Register(lambda: 0)


class _ControllerCard:
    """The narrow view of a :class:`PmacController` the table reads."""

    def __init__(self, ctl: PmacController) -> None:
        self.motor_status = ctl.motor_status
        self.motor_report = ctl.motor_report
        self.ivar = ctl.vars.I
        self._ctl = ctl

    def cs_status(self, cs: int) -> tuple[int, int, int]:
        w1, w2, w3 = self._ctl.coord_system(cs).status_words()
        return w1, w2, w3

    def servo_count(self) -> int:
        clock = self._ctl.scheduler.clock
        return int(clock.index(self._ctl.env.now))

    def task_shares(self) -> tuple[float, float, float]:
        """(servo share, RTI share, servo period s) of the processor now."""
        load = self._ctl.background.load()
        return load["servo"], load["rti"], self._ctl.scheduler.period_s


def for_controller(ctl: PmacController) -> dict[tuple[str, int], Register]:
    """The mapping table of ``ctl`` (``set_motor_position`` used where it exists)."""
    return table(_ControllerCard(ctl), getattr(ctl, "set_motor_position", None))


__all__ = [
    "Card", "Register", "for_controller", "motor_register", "position_raw", "report_at",
    "table", "velocity_raw",
]  # fmt: skip
