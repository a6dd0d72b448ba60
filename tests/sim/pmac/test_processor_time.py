"""The processor-time model (sim/pmac/tasks/cpu.py) under the loads the manual names: move planning
in the RTI (TUM p236, p376), a servo task that leaves nothing (TUM p238: an overloaded card
stops communicating and trips its watchdog), and a host command answered at the end of the
background cycle in progress (TUM p237). Costs are set in the config so the figures follow
from them; the card has no motors (the servo task takes no time) unless a test defines some.
"""

from __future__ import annotations

import math

import pytest

#: Every cost but move planning zero: an RTI's work is then exactly its planning.
PLANNING_ONLY = {
    "cpu_plan_line_us": 2000,
    "cpu_rti_base_us": 0,
    "cpu_plc_scan_us": 0,
    "cpu_plc_statement_us": 0,
}
PLAN_S = 2000e-6


def _planning_rig(make_rig, rti_base_us: float = 0, motors: int = 0):
    """PLC 0 enabled (it costs nothing here; it keeps the processor model accounting), a
    rotary buffer holding a LINEAR program of two set-up lines and four long moves, and
    ``motors`` motors at 20 µs of servo time each."""
    rig = make_rig(**{**PLANNING_ONLY, "cpu_rti_base_us": rti_base_us},
                   cpu_servo_motor_us=20)
    _define_motors(rig, motors)
    rig.c.plcs.load(0, "P1=P1+1")
    rig.ok("ENABLE PLC 0")
    rig.rotary_setup()
    rig.c.load_lines(1, ["LINEAR", "TM200", "X1", "X2", "X3", "X4"])
    return rig


def test_lines_stored_but_not_yet_calculated_cost_the_rti_nothing(make_rig):
    """Planning is done in the RTI for lines being calculated (TUM p236); lines waiting in
    the rotary buffer before ``R`` cost nothing, so no RTI overruns however long they are."""
    rig = _planning_rig(make_rig)
    rig.run_for(0.05)
    assert rig.events("line_calculated") == []
    assert rig.events("rti_overrun") == []


@pytest.mark.parametrize(("rti_base_us", "motors"), [(0, 0), (100, 0), (100, 8)])
def test_planning_several_lines_in_one_rti_overruns_until_the_work_is_done(make_rig,
                                                                          rti_base_us, motors):
    """``R`` calculates the set-up lines and the first moves in one go (two moves ahead for
    LINEAR, TUM p339): 5 lines at 2 ms each are 10 ms of RTI work. Every following RTI finds
    it unfinished and overruns (``over_s`` = what is left, in wall time at the share of the
    processor the motors' servo updates leave), its own fixed cost (``rti_base``) adding to
    the work, until it is done."""
    rig = _planning_rig(make_rig, rti_base_us, motors)
    share = 1.0 - rig.c.status()["cpu"]["servo"]
    rig.run_for(0.01)
    since = rig.c.log.last_seq
    rig.ok("R")
    rig.run_for(0.1)
    calculated = rig.events("line_calculated", since=since)
    assert [f["n"] for _, _, f in calculated] == [1, 2, 3, 4, 5]
    k_plan = calculated[0][0]
    assert {k for k, _, _ in calculated} == {k_plan}
    rti_cycles = rig.c.scheduler.rti_period_s() / rig.period
    rti_s = rig.c.scheduler.rti_period_s()
    base = rti_base_us * 1e-6
    overruns = rig.events("rti_overrun", since=since)
    left = [(5 * PLAN_S + n * (base - rti_s * share)) / share for n in range(1, 14)]
    expected = [x for x in left if x > 0]
    assert len(expected) >= 7
    assert [f["over_s"] for _, _, f in overruns] == pytest.approx(expected, abs=1e-9)
    assert [k for k, _, _ in overruns] == [
        k_plan + n * rti_cycles for n in range(1, len(expected) + 1)]


