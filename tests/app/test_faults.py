"""The fault table's decisions: which commands a seeded fault hits is reproducible, and nth,
count and match pick them as documented (app/faults.py)."""

from __future__ import annotations

from motionsim.app.faults import FAULT_SPEC, FaultTable
from motionsim.sim.pmac import PmacController


def _hits(spec: dict, commands: list[str]) -> tuple[list[int], list[dict]]:
    ctl = PmacController("p")
    table = FaultTable(ctl)
    table.add(FAULT_SPEC.validate_python(spec))
    hits = [i for i, c in enumerate(commands) if table.forced_error(c) is not None]
    return hits, [e.to_dict("p") for e in ctl.log.events() if e.type == "fault"]


COMMANDS = [f"P{i % 3}={i}" for i in range(60)]
RANDOM = {"kind": "error_reply", "error": "ERR003", "probability": 0.5, "count": None}


def test_the_same_seed_hits_the_same_commands():
    a, ea = _hits({**RANDOM, "seed": 7}, COMMANDS)
    b, eb = _hits({**RANDOM, "seed": 7}, COMMANDS)
    assert a == b and ea == eb
    assert 10 < len(a) < 50
    c, _ = _hits({**RANDOM, "seed": 8}, COMMANDS)
    assert c != a


def test_nth_and_count_pick_the_matching_commands_in_order():
    hits, events = _hits({"kind": "error_reply", "error": "ERR001", "match": "^P1=",
                          "nth": 2, "count": 3}, COMMANDS)
    matching = [i for i, c in enumerate(COMMANDS) if c.startswith("P1=")]
    assert hits == matching[1:4]
    assert [e["command"] for e in events] == [COMMANDS[i] for i in hits]
    assert all(e["error"] == "ERR001" and e["fault"] == "f1" for e in events)


def test_match_is_a_case_insensitive_search():
    hits, _ = _hits({"kind": "error_reply", "error": "ERR003", "match": "p2=", "count": None},
                    COMMANDS)
    assert hits == [i for i, c in enumerate(COMMANDS) if c.startswith("P2=")]
