"""Which line a Trio process reports (the ``process`` resource and events, API.md) while it
runs, when it is stopped, at its end; a program's last unterminated PRINT at its end.

Timing model of sim/trio/process.py: every statement costs ``statement_s`` (100 µs default).
"""

from __future__ import annotations

from tests.sim.trio.conftest import fields, run_to


def _proc(trio, p: int) -> dict:
    (out,) = [d for d in trio.processes() if d["process"] == p]
    return out


def test_a_process_reports_the_line_it_executes_and_the_line_it_was_stopped_on(trio):
    trio.store_program("P", "VR(1)=1\nWA(10)\nWA(10)\nVR(2)=2\n")
    trio.run_program("P", 2)
    assert _proc(trio, 2)["line"] == 1  # started, not yet stepped: its first line
    run_to(trio, 0.005)
    assert _proc(trio, 2)["line"] == 2 and _proc(trio, 2)["state"] == "running"
    run_to(trio, 0.015)
    assert _proc(trio, 2)["line"] == 3
    process = trio.basic[2]
    process.stop()
    process.stop()  # already stopped: nothing more
    stopped = fields(trio, "process", process=2, state="stopped")
    assert [f["line"] for _, f in stopped] == [3]
    assert _proc(trio, 2)["line"] == 3 and _proc(trio, 2)["state"] == "stopped"
    run_to(trio, 0.05)
    assert trio.get_variable("VR(2)") == 0.0 and _proc(trio, 2)["state"] == "stopped"
    assert len(fields(trio, "process", process=2, state="stopped")) == 1


def test_a_program_of_more_than_256_statements_runs_to_its_last_line(trio):
    trio.store_program("L", "".join(f"VR({i})={i + 1}\n" for i in range(300)))
    trio.run_program("L", 1)
    run_to(trio, 0.02)
    assert _proc(trio, 1)["state"] == "running" and 190 <= _proc(trio, 1)["line"] <= 210
    run_to(trio, 0.1)
    assert trio.get_variable("VR(299)") == 300.0
    ((_, end),) = fields(trio, "process", process=1, state="stopped")
    assert end["line"] == 300 and "error" not in end


def test_an_unterminated_print_is_sent_when_the_program_ends(trio):
    trio.store_program("T", 'PRINT "abc";\nVR(1)=1\n')
    trio.run_program("T", 1)
    run_to(trio, 0.01)
    assert [f["text"] for _, f in fields(trio, "print", process=1)] == ["abc"]
    assert [f["channel"] for _, f in fields(trio, "print", process=1)] == [0]