def test_a_line_calculated_later_costs_one_line_of_planning(make_rig):
    """When move 4 starts, the next line is calculated; its 2 ms of planning outlast one RTI
    period, so exactly one RTI overruns, by what is left of that one line. It is charged at
    the RTI at which the processor next looks at the line counters, at most two RTIs after
    the calculation ``[INF]``."""
    rig = _planning_rig(make_rig)
    rig.ok("R")
    rig.run_for(0.1)
    since = rig.c.log.last_seq
    rig.run_for(0.5)
    ((k_calc, _, line),) = rig.events("line_calculated", since=since)
    assert line["n"] == 6
    rti_s = rig.c.scheduler.rti_period_s()
    ((k_over, _, over),) = rig.events("rti_overrun", since=since)
    assert over["over_s"] == pytest.approx(PLAN_S - rti_s, abs=1e-9)
    rti_cycles = round(rti_s / rig.period)
    assert k_calc < k_over <= k_calc + 2 * rti_cycles


def test_a_streamed_program_with_plc0_fits_the_rti_at_the_default_costs(rig):
    """At the default costs (module docstring: tens of µs a line) planning a LINEAR program
    while a short PLC 0 runs takes a small share of the RTI: no RTI overruns, and the load
    figures are shares of the processor, none negative, adding up to one."""
    rig.c.plcs.load(0, "P1=P1+1")
    rig.ok("ENABLE PLC 0")
    rig.rotary_setup()
    rig.c.load_lines(1, ["LINEAR", "TM20"] + [f"X{n}" for n in range(1, 21)])
    rig.ok("R")
    rig.run_for(1.5)
    assert len(rig.events("line_calculated")) > 12
    assert rig.events("rti_overrun") == []
    cpu = rig.c.status()["cpu"]
    assert 0.0 < cpu["rti"] < 0.05
    assert cpu["background"] >= 0.0 and cpu["servo"] >= 0.0
    assert cpu["servo"] + cpu["rti"] + cpu["background"] == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("housekeeping_us", [20, 0])
@pytest.mark.parametrize("servo_us", [500, 600])
def test_a_servo_task_using_the_whole_processor_starves_rti_and_background(make_rig, servo_us,
                                                                          housekeeping_us):
    """Servo updates at 2 kHz (500 µs) costing ``servo_us`` each leave the lower-priority
    tasks nothing: no host command is answered, every RTI finds the last one's work still
    to do (it never ends: ``over_s`` infinite), the load shows the servo task alone, and the
    watchdog trips I40 servo cycles after the model woke (TUM p238, TSRM p57), whatever the
    housekeeping costs."""
    rig = make_rig(servo_hz=2000, cpu_servo_base_us=servo_us, i40=300,
                   cpu_housekeeping_us=housekeeping_us)
    reply = rig.c.terminal("I10")
    rig.run_for(0.1)
    cpu = rig.c.status()["cpu"]
    assert (cpu["servo"], cpu["rti"], cpu["background"]) == (1.0, 0.0, 0.0)
    overruns = rig.events("rti_overrun")
    assert len(overruns) > 50
    assert all(math.isinf(f["over_s"]) and f["over_s"] > 0 for _, _, f in overruns)
    rig.run_for(0.3)
    assert not reply.done
    ((k_trip, _, _),) = rig.events("watchdog")
    assert k_trip == 300


def _define_motors(rig, motors: int) -> None:
    """Assign motors 1..``motors`` to axes of CS 1 (each then takes servo time)."""
    for motor, axis in zip(range(1, motors + 1), "XYZABCUV", strict=False):
        rig.ok(f"&1 #{motor}->{axis}")


def _plc1_card(make_rig, motors: int, statements: int, host_us: float = 0):
    """A card whose background cycle is one scan of PLC 1, ``statements`` × 100 µs, all other
    background and RTI costs zero but ``host_us`` a host command, an RTI only every 256
    servo cycles (I8=255), and ``motors`` motors at 20 µs of servo time each."""
    rig = make_rig(i8=255, i5=2, cpu_housekeeping_us=0, cpu_host_command_us=host_us,
                   cpu_plc_scan_us=0, cpu_rti_base_us=0, cpu_plc_statement_us=100,
                   cpu_servo_motor_us=20)
    _define_motors(rig, motors)
    rig.c.plcs.load(1, "\n".join(["P1=P1+1"] * statements))
    rig.ok("ENABLE PLC 1")
    return rig


