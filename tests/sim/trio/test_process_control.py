"""Processes: HALT, PROCESS, PROC_STATUS, RUN "prog", n / STOP "prog" from programs, the PROC(n)
modifier (PMOVE PROC(n) for every process, the command line's 0 included).

Sources: spec §10.6 / §10.7 — PMOVE with PROC (TRM p. 8-130), PROC_STATUS 0 = not running
(3P programs), RUN "prog", n and STOP "prog" (3P programs, TrioPC Run/Stop); HALT and the
PROCESS listing are ``[BK]`` (the pages were not reachable).
"""

from __future__ import annotations

from tests.sim.trio.conftest import fields, run_to


def test_pmove_proc_n_reads_each_process_buffer_including_the_command_line(trio):
    trio.store_program("MV", "MOVE(10) AXIS(3)\nWA(100)\n")
    trio.run_program("MV", 4)
    run_to(trio, 0.00005)
    trio.terminal("MOVE(10) AXIS(0)")
    run_to(trio, 0.0002)
    assert trio.terminal("? PMOVE PROC(0)").reply == "1.0000"
    assert trio.terminal("? PMOVE PROC(4)").reply == "1.0000"
    assert trio.terminal("? PMOVE PROC(2)").reply == "0.0000"
    run_to(trio, 0.0015)
    assert trio.terminal("? PMOVE PROC(0)").reply == "0.0000"
    assert trio.terminal("? PMOVE PROC(4)").reply == "0.0000"
    r = trio.terminal("? PMOVE PROC(9)")
    assert r.error.endswith("Process number out of range: 9")


def test_proc_status_zero_when_not_running(trio):
    trio.store_program("W", "WA(50)\n")
    trio.store_program("MAIN", 'RUN "W", 4\nWA(2)\nVR(1)=PROC_STATUS PROC(4)\n'
                               'WAIT UNTIL PROC_STATUS PROC(4)=0\nVR(2)=1\n')
    trio.run_program("MAIN", 1)
    run_to(trio, 0.01)
    assert trio.get_variable("VR(1)") == 1.0 and trio.get_variable("VR(2)") == 0.0
    run_to(trio, 0.1)
    assert trio.get_variable("VR(2)") == 1.0
    assert trio.terminal("? PROC_STATUS PROC(4)").reply == "0.0000"
    assert trio.terminal("? PROC_STATUS PROC(0)").reply == "1.0000"


def test_stop_prog_from_another_program(trio):
    trio.store_program("LOOP", "WHILE TRUE\n WA(1)\nWEND\n")
    trio.store_program("BOSS", 'RUN "LOOP", 3\nWA(10)\nSTOP "LOOP"\n')
    trio.run_program("BOSS", 1)
    run_to(trio, 0.1)
    states = {p["process"]: p["state"] for p in trio.processes()}
    assert states == {1: "stopped", 3: "stopped"}


def test_halt_stops_every_program_but_not_the_motion(trio):
    trio.store_program("A", "MOVE(100) AXIS(0)\nWHILE TRUE\n WA(1)\nWEND\n")
    trio.store_program("B", "WHILE TRUE\n WA(1)\nWEND\n")
    trio.run_program("A", 1)
    trio.run_program("B", 2)
    run_to(trio, 0.02)
    r = trio.terminal("HALT")
    assert r.error is None
    assert {p["state"] for p in trio.processes()} == {"stopped"}
    assert trio.axis(0)["mtype"] == 1  # the move goes on
    run_to(trio, 0.5)
    assert trio.axis(0)["dpos"] == 100.0


def test_halt_in_a_program_stops_it_too(trio):
    trio.store_program("B", "WHILE TRUE\n WA(1)\nWEND\n")
    trio.store_program("H", "WA(5)\nHALT\nVR(1)=1\n")
    trio.run_program("B", 2)
    trio.run_program("H", 1)
    run_to(trio, 0.1)
    assert {p["state"] for p in trio.processes()} == {"stopped"}
    assert trio.get_variable("VR(1)") == 0.0


def test_process_lists_the_running_programs(trio):
    assert trio.terminal("PROCESS").reply == "No processes running"
    trio.store_program("LOOP", "WHILE TRUE\n WA(1)\nWEND\n")
    trio.run_program("LOOP", 3)
    trio.run_program("LOOP", 5)
    run_to(trio, 0.01)
    lines = trio.terminal("PROCESS").reply.split("\r\n")
    assert [ln.split()[:4] for ln in lines] == [
        ["Process", "3:", "LOOP", "running"], ["Process", "5:", "LOOP", "running"]
    ]


def test_run_from_a_program_picks_the_given_process(trio):
    trio.store_program("CHILD", "VR(5)=PROCNUMBER\n")
    trio.store_program("PARENT", 'RUN "CHILD", 6\n')
    trio.run_program("PARENT", 1)
    run_to(trio, 0.01)
    assert trio.get_variable("VR(5)") == 6.0
    assert [f["process"] for _, f in fields(trio, "process", state="running")] == [1, 6]
