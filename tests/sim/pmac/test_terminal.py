"""The host command line: on-line versus buffered, replies, ERR codes (seed 000, TUM p46,
TSRM p295, p328, spec §2, §3)."""

from __future__ import annotations

import pytest


def test_i100_is_a_query_when_buffers_are_closed(rig):
    """Seed 000: "an I100 command is a request for a value of I-variable 100 when buffers are
    closed"."""
    rig.ok("I100=7")
    assert rig.ok("I100") == "7"
    assert rig.events("line_loaded") == []


def test_i100_is_a_full_circle_move_when_a_buffer_is_open(rig):
    """Seed 000: with a buffer open I100 is a full-circle move (vector X component 100)."""
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    assert rig.ok("I100") == ""
    assert [(f["text"], f["words"]) for _, _, f in rig.events("line_loaded")] == [("I100", 1)]


def test_full_circle_time_from_arc_length(make_rig):
    """CIRCLE1 with Isx13 > 0: time = arc length / F (2π·100 units at F=1000/s ≈ 628 ms)."""
    rig = make_rig(i5113=10)
    rig.rotary_setup()
    rig.c.load_lines(1, ["CIRCLE1 TA10 TS0 F1000 I100"])
    rig.ok("R")
    rig.run_until_idle()
    (k0, _, _), = rig.events("move_start")
    (k1, _, _), = rig.events("move_end")
    import math

    assert k1 - k0 == math.ceil((2 * math.pi * 0.1 + 0.01) / rig.period - 1e-6)


def test_b0_points_at_the_rotary_program_when_closed_and_is_a_b_axis_move_when_open(rig):
    """TSRM p295: with a buffer open, B0 is stored as a B-axis move."""
    rig.ok("&1 DEFINE ROT 100")
    rig.ok("B0")
    assert rig.c.coord_system(1).program == 0
    rig.ok("OPEN ROT")
    rig.ok("B0")
    assert [f["text"] for _, _, f in rig.events("line_loaded")] == ["B0"]


def test_x1000_on_line_is_err005(rig):
    """TUM p46: program commands with no buffer open answer ERR005."""
    assert rig.cmd("X1000").error == "ERR005"
    assert rig.cmd("LINEAR").error == "ERR005"
    assert rig.cmd("M1==1").error == "ERR005"


def test_assignments_act_at_once_when_closed_and_are_stored_when_open(rig):
    """TUM p249: an assignment is added to the open buffer, else executed immediately."""
    rig.ok("P1=2*3+1")
    assert rig.c.get_variable("P1") == 7
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.ok("P1=1")
    assert rig.c.get_variable("P1") == 7
    assert [f["text"] for _, _, f in rig.events("line_loaded")] == ["P1=1"]


def test_on_line_m_write_is_an_mvar_event(rig):
    k = rig.cyc(rig.cmd("M7=1").t_done)
    assert rig.events("mvar") == [(k, "mvar", {"name": "M7", "value": 1.0, "sync": False})]


def test_several_commands_on_one_line_answer_one_line_each(rig):
    """TSRM p402: several queries on one line answer one line each, in order."""
    assert rig.ok("I16 I17 I8") == "5\r10\r2"
    assert rig.ok("i16..17") == "5\r10"
    assert rig.ok("I16,2,1") == "5\r10"


def test_i_variable_default_restore(rig):
    """TUM p243: I{n}=* restores the manufacturer's default."""
    rig.ok("I16=3 I17=4")
    rig.ok("I16=*")
    assert rig.ok("I16 I17") == "5\r4"
    rig.ok("I16..17=*")
    assert rig.ok("I16 I17") == "5\r10"


def test_abbreviations_and_run_together_commands(rig):
    rig.ok("&1DEF ROT 50")
    rig.ok("&1B0R")
    assert rig.c.coord(1)["program"]["state"] == "running"


def test_only_one_port_may_hold_the_buffers_open(rig):
    """TUM p48: lines are accepted only from the port that opened; ERR007 for another."""
    rig.rotary_setup()
    other = rig.c.open_port("tcp")
    other.state  # noqa: B018
    rig.ok("OPEN ROT")
    assert rig.cmd("OPEN ROT", other).error == "ERR007"
    assert rig.cmd("X10", other).error == "ERR005"
    rig.ok("X10")
    rig.c.close_port(rig.c.rest_port)
    rig.ok("OPEN ROT", other)