@pytest.mark.parametrize("motors", [0, 8])
def test_a_command_sent_mid_cycle_is_answered_when_the_cycle_in_progress_ends(make_rig, motors):
    """A background cycle is one PLC 1-31 scan, then a host command (TUM p237). PLC 1 of 20
    statements at 100 µs is 2 ms of processor time, spread over 2 ms / (the share the servo
    updates of the motors leave); a command arriving 1 ms into a cycle is answered at its
    end (the RTI, every 256 servo cycles with I8=255, does not come in between), not one
    cycle's length after the command arrived."""
    rig = _plc1_card(make_rig, motors, 20)
    rig.run_for(0.05)
    first = rig.cmd("P1")
    start = first.t_done  # one cycle ends and the next begins with a scan
    length = 0.002 / (1.0 - rig.c.status()["cpu"]["servo"])
    assert rig.c.scheduler.next_rti_after(start) > start + 2 * length
    rig.run_for(0.001)
    second = rig.cmd("P1")
    assert rig.cyc(second.t_done) == rig.cyc(rig.c.scheduler.servo_at_or_after(start + length))
    assert int(second.reply) == int(first.reply) + 20  # exactly one more scan of PLC 1
    assert rig.c.status()["cpu"]["background_cycle_s"] == pytest.approx(second.t_done - start)


def test_a_second_queued_command_waits_a_whole_cycle_that_also_pays_for_it(make_rig):
    """Two commands sent together in a 2 ms background cycle (PLC 1): the first is answered
    at that cycle's end, the second at the end of the next cycle, which begins with it
    queued and so takes its 0.5 ms of command processing on top of the scan (TUM p237: one
    host command a background cycle). With PLC 1 disabled the card is idle again and its
    background cycle is the free-running housekeeping's, one servo cycle."""
    rig = _plc1_card(make_rig, 0, 20, host_us=500)
    rig.run_for(0.05)
    start = rig.cmd("P1").t_done
    while rig.c.scheduler.next_rti_after(start) < start + 0.01:
        start = rig.cmd("P1").t_done  # a cycle well before the next RTI
    first, second = rig.c.terminal("P1"), rig.c.terminal("P2")
    while not second.done:
        rig.c.env.step()
    at = rig.c.scheduler.servo_at_or_after
    assert rig.cyc(first.t_done) == rig.cyc(at(start + 0.002))
    assert rig.cyc(second.t_done) == rig.cyc(at(first.t_done + 0.0025))
    assert rig.c.status()["cpu"]["background_cycle_s"] == pytest.approx(
        second.t_done - first.t_done)
    rig.ok("DISABLE PLC 1")  # nothing left to run: free-running housekeeping, one a cycle
    rig.run_for(0.1)
    assert rig.c.status()["cpu"]["background_cycle_s"] == pytest.approx(rig.period)
    t_sent = rig.c.now  # answered once its 0.5 ms of processing is done
    assert rig.cyc(rig.cmd("P1").t_done) == rig.cyc(at(t_sent + 0.0005))


def test_a_stall_due_later_does_not_hold_back_a_command_answered_before_it(make_rig):
    """An injected stall starves the background only inside its window: a command sent
    before a stall that starts 0.1 s later is answered on the same servo cycle as on a card
    with no stall coming (the next one: the idle card answers at once)."""
    replies = []
    for stall in (False, True):
        rig = make_rig()
        rig.run_for(10.5 * rig.period)
        if stall:
            rig.c.background.stall(rig.c.now + 0.1, rig.c.now + 0.2)
        replies.append(rig.cyc(rig.cmd("I10").t_done))
    assert replies[1] == replies[0] == 11


