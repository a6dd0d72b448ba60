"""Scenario hosts that write through the card's command line (``write_via: terminal``): the
write latency is the card's reply time, so PLC 0 load shows in it; ``direct`` has none."""

from __future__ import annotations

from pathlib import Path

import pytest
from motionsim.app.scenarios.errors import ScenarioError
from motionsim.app.scenarios.model import load_scenario, parse_scenario
from motionsim.app.scenarios.report import report
from motionsim.app.scenarios.runner import run

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "scenarios" / "write_via_terminal.yaml"


@pytest.fixture(scope="module")
def example():
    result = run(load_scenario(EXAMPLE))
    return result, report(result)


def test_terminal_writes_take_the_cards_reply_time_and_plc0_makes_it_longer(example):
    result, rep = example
    period = result.controllers["idle"].scheduler.period_s
    m = {c: rep["controllers"][c]["cs"][1] for c in ("direct", "idle", "busy")}
    # every card streams the whole program without starving
    assert all(x["lines_executed"] == 1000 and x["starvations"] == 0 for x in m.values())
    # direct: batches straight into the buffer, no reply to wait for
    assert m["direct"]["write_replies"] == 0 and m["direct"]["write_reply_mean_s"] is None
    assert m["direct"]["host_writes"] < 30
    # terminal: one command per program line (5 set-up lines + 1000 moves)
    assert m["idle"]["host_writes"] == m["idle"]["write_replies"] == 1005
    assert m["idle"]["write_reply_mean_s"] == pytest.approx(period, rel=1e-6)
    assert m["busy"]["write_reply_mean_s"] > 1.8 * m["idle"]["write_reply_mean_s"]
    assert m["busy"]["write_reply_max_s"] == pytest.approx(3 * period, rel=1e-6)  # one RTI
    assert rep["headline"]["write_reply_max_s"] == m["busy"]["write_reply_max_s"]


def test_terminal_writes_store_the_program_in_order_one_reply_at_a_time(example):
    result, _ = example
    log = result.controllers["busy"].log
    writes = log.events("host_write")
    loaded = log.events("line_loaded")
    assert [e.t for e in loaded] == [w.t for w in writes]
    assert [e.fields["n"] for e in loaded] == list(range(1, 1006))
    cmds = sorted((e.t - e.fields["reply_s"], e.t) for e in log.events("host_write", "host_pr"))
    assert all(b[0] >= a[1] for a, b in zip(cmds, cmds[1:], strict=False))


def test_same_seed_gives_a_byte_identical_log_with_terminal_writes(example):
    result, _ = example
    again = run(load_scenario(EXAMPLE))
    assert again.to_jsonl() == result.to_jsonl()
    other = run(parse_scenario(dict(load_scenario(EXAMPLE).raw, seed=8), base_dir=EXAMPLE.parent))
    assert other.to_jsonl() != result.to_jsonl()


def test_write_via_defaults_to_direct_and_rejects_other_paths():
    raw = load_scenario(EXAMPLE).raw
    host = {k: v for k, v in raw["hosts"][1].items() if k != "write_via"}
    scn = parse_scenario(dict(raw, hosts=[host]), base_dir=EXAMPLE.parent)
    assert scn.hosts[0].write_via == "direct"
    with pytest.raises(ScenarioError, match="write_via"):
        parse_scenario(dict(raw, hosts=[dict(host, write_via="dpram")]), base_dir=EXAMPLE.parent)