def test_r_without_b0_is_err015(rig):
    """Spec §2.2: ERR015, not pointing to a valid program buffer."""
    rig.ok("&1 DEFINE ROT 100")
    assert rig.cmd("R").error == "ERR015"
    rig.ok("&2 B0")
    assert rig.cmd("&2 R").error == "ERR015"  # CS 2 has no rotary buffer


def test_error_discards_the_rest_of_the_line_after_the_data_already_produced(rig):
    r = rig.cmd("I16 X10 I17")
    assert (r.reply, r.error) == ("5", "ERR005")


def test_malformed_line_is_err003_and_changes_nothing(rig):
    r = rig.cmd("P1=5 P2=(3")
    assert r.error == "ERR003"
    assert rig.c.get_variable("P1") == 0


def test_addressing_is_per_port_and_reported(rig):
    other = rig.c.open_port("tcp")
    rig.ok("&3 #4")
    assert rig.ok("& #") == "3\r4"
    assert rig.ok("& #", other) == "1\r1"


def test_pr_reports_lines_ahead_of_calculation(rig):
    """TUM p338: PR, program remaining."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5"])
    assert rig.ok("PR") == "5"
    rig.ok("R")
    rig.run_for(0.01)
    assert rig.ok("PR") == "2"


def test_identification_replies(rig):
    """Spec §9.8: ver / cid; ?? is 18 hex characters, ? and ??? 12."""
    assert rig.ok("ver") == "1.947  "
    assert rig.ok("cid") == "603382"
    assert len(rig.ok("??")) == 18
    assert len(rig.ok("#1?")) == 12
    assert rig.ok("???") == "000000000000"


def test_axis_definition(rig):
    """PSRM p179: #1->X assigns, #1-> reports; a motor in another CS is ERR003."""
    rig.ok("&1 #1->1000X")
    assert rig.ok("#1->") == "1000X"
    assert rig.cmd("&2 #1->Y").error == "ERR003"


def test_reply_comes_in_the_next_background_cycle(rig):
    """The host port is served in the background cycle: one servo cycle after the command."""
    rig.run_for(0.0101)
    t0 = rig.c.now
    r = rig.cmd("I16")
    assert rig.cyc(r.t_done) == int(t0 / rig.period) + 1


@pytest.mark.parametrize("text", ["", "   ", "; just a comment"])
def test_empty_line_answers_nothing(rig, text):
    assert (rig.cmd(text).reply, rig.cmd(text).error) == ("", None)


def test_an_epics_style_poll_line_answers_one_line_per_item(rig):
    """Spec §5.3: the EPICS driver polls ``#1P #1F i124 #1? &1?? ??? &1%`` — one line each."""
    reply = rig.ok("#1P #1F i124 #1? &1?? ??? &1%")
    lines = reply.split("\r")
    assert len(lines) == 7
    # I124 is an address-type variable: reported in hex with the factory I9 = 2 (TUM p46).
    assert lines[0] == "0" and lines[2] == "$40001" and lines[6] == "100"
    rig.ok("&1%50")
    rig.run_for(1.0)  # the time base slews at Isx94 (≈ 1 s for 100 %)
    assert rig.ok("%") == "50"


def test_q_variables_are_per_coordinate_system(rig):
    """TSRM p23: Q-variables have one bank per coordinate system."""
    rig.ok("&2 Q1=5")
    assert rig.ok("&1 Q1") == "0"
    assert rig.ok("&2 Q1") == "5"
    assert rig.c.get_variable("&2Q1") == 5


def test_send_and_cmd_are_stored_and_ignored(rig):
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.ok('SEND"hello" N10 CMD"#1J+"')
    assert [(f["text"], f["words"]) for _, _, f in rig.events("line_loaded")] == [
        ('SEND"hello" N10 CMD"#1J+"', 3)
    ]
    rig.ok("CLOSE R")
    rig.run_for(0.05)
    assert rig.events("move_start") == []