@pytest.mark.parametrize("motors", [0, 8])
def test_a_plc0_longer_than_the_rti_reruns_the_moment_its_last_scan_ends(make_rig, motors):
    """A PLC 0 scan longer than the RTI period: the RTI that finds it running is latched and
    PLC 0 runs again as soon as the scan ends ``[INF]`` (one-deep latch), so the processor
    stays in foreground and scan n begins on the first servo cycle at or after n scans' work
    (2 ms each here) at the share of the processor the servo updates of the motors leave
    (TUM p236-237) — mostly between RTIs, not on them."""
    rig = make_rig(i40=100000, cpu_rti_base_us=0, cpu_plc_scan_us=0, cpu_plc_statement_us=10,
                   cpu_servo_motor_us=20)
    _define_motors(rig, motors)
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 199))  # 200 statements, 2 ms
    since = rig.c.log.last_seq
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.03)
    share = 1.0 - rig.c.status()["cpu"]["servo"]
    assert share == pytest.approx(1.0 - motors * 20e-6 / rig.period)
    starts = [e.t for e in rig.c.log.read(since, ["mvar"]).events if e.fields["name"] == "M1"]
    assert len(starts) >= 8
    at = rig.c.scheduler.servo_at_or_after
    assert [rig.cyc(t) for t in starts] == [
        rig.cyc(at(starts[0] + n * 2e-3 / share)) for n in range(len(starts))]
    rti_cycles = round(rig.c.scheduler.rti_period_s() / rig.period)
    assert any(rig.cyc(t) % rti_cycles for t in starts)


def test_a_plc0_scan_that_disables_plc0_still_holds_the_processor_for_its_length(make_rig):
    """The RTI's tasks have priority over the background (TUM p237): a 4 ms scan of PLC 0
    whose last statement is ``DISABLE PLC 0`` still takes 4 ms of processor time. The RTIs
    in those 4 ms find it running (overruns) and a host command sent meanwhile is answered
    only after it, within the two servo cycles the background cycle then needs."""
    rig = make_rig(cpu_rti_base_us=0, cpu_plc_scan_us=0, cpu_plc_statement_us=10)
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 398 + ["DISABLE PLC 0"]))
    since = rig.c.log.last_seq
    rig.ok("ENABLE PLC 0")
    while not rig.events("mvar", since=since):
        rig.c.env.step()
    ((k_scan, _, _),) = rig.events("mvar", since=since)
    t_scan = k_scan * rig.period
    rig.run_for(1.5 * rig.period)
    reply = rig.cmd("P10")
    assert reply.reply == "398"
    assert t_scan + 4e-3 < reply.t_done <= t_scan + 4e-3 + 2 * rig.period
    rti_cycles = round(rig.c.scheduler.rti_period_s() / rig.period)
    overruns = [k for k, _, _ in rig.events("rti_overrun", since=since)]
    assert overruns == [k for k in range(k_scan + 1, k_scan + 10) if k % rti_cycles == 0]
    assert len(rig.events("mvar", since=since)) == 1  # disabled: PLC 0 scanned once


def test_an_idle_card_reloads_its_watchdog_every_cycle_after_answering_a_command(rig):
    """With nothing to run, the background is free-running housekeeping that reloads the
    watchdog every servo cycle (TUM p237, TSRM p57): a second after answering a command the
    last reload is the current servo cycle and the whole I40 margin is left."""
    rig.ok("I10")
    rig.run_for(1.0)
    wd = rig.c.status()["watchdog"]
    assert rig.cyc(wd["reload_s"]) == rig.c.scheduler.clock.index(rig.c.now)
    assert wd["cycles_left"] == wd["limit_cycles"] == 4096
    cpu = rig.c.status()["cpu"]
    assert (cpu["servo"], cpu["rti"], cpu["background"]) == (0.0, 0.0, 1.0)


def test_plc0_enabled_between_rtis_first_scans_at_the_next_rti(make_rig):
    """PLC 0 runs in the RTI (TUM p376): enabled half-way through servo cycle 10 (as the
    REST resource does, no background cycle involved), it first scans at cycle 12, the next
    RTI (every I8+1 = 3 cycles), then once per RTI."""
    rig = make_rig(i5=3)
    rig.c.plcs.load(0, "M1=M1+1")
    rig.run_for(10.5 * rig.period)
    since = rig.c.log.last_seq
    rig.c.plcs.set_enabled((0,), True)
    rig.run_for(0.01)
    scans = [k for k, _, f in rig.events("mvar", since=since)]
    assert scans[:5] == [12, 15, 18, 21, 24]


