"""Background PLC scheduling edges (TUM p376; TSRM p39 I5; spec §9.5): I5 = 1 permits the
foreground PLC 0 only; the round robin covers PLC 1 ... 31 and starts at PLC 1; a PLC never
entered has 0 lines. Virtual time, on the event log."""

from __future__ import annotations


def _enter(rig, n: int, *lines: str) -> None:
    rig.ok(f"OPEN PLC {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def _names(rig) -> list[str]:
    return [f["name"] for _, _, f in rig.events("mvar")]


def test_tsrm_i5_1_runs_no_background_plc(rig):
    rig.ok("I5=1")
    _enter(rig, 1, "M1=M1+1")
    rig.ok("ENABLE PLC 1")
    rig.run_for(rig.period * 60)
    assert "M1" not in _names(rig)


def test_the_round_robin_starts_at_plc_1_and_reaches_plc_31(rig):
    rig.ok("I5=2")
    _enter(rig, 1, "M1=M1+1", "DISABLE PLC 1")
    _enter(rig, 2, "M2=M2+1", "DISABLE PLC 2")
    _enter(rig, 31, "M31=M31+1", "DISABLE PLC 31")
    rig.ok("ENABLE PLC 1,2,31")
    rig.run_for(rig.period * 200)
    assert _names(rig) == ["M1", "M2", "M31"]


def test_a_plc_never_entered_has_no_lines(rig):
    assert rig.c.plcs.describe(5)["lines"] == 0