@pytest.mark.parametrize("entry", ["closed", "OPEN ROT", "OPEN PLC 1"])
def test_percent_queries_and_sets_the_addressed_cs_override(rig, entry):
    """TSRM ``%`` (spec §5.3, §4.3): ``%`` answers the addressed CS's feedrate override, ``%n``
    sets it; ``&n`` in front addresses the CS first. The EPICS driver polls ``&1%`` — also
    while it holds a buffer open for entry, where ``%`` is not program text and acts on-line."""
    rig.ok("&1 DEFINE ROT 100")
    if entry != "closed":
        rig.ok(entry)
    assert rig.ok("%") == "100"
    assert rig.ok("&1%") == "100"
    assert rig.ok("&2%") == "100"
    rig.ok("%50")  # the port addresses CS 2 now
    rig.run_for(1.0)  # the time base slews at Isx94 (≈ 1 s for 100 %)
    assert rig.ok("&1%") == "100"
    assert rig.ok("&2%") == "50"
    rig.ok("&1%50")
    rig.run_for(1.0)
    assert rig.ok("&1%") == "50"
    assert rig.ok("&1% &2%") == "50\r50"
    assert rig.c.coord_system(1).feed_override == 50
    assert rig.events("line_loaded") == []  # nothing was stored in a buffer


def test_plc_entry_still_answers_on_line_queries_and_stores_plc_text(rig):
    """With a PLC open, PLC text is stored; a line of on-line-only commands (``SIZE``,
    ``PR``, ``I16``) is answered on-line ``[INF]``; anything else is ERR003 as before."""
    rig.ok("&1 DEFINE ROT 100")
    rig.ok("OPEN PLC 1 CLEAR")
    assert int(rig.ok("SIZE")) < 0
    assert rig.ok("PR") == "0"
    assert rig.ok("I16") == "5"
    rig.ok("P1=P1+1")
    assert rig.cmd("X10").error == "ERR003"
    rig.ok("CLOSE")
    assert rig.c.plcs.plc(1).program.lines == ("P1=P1+1",)


def test_i9_bit0_reports_variables_as_whole_statements(rig):
    """PSRM I9 / TSRM p42 (spec §9.8): with I9 bit 0 = 0 a query answers the value only; with
    bit 0 = 1 the full statement, one line per variable."""
    assert rig.ok("I16") == "5"
    rig.ok("I9=3 P7=1.5")
    assert rig.ok("I16") == "I16=5"
    assert rig.ok("I16..17") == "I16=5\rI17=10"
    assert rig.ok("P7") == "P7=1.5"
    rig.ok("I9=2")
    assert rig.ok("P7") == "1.5"


def test_tsrm_p259_reports_before_an_unfinished_expression_are_answered(rig):
    """Commands run left to right (TSRM p259, spec §2.3 ``[INF]``): ``I10 P1=(3 P2`` fails at
    ``P2`` (the parenthesis is still open), and the text before it, ``I10 P1=(3``, fails too —
    at ``P1=(3``; the report before both, ``I10``, is answered, then ERR003, and ``P1`` is
    not written (a malformed line changes nothing)."""
    rig.ok("P1=7")
    for line, reports in [("I10 P1=(3 P2", "3713707"), ("I10 I9 P1=SIN( P2=1", "3713707\r2"),
                          ("I10 P1=3+ P2=1", "3713707")]:
        reply = rig.cmd(line)
        assert (reply.reply, reply.error) == (reports, "ERR003"), line
        assert reply.detail[0] == "parse_error"
    assert rig.ok("P1 P2") == "7\r0"


def test_a_refused_plc_line_says_why_for_people(rig):
    """With a PLC open a line the PLC cannot store answers ERR003 (TSRM I6 table) and the
    REST terminal says why: the parse error and its column, or the valid Turbo PMAC command
    motionsim does not simulate (``DISPLAY``, the LCD display's PLC command, spec §12)."""
    rig.ok("OPEN PLC 1 CLEAR")
    reply = rig.cmd("IF((P1>-20) AND (P1<20))")
    assert reply.error == "ERR003"
    assert reply.detail[0] == "parse_error" and reply.detail[1].endswith("(column 4)")
    reply = rig.cmd('DISPLAY 0 "X"')
    assert reply.error == "ERR003"
    assert reply.detail[0] == "not_simulated" and reply.detail[1].startswith("DISPLAY ")
    rig.ok("P1=1")
    rig.ok("CLOSE")
    assert rig.c.plcs.plc(1).program.lines == ("P1=1",)


