"""Control flow in fixed motion programs, in virtual time, asserted on the event log (spec
pmac.md §12.1; PSRM p313 ELSE, p357 WHILE; TSRM p416 CALL, p466 READ, p182 BLOCKSTART;
TUM p252 conditions, p330 RETURN, p341 double jump-back; PUM p165 nesting, p216 WAIT)."""

from __future__ import annotations

import pytest

SETUP = "TM100 TA10 TS0"


def load(rig, n: int, lines: list[str]) -> None:
    rig.ok(f"OPEN PROG {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def run(rig, n: int = 1, cs: int = 1) -> None:
    rig.ok(f"&{cs} B{n} R")
    rig.run_until_idle()


def starts(rig) -> list[int]:
    return [e["n"] for _, _, e in rig.events("move_start")]


def states(rig) -> list[str]:
    return [e["state"] for _, _, e in rig.events("program")]


def P(rig, n: int) -> float:
    return rig.c.vars.read("P", n)


def test_psrm_p313_block_if_else_endif_takes_one_branch(rig):
    load(rig, 1, [SETUP, "P1=2",
                  "IF (P1=1)", "X10", "ELSE", "X20", "IF (P1>1)", "Y5", "ENDIF", "ENDIF"])
    run(rig)
    assert starts(rig) == [6, 8]  # the ELSE branch, and the nested IF inside it
    assert rig.c.positions(1) == pytest.approx({"X": 20.0, "Y": 5.0})
    assert states(rig) == ["running", "stopped"]


def test_psrm_p313_one_line_if_and_one_line_else(rig):
    """``IF (c) {statements}`` on one line, ``ELSE {statements}`` on the next: no ENDIF."""
    load(rig, 1, [SETUP, "P1=0", "IF (P1 !< 5) X10", "ELSE X-10", "IF (P1=0) Y3 P2=1",
                  "ELSE Y-3 P2=2", "X1"])
    run(rig)
    assert starts(rig) == [4, 5, 7]
    assert P(rig, 2) == 1
    assert rig.c.positions(1) == pytest.approx({"X": 1.0, "Y": 3.0})


def test_psrm_p357_while_loop_repeats_its_move_and_blends(rig):
    load(rig, 1, [SETUP, "P1=0", "WHILE (P1<3)", "X(P1*10+10)", "P1=P1+1", "ENDWHILE",
                  "Y1"])
    run(rig)
    assert starts(rig) == [4, 4, 4, 7]
    ends = rig.by_n("move_end")
    # one ENDWHILE between moves: the loop's moves blend (each ends as the next starts)
    moves = rig.events("move_start", "move_end")
    pairs = [(k, t) for k, t, _ in moves]
    for (k1, t1), (k2, t2) in zip(pairs[1:-1:2], pairs[2::2], strict=False):
        assert t1 == "move_end" and t2 == "move_start" and k1 == k2
    assert ends[7] > ends[4]
    assert rig.c.positions(1)["X"] == pytest.approx(30.0)


def test_psrm_p357_a_loop_with_no_move_runs_twice_per_rti(rig):
    """The double-jump-back rule throttles an empty loop: two passes per RTI, then the
    calculation waits for the next RTI; the move after the loop starts 5 RTIs after the
    first planning RTI for ten increments."""
    load(rig, 1, ["TM100 TA10 TS0", "P1=0", "WHILE (P1<10)", "P1=P1+1", "ENDWHILE", "X10"])
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    (run_at, _, _), = [e for e in rig.events("program") if e[2]["state"] == "running"]
    first_rti = -(-(run_at + 1) // 3) * 3
    (start_at, _, e), = rig.events("move_start")
    assert e["n"] == 6
    assert start_at == first_rti + 5 * 3
    assert P(rig, 1) == 10


def test_tum_p341_two_endwhiles_between_moves_stop_the_last_move(rig):
    """Nested loops with the move in the inner loop: leaving the inner loop and jumping back
    in the outer one meets two backward jumps, so the last calculated move comes to a stop
    (its end is not the next move's start) — within the inner loop moves blend."""
    load(rig, 1, [SETUP, "P1=0", "WHILE (P1<2)", "P2=0", "WHILE (P2<2)",
                  "X(P1*100+P2*10+10)", "P2=P2+1", "ENDWHILE", "P1=P1+1", "ENDWHILE"])
    run(rig)
    moves = [(k, t) for k, t, _ in rig.events("move_start", "move_end")]
    assert [t for _, t in moves].count("move_start") == 4
    end_of_2nd = moves[3][0]  # move_end of the 2nd move (the inner loop's last)
    assert moves[3][1] == "move_end"
    start_of_3rd = moves[4][0]
    assert start_of_3rd > end_of_2nd  # stopped, then calculated again
    assert moves[1][1] == "move_end" and moves[1][0] == moves[2][0]  # 1st blends into 2nd


def test_tsrm_p416_gosub_and_call_with_labels_return_to_the_next_line(rig):
    load(rig, 20, ["N1000 X(P7)", "RETURN", "O2000 Y(P7)", "RET"])
    load(rig, 1, [SETUP, "P7=4", "GOSUB 10", "CALL 20.01", "P7=6 CALL20.02", "Z1",
                  "RETURN", "N10 X2", "RETURN"])
    run(rig)
    assert rig.c.positions(1) == pytest.approx({"X": 4.0, "Y": 6.0, "Z": 1.0})
    progs = [(e["prog"], e["n"]) for _, _, e in rig.events("line_calculated")]
    assert progs == [(1, 1), (1, 2), (1, 8), (20, 1), (1, 5), (20, 3), (1, 6)]


def test_tsrm_p466_read_puts_the_calling_lines_values_in_q101_to_q126(rig):
    load(rig, 30, ["READ(A,B,D)", "X(Q101) Y(Q102) Z(Q104)", "RET"])
    load(rig, 1, [SETUP, "CALL30 A5 B(2*3) D-1 E9", "CALL30 B1 A2"])
    rig.ok("&1 B1")
    rig.ok("&1 Q100=0")
    run(rig)
    assert rig.c.vars.read("Q", 104, 1) == -1  # D of the first call
    assert rig.c.positions(1) == pytest.approx({"X": 2.0, "Y": 1.0, "Z": -1.0})
    # the second call: B is read, A after it too (both in the list); E was never read
    assert rig.c.vars.read("Q", 102, 1) == 1 and rig.c.vars.read("Q", 101, 1) == 2
    assert rig.c.vars.read("Q", 100, 1) == 0b11
    assert rig.c.vars.read("Q", 105, 1) == 0


def test_tsrm_p466_read_stops_at_the_first_letter_not_in_its_list(rig):
    load(rig, 30, ["READ(A,B)", "RET"])
    load(rig, 1, [SETUP, "Q101=0 Q102=0", "GOSUB30 A5 C1 B7", "X1", "RET", "N30 READ(A,B)",
                  "RET"])
    run(rig)
    assert rig.c.vars.read("Q", 101, 1) == 5
    assert rig.c.vars.read("Q", 102, 1) == 0  # B comes after C, which READ does not list
    assert rig.c.vars.read("Q", 100, 1) == 1


def test_pum_p165_goto_with_a_variable_destination_is_a_case_statement(rig):
    load(rig, 1, [SETUP, "P3=2", "GOTO(P3*10)", "N10 X1", "RETURN", "N20 X2", "RETURN"])
    run(rig)
    assert starts(rig) == [6]
    assert rig.c.positions(1)["X"] == pytest.approx(2.0)


def test_tum_p330_return_in_the_main_program_ends_it(rig):
    load(rig, 1, [SETUP, "X1", "RETURN", "X2"])
    run(rig)
    assert starts(rig) == [2]
    assert states(rig) == ["running", "stopped"]


def test_stop_halts_and_r_resumes_at_the_next_line(rig):
    load(rig, 1, [SETUP, "X1", "STOP", "X2"])
    run(rig)
    assert starts(rig) == [2] and states(rig) == ["running", "stopped"]
    # past the STOP: X2, line 4, at word offset 5 (TM100 TA10 TS0: 3 words, X1, STOP)
    assert rig.ok("&1PC") == "P1:5"
    rig.ok("&1 R")  # (a B1 would point it at the top again)
    rig.run_until_idle()
    assert starts(rig) == [2, 4]
    assert rig.c.positions(1)["X"] == pytest.approx(2.0)


def test_pum_p216_while_wait_suspends_calculation_until_the_condition_changes(rig):
    load(rig, 1, [SETUP, "P10=0", "WHILE (P10=0) WAIT", "X3"])
    rig.ok("&1 B1 R")
    rig.run_for(0.5)
    assert starts(rig) == [] and rig.c.coord(1)["program"]["state"] == "running"
    rig.ok("P10=1")
    set_at = rig.cyc(rig.c.env.now)
    rig.run_until_idle()
    (start_at, _, e), = rig.events("move_start")
    assert e["n"] == 4
    assert set_at <= start_at <= set_at + 3 + 3  # calculated at the next RTI (+ the reply)


def test_tsrm_p182_a_step_runs_through_a_blockstart_blockstop_block(rig):
    load(rig, 1, [SETUP, "X1", "BLOCKSTART", "X2", "X3", "BLOCKSTOP", "X4"])
    rig.ok("&1 B1 S")
    rig.run_until_idle()
    assert starts(rig) == [2]
    rig.ok("&1 S")
    rig.run_until_idle()
    assert starts(rig) == [2, 4, 5]  # the whole block in one step
    rig.ok("&1 S")
    rig.run_until_idle()
    assert starts(rig) == [2, 4, 5, 7]


@pytest.mark.parametrize(("cond", "expected"), [
    ("P1=2", 1), ("P1!=2", 0), ("P1>1", 1), ("P1!>1", 0), ("P1<3", 1), ("P1!<3", 0),
    ("P1~2.5", 1), ("P1!~2.5", 0), ("P1~4", 0), ("P1=2 AND P2=5", 1), ("P1=1 AND P2=5", 0),
    ("P1=1 OR P2=5", 1), ("P1=1 OR P2=4 AND P1=2", 0), ("P1=2 OR P2=4 AND P1=9", 1),
    ("SIN(P2-P2)!>P1/1000", 1),
])
def test_tum_p252_every_comparator_and_and_binding_tighter_than_or(rig, cond, expected):
    load(rig, 1, ["P1=2 P2=5 P3=0", f"IF ({cond}) P3=1", "ELSE P3=0"])
    run(rig)
    assert P(rig, 3) == expected


# -- bad input: structural errors at entry, run-time errors ---------------------------------

def test_err009_endif_without_if_is_refused_with_its_column_and_nothing_is_stored(rig):
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("X1")
    reply = rig.cmd("P5=1 ENDIF")
    assert reply.error == "ERR009"
    assert "column 6" in reply.detail[1]
    assert rig.cmd("ENDWHILE").error == "ERR009"
    assert rig.cmd("ELSE").error == "ERR009"
    rig.ok("CLOSE")
    assert rig.ok("LIST PROG 1") == "X1\rRET"  # nothing of the refused lines


def test_err009_a_block_left_open_at_close_and_err016_when_run(rig):
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("WHILE (P1<1)")
    rig.ok("X1")
    assert rig.cmd("CLOSE").error == "ERR009"
    assert rig.c.programs.editing() is None  # entry has ended all the same
    assert rig.cmd("&1 B1 R").error == "ERR016"
    assert states(rig) == []


def test_err009_a_refused_line_leaves_the_open_structure_as_it_was(rig):
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("IF (P1=0)")
    assert rig.cmd("ENDWHILE").error == "ERR009"
    rig.ok("X1")
    rig.ok("ENDIF")
    rig.ok("CLOSE")
    run(rig)
    assert starts(rig) == [2]


def test_pum_p165_gosub_nesting_beyond_15_is_a_run_time_error(rig):
    load(rig, 1, [SETUP, "X1", "N5 GOSUB5"])
    run(rig)
    (_, _, err), = rig.events("program_error")
    assert "nested" in err["reason"]
    assert rig.c.coord(1)["program"]["state"] == "aborted"
    w2 = int(rig.ok("&1??")[6:12], 16)
    assert w2 >> 22 & 1  # run-time error (TSRM p286)
    assert starts(rig) == []  # found in the pass that calculated X1: nothing moved


def test_a_jump_to_a_missing_label_is_a_run_time_error(rig):
    load(rig, 1, [SETUP, "GOTO 77", "X1"])
    run(rig)
    (_, _, err), = rig.events("program_error")
    assert err["reason"] == "GOTO: no label N77" and err["n"] == 2
    assert starts(rig) == []
    assert int(rig.ok("&1??")[6:12], 16) >> 22 & 1


def test_a_call_of_a_missing_prog_is_a_run_time_error(rig):
    load(rig, 1, [SETUP, "CALL 99"])
    run(rig)
    (_, _, err), = rig.events("program_error")
    assert "PROG 99" in err["reason"]


def test_control_flow_a_rotary_buffer_does_not_take_is_not_simulated_and_not_stored(rig):
    """The one-line IF is simulated in a rotary buffer since issue 37 (PUM p162: the only
    conditional a rotary buffer takes; tests/sim/pmac/test_rotary_gcode.py), which this test
    used as its example; GOSUB stays not simulated there."""
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    reply = rig.cmd("GOSUB10 X1")
    assert reply.error == "ERR003" and reply.detail[0] == "not_simulated"
    rig.ok("CLOSE")
    assert rig.c.rotary(1)["lines_ahead"] == 0


# -- listing and program counter ----------------------------------------------------------

def test_spec_12_9_list_prog_prints_control_flow_in_the_cards_form(rig):
    load(rig, 1, ["if (P1 = 0) ; comment", "  X10", "Else", "  Gosub 101 A2", "End If",
                  "While (M11 = 0) Wait", "P2=1", "O101 READ(A)",
                  "Return"])
    assert rig.ok("LIST PROG 1").split("\r") == [
        "IF(P1=0)", "X10", "ELSE", "GOSUB101A2", "ENDI", "WHILE(M11=0)WAIT", "P2=1",
        "N101READ(A)", "RET", "RET"]


def test_pc_follows_a_jump_into_a_called_program(rig):
    load(rig, 20, ["X1", "STOP", "X2", "RET"])
    load(rig, 1, [SETUP, "CALL20", "X9"])
    run(rig)
    assert rig.ok("&1PC") == "P20:2"  # X2 of PROG 20, after X1 and STOP (a word each)