def test_a_latched_plc0_reruns_on_a_servo_cycle_when_commands_arrive_between_cycles(make_rig):
    """Every task runs on the servo interrupt's time grid: a latched PLC 0 (scans longer
    than the RTI period) whose work ends between two servo cycles reruns on the next cycle,
    even when a host command arrives in that gap (as over REST, at any instant)."""
    rig = make_rig(i40=100000, cpu_rti_base_us=0, cpu_plc_scan_us=0, cpu_plc_statement_us=10)
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 199))  # 2 ms a scan
    since = rig.c.log.last_seq
    rig.ok("ENABLE PLC 0")
    for _ in range(120):  # a command every 0.3 servo cycles, off the cycle grid
        rig.run_for(0.3 * rig.period)
        rig.c.terminal("P10")
    rig.run_for(0.01)
    starts = [e.t for e in rig.c.log.read(since, ["mvar"]).events]
    assert len(starts) >= 8
    for t in starts:  # rig.cyc asserts each instant is a whole servo cycle
        rig.cyc(t)


def test_a_command_sent_in_a_stall_is_answered_on_the_first_cycle_after_it_ends(make_rig):
    """A stall (sim/faults.py) holds the background back for its length only: a command sent
    in the middle of a 50 ms stall, a second into the run, is answered on the first servo
    cycle after the stall ends (the background cycle's 40 µs of work fit in one), not at a
    later RTI (every 256 servo cycles with I8=255)."""
    rig = make_rig(i8=255, cpu_housekeeping_us=20, cpu_host_command_us=20)
    rig.run_for(1.0)
    t0 = rig.c.now
    rig.c.background.stall(t0, t0 + 0.05)
    rig.run_for(0.01)
    reply = rig.cmd("I10")
    k_end = rig.cyc(rig.c.scheduler.servo_at_or_after(t0 + 0.05))
    assert k_end <= rig.cyc(reply.t_done) <= k_end + 1


@pytest.mark.parametrize("sent", [0.0, 0.025])
@pytest.mark.parametrize("motors", [0, 8])
def test_a_stall_starting_inside_a_background_cycle_delays_its_end_by_its_length(make_rig,
                                                                              motors, sent):
    """A background cycle of 10 ms of work (PLC 1, 100 statements at 100 µs) at the share of
    the processor the servo updates of the motors leave, interrupted 3 ms after it began by a
    20 ms stall, ends 20 ms later than it would have: the stall adds exactly its length, and
    a command sent as the cycle begins or after the stall, while the cycle goes on, is
    answered then (no RTI comes in between: every 256 servo cycles with I8=255)."""
    rig = _plc1_card(make_rig, motors, 100)
    rig.run_for(1.0)
    length = 0.01 / (1.0 - rig.c.status()["cpu"]["servo"])
    first = rig.cmd("P1")
    while rig.c.scheduler.next_rti_after(first.t_done) < first.t_done + 0.02 + 2 * length:
        first = rig.cmd("P1")  # wait for a cycle well before the next RTI
    start = first.t_done  # one cycle ends and the next begins with a scan
    rig.c.background.stall(start + 0.003, start + 0.023)
    if sent:
        rig.run_for(sent)  # at 25 ms the stall is over, the cycle not yet
    second = rig.cmd("P1")
    end = rig.c.scheduler.servo_at_or_after(start + 0.02 + length)
    assert rig.cyc(second.t_done) == rig.cyc(end)
    assert int(second.reply) == int(first.reply) + 100