def test_tsrm_p23_every_variable_number_0_to_8191_is_queried_and_8192_is_err003(rig):
    """TSRM p23 (spec §3): I, P, Q and M variables are numbered 0..8191; a query beyond is
    ERR003."""
    rig.ok("P0=4 P8191=2")
    assert rig.ok("P0 P8191") == "4\r2"
    assert rig.ok("P0..1") == "4\r0"
    assert rig.cmd("P8192").error == "ERR003"
    assert rig.cmd("P8193").error == "ERR003"


def test_i9_bit0_reports_an_indirect_query_as_the_whole_statement(rig):
    """PSRM I9 / TSRM p328 (spec §2.3): bit 0 = 1 reports the variable as a statement, for
    ``P(expression)`` (TUM p243) as for ``P2``; I9 alone decides it, whatever I8 holds."""
    rig.ok("P1=1 P2=5")
    assert rig.ok("P(P1+1)") == "5"
    rig.ok("I9=1")
    assert rig.ok("P(P1+1)") == "P2=5"
    rig.ok("I8=0 I9=3")
    assert rig.ok("P(P1+1)") == "P2=5"


def _stop_run(rig, command, plc_open):
    rig.ok("&1 #1->1000X")
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("LINEAR INC TA10 TS0 TM500 X1 X1 X1")
    rig.ok("CLOSE")
    rig.ok("&1 B1 R")
    rig.run_for(0.2)
    rig.ok("OPEN PLC 1 CLEAR" if plc_open else "I10")  # one background cycle either way
    reply = rig.cmd(command)
    rig.run_for(2.0)
    if plc_open:
        rig.ok("CLOSE")
        assert rig.c.plcs.plc(1).program is None  # nothing stored in the PLC
    states = [f["state"] for _, _, f in rig.events("program")]
    return reply.error, rig.c.positions(1), states


@pytest.mark.parametrize("command", ["&1/", "&1\\", "&1H", "&1Q", "&1A"])
def test_the_stop_commands_act_on_line_while_the_port_holds_a_plc_open(make_rig, command):
    """``/`` (stop at the end of the move, TUM p217), ``\\`` (quick stop; outside lookahead
    it acts as ``H``, TSRM p177), ``H``, ``Q``, ``A`` have no PLC-program form: with a PLC
    open for entry they act on-line ``[INF]`` (seed 000), as with no buffer open, so a host
    can stop a CS while it enters a PLC."""
    error, at, states = _stop_run(make_rig(), command, plc_open=True)
    assert error is None
    assert (at, states) == _stop_run(make_rig(), command, plc_open=False)[1:]
    assert at["X"] < 3.0 and states[-1] != "running"  # the program did not run to its end


def test_tsrm_p259_addressing_and_definition_reports_before_a_failing_command_still_act(rig):
    """``#n`` and ``M{n}->`` are reports (TSRM p259: left to right, spec §2.3 ``[INF]``): on a
    line that fails later they still act / answer (``#`` alone names the addressed motor)."""
    assert rig.cmd("#3 P1=(3 P2").error == "ERR003"
    assert rig.ok("#") == "3"
    rig.ok("M1->Y:$78802,8")
    reply = rig.cmd("M1-> P1=(3 P2")
    assert (reply.reply, reply.error) == ("Y:$78802,8", "ERR003")


def test_i9_bit0_reports_m_and_l_definitions_as_whole_statements(rig):
    """PSRM I9 / TSRM p328 (spec §2.3): ``M1->`` answers the definition alone with I9 bit 0
    = 0, the whole statement with bit 1 (``L35->`` the same, PUM-V p238 PLCC L-variables)."""
    rig.ok("M1->Y:$78802,8")
    rig.ok("L35->Y:$078802,2,1")
    rig.ok("I9=0")
    assert (rig.ok("M1->"), rig.ok("L35->")) == ("Y:$78802,8", "Y:$78802,2")
    rig.ok("I9=1")
    assert (rig.ok("M1->"), rig.ok("L35->")) == ("M1->Y:$78802,8", "L35->Y:$78802,2")
