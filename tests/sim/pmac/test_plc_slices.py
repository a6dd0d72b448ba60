"""A long PLC scan is worked through in slices (issue 33 item 4).

A background PLC scan runs to its end before the next PLC's (seed 003), but on the card the
servo and real-time interrupts cut it many times. The simulation does the same at a
coarser grain: at most ``cpu.SCAN_SLICE`` statements run at one simulated instant; the scan
goes on at the servo cycle where the processor time of the statements so far has been used
up. Nothing changes for a scan below the slice (the golden scenarios pin that); a scan of a
PLC at the size cap no longer runs as one long event that a realtime clock slice cannot cut.
"""

from __future__ import annotations

from collections import Counter

from motionsim.sim.pmac.tasks import cpu

from .conftest import Rig

N = 4999  # M-variable writes in one scan, then the PLC disables itself: one scan in all


def _run(rig: Rig) -> list[tuple[int, float]]:
    rig.ok("I5=2")
    rig.c.plcs.load(1, "\n".join(["M3=M3+1"] * N + ["DISABLE PLC 1"]))
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.5)
    return [(k, f["value"]) for k, _, f in rig.events("mvar") if f["name"] == "M3"]


def test_a_scan_longer_than_a_slice_runs_in_slices_at_later_servo_cycles():
    writes = _run(rig := Rig())
    assert [v for _, v in writes] == list(range(1, N + 1))  # every statement once, in order
    per_cycle = Counter(k for k, _ in writes)
    assert sorted(per_cycle.values(), reverse=True) == [cpu.SCAN_SLICE, cpu.SCAN_SLICE,
                                                        N - 2 * cpu.SCAN_SLICE]
    cycles = sorted(per_cycle)
    assert cycles[0] < cycles[1] < cycles[2]
    plc = rig.c.plcs.plc(1)
    assert (plc.scans, plc.last_statements, plc.mid_scan) == (1, N + 1, False)


def test_a_scan_within_the_slice_runs_at_one_instant(monkeypatch):
    monkeypatch.setattr(cpu, "SCAN_SLICE", N + 10)
    writes = _run(Rig())
    assert len({k for k, _ in writes}) == 1
    assert [v for _, v in writes] == list(range(1, N + 1))


def test_the_slices_are_charged_the_processor_time_of_the_whole_scan(monkeypatch):
    """Slicing moves where the statements run, not what the scan costs: the background cycle
    that holds it ends no earlier than the unsliced one (each slice resumes on a servo cycle,
    so it may end up to one servo cycle per slice later)."""
    sliced = Rig()
    _run(sliced)
    monkeypatch.setattr(cpu, "SCAN_SLICE", N + 10)
    whole = Rig()
    _run(whole)
    t_sliced = sliced.c.background.last_background_s
    t_whole = whole.c.background.last_background_s
    assert t_whole is not None and t_sliced is not None
    assert t_whole - 1e-9 <= t_sliced <= t_whole + 3 * whole.period + 1e-9


def test_a_host_command_is_answered_after_the_whole_sliced_scan():
    """Host commands run between background scans (TSRM p39): a DISABLE sent while a long
    scan is in its slices is answered once the scan has ended."""
    rig = Rig()
    rig.ok("I5=2")
    rig.c.plcs.load(1, "\n".join(["M3=M3+1"] * N))
    rig.ok("ENABLE PLC 1")
    plc = rig.c.plcs.plc(1)
    while not plc.mid_scan:
        rig.c.env.step()
    rig.ok("DISABLE PLC 1")
    assert len(rig.events("mvar")) == N and not plc.enabled


def test_plc0_disabling_a_plc_in_the_middle_of_its_sliced_scan_ends_it():
    """PLC 0 runs in the real-time interrupt, between the slices of a background scan: its
    DISABLE PLC 1 ends that scan where it is; nothing more of it runs."""
    rig = Rig()
    rig.ok("I5=3")
    rig.c.plcs.load(1, "\n".join(["M3=M3+1"] * N))
    rig.c.plcs.load(0, "\n".join(["IF (M3>0)", "DISABLE PLC 1", "ENDIF"]))
    rig.ok("ENABLE PLC 0")
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.5)
    plc = rig.c.plcs.plc(1)
    writes = [f["value"] for _, _, f in rig.events("mvar") if f["name"] == "M3"]
    assert writes == list(range(1, len(writes) + 1))
    assert 0 < len(writes) < N and len(writes) % cpu.SCAN_SLICE == 0
    assert (plc.enabled, plc.mid_scan, plc.pc, plc.scans) == (False, False, 0, 0)