@pytest.mark.parametrize("delay", [0.0, 0.01])
def test_no_watchdog_reload_falls_inside_a_stall(make_rig, delay):
    """No background cycle completes in a stall, so nothing reloads the watchdog there
    (TSRM p57): read 20 ms after a 40 ms stall (starting now or 10 ms from now) on an idle
    card whose RTI comes only every 256 servo cycles (I8=255), the last reload is the first
    servo cycle after the stall, when the free-running housekeeping resumes, or later."""
    rig = make_rig(i8=255)
    rig.run_for(rig.c.scheduler.next_rti_after(1.0) + 0.5 * rig.period)  # just after an RTI
    t0 = rig.c.now + delay
    rig.c.background.stall(t0, t0 + 0.04)
    rig.run_for(delay + 0.06)
    assert rig.c.scheduler.next_rti_after(t0) > t0 + 0.06
    wd = rig.c.status()["watchdog"]
    k_end = rig.cyc(rig.c.scheduler.servo_at_or_after(t0 + 0.04))
    assert k_end <= rig.cyc(wd["reload_s"]) <= rig.c.scheduler.clock.index(rig.c.now)


def test_the_rti_load_is_the_share_of_the_last_full_second(make_rig):
    """The ``rti`` load figure is the RTI tasks' share of the processor over the last full
    second (``status()``). PLC 0 runs about 1 ms of its 1.33 ms RTI until P1 is set, then a
    few statements: the figure shows the old share until a whole second has passed under the
    new load (seconds counted from when the processor model woke), then only the new one;
    it is still that second's figure just after an RTI, when the current RTI's work is under
    way."""
    rig = make_rig(i40=100000, cpu_rti_base_us=0, cpu_plc_scan_us=0, cpu_plc_statement_us=10)
    rti_s = rig.c.scheduler.rti_period_s()
    rig.c.plcs.load(0, "\n".join(["M1=M1+1", "IF (P1=0)"] + ["P10=P10+1"] * 97 + ["ENDIF"]))
    rig.ok("ENABLE PLC 0")

    def share() -> float:
        return rig.c.status()["plcs"]["0"]["statements_last_scan"] * 10e-6 / rti_s

    rig.run_for(0.5)  # the first second awake is not over: the share so far
    heavy = share()
    assert rig.c.status()["cpu"]["rti"] == pytest.approx(heavy, rel=0.01)
    rig.run_for(2.0)
    assert heavy > 0.7
    assert rig.c.status()["cpu"]["rti"] == pytest.approx(heavy, rel=0.01)
    rig.c.set_variable("P1", 1)  # at 2.5 s: the second from 2 s to 3 s is mixed
    rig.run_for(0.4)
    light = share()
    assert light < 0.05
    assert rig.c.status()["cpu"]["rti"] == pytest.approx(heavy, rel=0.01)  # 1 s to 2 s
    rig.run_for(1.2)  # past 4 s: the second from 3 s to 4 s
    rig.run_for(rig.c.scheduler.next_rti_after(rig.c.now) - rig.c.now + 0.2 * rig.period)
    rig.c.terminal("P10")  # the processor accounts the time so far, 0.2 cycles after an RTI
    assert rig.c.status()["cpu"]["rti"] == pytest.approx(light, rel=0.01)
    cpu = rig.c.status()["cpu"]
    assert cpu["background"] == pytest.approx(1.0 - cpu["rti"])


@pytest.mark.parametrize("housekeeping_us", [20, 0])
def test_with_no_processor_left_plc0_enabled_over_rest_never_runs_and_the_card_trips(
        make_rig, housekeeping_us):
    """The servo updates take the whole processor (500 µs at 2 kHz): PLC 0, enabled as the
    REST resource does (no host command), never gets to run — its first RTI's work never
    ends, so every later RTI overruns — and no background cycle reloads the watchdog, which
    trips I40 servo cycles later, whatever the housekeeping costs."""
    rig = make_rig(servo_hz=2000, cpu_servo_base_us=500, i40=300,
                   cpu_housekeeping_us=housekeeping_us)
    rig.c.plcs.load(0, "M1=M1+1")
    rig.c.plcs.set_enabled((0,), True)
    rig.run_for(0.4)
    ((k_trip, _, _),) = rig.events("watchdog")
    assert k_trip == 300
    scans = [k for k, _, f in rig.events("mvar") if k < k_trip]
    assert scans == [3]  # the first RTI's scan, whose work never ends
    assert len(rig.events("rti_overrun")) > 50


