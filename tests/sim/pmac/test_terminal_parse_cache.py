"""The terminal's cache of parsed command lines is bounded: a host sending ever new lines
(every streamed move is a new text) never makes it grow past its size (bad input must not
exhaust the service's memory)."""

from __future__ import annotations

from motionsim.sim.pmac.host import terminal


def test_the_parse_cache_never_holds_more_than_its_size(rig):
    size = terminal._PARSE_CACHE_SIZE
    assert size == 512
    for n in range(size + 50):
        rig.ok(f"P{n % 8000}={n}")
        assert len(terminal._PARSE_CACHE) <= size
    assert rig.ok("P100") == "100"
