"""Faults injected inside the card from a scenario's ``faults:`` (``type: inject``): a stalled
background and a lost BREQ edge, and the simulated hosts' recovery paths they exercise."""

from __future__ import annotations

import pytest
from motionsim.app.scenarios.errors import ScenarioError
from motionsim.app.scenarios.model import loads_scenario
from motionsim.app.scenarios.runner import run

from tests.app.scenarios.fragments import PMAC_1MS_MOVES, breq_stream

PR_HOST = """\
name: stall
seed: 3
duration_s: 0.6
""" + PMAC_1MS_MOVES.replace("size_words: 400", "size_words: 6000") + """\
hosts:
  - name: h
    type: pr_polling
    poll_period_ms: 10
    reply_timeout_ms: 20
    lines_per_write: 50
    high_water: 300
    low_water: 100
    program:
      generate: {moves: 2000, move_ms: 1, axes: 2}
"""


def _events(result, *types):
    return [e for e in result.events("pmac") if e.type in types]


def test_a_stalled_background_leaves_pr_polls_unanswered_and_the_host_times_out_and_polls_again():
    scn = loads_scenario(PR_HOST + "faults:\n  - {type: inject, at_ms: 200, "
                                   "fault: {kind: stall, duration_ms: 100}}\n")
    result = run(scn)
    (fault,) = _events(result, "fault")
    assert fault["kind"] == "stall"
    assert fault.t == pytest.approx(0.2)
    assert (fault["start_s"], fault["end_s"]) == (pytest.approx(0.2), pytest.approx(0.3))
    timeouts = [e.t for e in _events(result, "host_timeout")]
    assert timeouts and all(0.2 < t <= 0.3 + 0.021 for t in timeouts)
    answered = [e.t for e in _events(result, "host_pr")]
    # no PR is answered inside the stall; the host's next polls after it are answered again
    assert not [t for t in answered if 0.2 + 1e-3 < t < 0.3]
    assert [t for t in answered if t > 0.3]
    # TUM p236: the background resumes after the stall, the servo/RTI work never stopped
    moves = [e.t for e in _events(result, "move_start")]
    assert [t for t in moves if 0.2 < t < 0.3]


def test_without_the_stall_every_poll_is_answered():
    result = run(loads_scenario(PR_HOST))
    assert not _events(result, "host_timeout", "fault")


LOST = breq_stream("name: lost\nseed: 2\nduration_s: 0.3\n", latency="0.5", moves=400,
                   host="h")


def test_a_lost_breq_edge_leaves_an_interrupt_only_host_waiting_while_breq_reads_high():
    """The level is right, the edge is gone: a host that only waits for the next interrupt
    never writes again (its recovery must read BREQ or PR: tests/api/test_faults.py)."""
    scn = loads_scenario(LOST + "faults:\n  - {type: inject, at_ms: 50, "
                                "fault: {kind: breq_lost, cs: 1, count: 1}}\n")
    result = run(scn)
    (fault,) = _events(result, "fault")
    assert fault["kind"] == "breq_lost" and fault["cs"] == 1 and fault.t >= 0.05
    rises = [e.t for e in _events(result, "breq") if e["level"]]
    assert fault.t not in rises  # that edge was never signalled
    writes = [e.t for e in _events(result, "host_write")]
    assert writes and max(writes) < fault.t + 1e-9
    assert result.controllers["pmac"].coord_systems[1].rotary.breq is True
    states = [e["state"] for e in _events(result, "program") if e.t > fault.t]
    assert "waiting" in states  # the buffer ran dry
    clean = run(loads_scenario(LOST))
    assert len([e for e in clean.events("pmac") if e.type == "line_loaded"]) > len(
        _events(result, "line_loaded"))


def test_the_lost_edge_is_the_nth_after_injection_and_reproducible():
    text = LOST + ("faults:\n  - {type: inject, at_ms: 50, "
                   "fault: {kind: breq_lost, nth: 3, count: 4, probability: 0.5, seed: 11}}\n")
    a, b = run(loads_scenario(text)), run(loads_scenario(text))
    ta = [e.t for e in _events(a, "fault")]
    assert ta == [e.t for e in _events(b, "fault")]
    assert 1 <= len(ta) <= 4
    assert a.to_jsonl() == b.to_jsonl()


@pytest.mark.parametrize("fault, field", [
    ("{kind: reply_drop}", "faults[0].fault.kind"),
    ("{kind: stall, duration_ms: -5}", "faults[0].fault.duration_ms"),
    ("{kind: breq_lost, cs: 17}", "faults[0].fault.cs"),
])
def test_an_impossible_injected_fault_is_refused_naming_its_field(fault, field):
    with pytest.raises(ScenarioError) as info:
        loads_scenario(LOST + f"faults:\n  - {{type: inject, fault: {fault}}}\n")
    assert info.value.field == field
    assert info.value.line is not None