def test_while_plc0_runs_the_watchdog_is_reloaded_by_the_housekeeping_pass_after_it(make_rig):
    """With PLC 0 running and no background PLC, the background is free-running housekeeping
    (TUM p237) and the watchdog is reloaded when the first pass after an RTI's tasks ends:
    0.33 ms of PLC 0 plus a 20 µs pass at the 64 % of the processor that the servo updates of
    8 motors (20 µs each) leave is 0.55 ms, so on the second servo cycle after the RTI."""
    rig = make_rig(cpu_rti_base_us=0, cpu_plc_scan_us=0, cpu_plc_statement_us=10,
                   cpu_servo_motor_us=20, cpu_housekeeping_us=20)
    rig.ok(" ".join(f"#{m}->{axis}" for m, axis in zip(range(1, 9), "XYZABCUV", strict=True)))
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 32))  # 0.33 ms
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.1)
    share = 1.0 - rig.c.status()["cpu"]["servo"]
    assert share == pytest.approx(1.0 - 8 * 20e-6 / rig.period)
    t_rti = rig.c.scheduler.next_rti_after(rig.c.now)
    rti_s = rig.c.scheduler.rti_period_s()
    rig.run_for(t_rti + rti_s + 0.5 * rig.period - rig.c.now)  # past the next RTI's wake-up
    reload = rig.c.scheduler.servo_at_or_after(t_rti + (0.33e-3 + 20e-6) / share)
    assert rig.cyc(rig.c.status()["watchdog"]["reload_s"]) == rig.cyc(reload)


@pytest.mark.parametrize("cycles", [1, 2, 3])
def test_a_background_cycle_lasts_at_least_background_cycles_servo_cycles(make_rig, cycles):
    """However little work it has, a background cycle ends on a servo cycle at least
    ``background_cycles`` servo cycles after it began (module docstring): with every cost
    zero, PLC 1 scans (one a cycle) exactly that many servo cycles apart."""
    rig = make_rig(i5=2, background_cycles=cycles, cpu_housekeeping_us=0, cpu_host_command_us=0,
                   cpu_plc_scan_us=0, cpu_plc_statement_us=0, cpu_rti_base_us=0)
    rig.c.plcs.load(1, "M1=M1+1")
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.02)
    scans = [k for k, _, _ in rig.events("mvar")]
    assert len(scans) > 10
    assert {b - a for a, b in zip(scans, scans[1:], strict=False)} == {cycles}


def test_a_tripped_card_runs_no_rti_tasks(make_rig):
    """Once the watchdog trips the CPU stops (TSRM p57): the load figures show no RTI share
    and the free-running background cycle of one servo cycle, though PLC 0 had taken the
    processor until then."""
    rig = make_rig(i40=300, cpu_plc_statement_us=10)
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 199))  # 2 ms a scan
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.3)
    assert rig.events("watchdog")
    cpu = rig.c.status()["cpu"]
    assert (cpu["rti"], cpu["background_cycle_s"]) == (0.0, pytest.approx(rig.period))


def test_the_rti_share_is_zero_at_the_instant_the_model_wakes(make_rig):
    """Read at the very instant a host command wakes the processor model (no time accounted
    yet), the RTI share is 0, not undefined."""
    rig = make_rig()
    rig.run_for(0.5)
    rig.c.terminal("I10")
    assert rig.c.status()["cpu"]["rti"] == 0.0


def test_in_the_first_second_awake_the_rti_share_is_that_of_the_time_so_far(make_rig):
    """PLC 0 enabled a second into the run: half a second later the RTI share is PLC 0's
    share of those 0.5 s (the first full second awake is not over)."""
    rig = make_rig(i40=100000, cpu_rti_base_us=0, cpu_plc_scan_us=0, cpu_plc_statement_us=10)
    rig.run_for(1.0)
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 99))  # 1 ms a scan
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.5)
    expected = 1e-3 / rig.c.scheduler.rti_period_s()
    assert rig.c.status()["cpu"]["rti"] == pytest.approx(expected, rel=0.01)
