"""A long stream through a small rotary buffer with a host that obeys BREQ (seed 000: the ring
"permits continuous execution of programs larger than PMAC's memory space"). The full 10^6-line
run is ``bench/bench_pmac_stream.py``; here 10^5 lines, with memory held flat."""

from __future__ import annotations

import gc
import sys

from motionsim.sim.pmac import PmacController


def test_a_600_word_buffer_streams_100k_lines_with_a_breq_host_and_flat_memory():
    c = PmacController("s", log_capacity=10_000)
    c.define_rotary(1, 600)
    c.load_lines(1, ["TA1 TS0 TM5"])
    c.run(1)
    rot = c.coord_system(1).rotary
    n = 100_000
    seen = {"max_words": 0, "max_ahead": 0}
    sizes = []

    def host():
        for i in range(n):
            if not rot.breq:
                yield c.wait_breq(1)
            c.load_lines(1, [f"X{i % 100}"])
            seen["max_words"] = max(seen["max_words"], rot.used_words)
            seen["max_ahead"] = max(seen["max_ahead"], rot.lines_ahead)
            if i in (20_000, n - 1):
                gc.collect()
                sizes.append(len(gc.get_objects()) + len(c.env._queue))

    c.env.process(host())
    c.env.run()
    assert c.log.events("move_end")[-1]["n"] == n + 1  # every line ran (line 1 = header)
    assert seen["max_ahead"] <= 10  # the host stopped at I17
    assert seen["max_words"] <= 10 + 3  # I17 ahead + executing + 2 calculated
    assert rot.used_words == 0 and rot.lines_ahead == 0
    assert len(c.log) == 10_000  # the log is a bounded ring
    # object count does not grow with the number of lines streamed
    assert sizes[1] - sizes[0] < 2_000, sizes
    assert c.coord(1)["program"]["state"] == "waiting"
    assert sys.getrefcount(rot) < 10
