"""Controller-level rules of the simulated Turbo PMAC that the narrower test files leave open:
the config check, the event ring, buffer memory (``SIZE``, TSRM SIZE), the ``DEFINE ROT``
refusals (TUM p337), the REST batch and single-line paths of ``load_lines`` (API.md "rotary
lines", parse errors with ``index`` / ``line`` / ``column`` / ``text``), ports that go away,
``CMD"..."`` addressing (TSRM p422), motor reports (TSRM p402) and Mxx62 writes, and the
controller resource's figures (API.md "PLC programs"). Virtual time throughout."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import BufferFull, Halted, InvalidValue, NotFound, ParseError
from motionsim.sim.pmac import PmacController


def _refusal(rig, text: str, port=None) -> tuple[str | None, str]:
    """The error code and the message a terminal line is refused with."""
    reply = rig.cmd(text, port)
    return reply.error, (reply.detail or ("", ""))[1]


# -- construction ---------------------------------------------------------------------------


def test_a_processor_cost_key_does_not_end_the_config_check():
    """Unknown keys are refused naming the field, also when a ``cpu_*_us`` key comes first."""
    with pytest.raises(InvalidValue) as refused:
        PmacController("pmac", {"cpu_housekeeping_us": 20, "i99999": 1})
    assert refused.value.details["field"] == "i99999"
    with pytest.raises(InvalidValue) as refused:
        PmacController("pmac", {"cpu_host_command_us": 20, "servo_khz": 1})
    assert refused.value.details["field"] == "servo_khz"


def test_the_event_ring_holds_the_last_100000_events():
    """API.md events: the log keeps the last 100 000 events (the service's default capacity);
    the 100 001st drops the first, and a reader from the start is told it lost seq 1."""
    c = PmacController("pmac")
    for i in range(100_000):
        c.log.emit("mvar", name="M1", value=float(i), sync=False)
    assert c.log.first_seq == 1
    c.log.emit("mvar", name="M1", value=-1.0, sync=False)
    assert (c.log.first_seq, c.log.last_seq) == (2, 100_001)
    page = c.log.read(0, limit=1)
    assert (page.gap.from_seq, page.gap.to_seq) == (1, 1)
    assert page.events[0].seq == 2


def test_coordinate_systems_are_numbered_1_to_16(rig):
    """A Turbo PMAC has coordinate systems &1..&16: CS 0 and 17 do not exist."""
    assert rig.c.coord(16)["cs"] == 16
    for cs in (0, 17):
        with pytest.raises(NotFound):
            rig.c.coord(cs)
    assert set(rig.c.coord_systems) == set(range(1, 17))


# -- buffer memory and DEFINE ROT -------------------------------------------------------------


def test_size_is_what_the_rotary_gather_and_program_buffers_leave_free(rig):
    """TSRM SIZE: the 65 536 words less the rotary buffers, the gather buffer and the fixed
    programs' words (here 1000 + 500 + 3)."""
    rig.ok("&1 DEFINE ROT 1000")
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("X1")
    rig.ok("X2 Y3")
    rig.ok("CLOSE")
    assert rig.ok("SIZE") == str(65_536 - 1000 - 3)
    rig.ok("DEFINE GATHER 500")
    assert rig.ok("SIZE") == str(65_536 - 1000 - 500 - 3)


@pytest.mark.parametrize("words", [0, -5, True, 2.5, "10", None])
def test_a_rotary_buffer_size_must_be_a_positive_whole_number(rig, words):
    """REST ``PUT .../rotary {"size_words"}``: anything but a whole number >= 1 is refused
    naming ``size_words``, and no buffer is defined."""
    with pytest.raises(InvalidValue) as refused:
        rig.c.define_rotary(1, words)
    assert refused.value.details["field"] == "size_words"
    assert rig.c.rotary(1) is None


def test_a_one_word_rotary_buffer_holds_one_one_word_line(rig):
    """The smallest buffer, 1 word, takes ``X1`` (one word) and refuses the next with ERR006."""
    rig.c.define_rotary(1, 1)
    assert rig.c.load_lines(1, ["X1"]).free_words == 0
    with pytest.raises(BufferFull) as full:
        rig.c.load_lines(1, ["X2"])
    assert full.value.pmac_error == "ERR006"
    assert rig.c.rotary(1)["used_words"] == 1


def test_define_rot_names_the_lowest_cs_that_already_has_a_buffer(rig):
    """TUM p337: rotary buffers are defined from the highest CS down; ``&4 DEFINE ROT`` after
    CS 3 and CS 2 have theirs is ERR003 naming CS 2, the lowest."""
    rig.ok("&3 DEFINE ROT 100")
    rig.ok("&2 DEFINE ROT 100")
    error, message = _refusal(rig, "&4 DEFINE ROT 100")
    assert error == "ERR003"
    assert message.startswith("CS 2 (lower-numbered)")
    assert rig.c.rotary(4) is None


def test_define_rot_on_a_cs_that_has_one_says_so(rig):
    """A second ``DEFINE ROT`` for the same CS is ERR003 because it has one already, not
    because of the ordering rule (no lower CS has a buffer)."""
    rig.ok("&1 DEFINE ROT 100")
    error, message = _refusal(rig, "&1 DEFINE ROT 200")
    assert (error, message) == ("ERR003", "CS 1 already has a rotary buffer")
    assert rig.c.rotary(1)["size_words"] == 100


def test_open_prog_names_the_lowest_cs_that_is_running(rig):
    """TSRM p381: ``OPEN PROG`` while a CS runs a program is ERR001; with CS 2 and CS 3
    running it names CS 2."""
    rig.ok("OPEN PROG 5 CLEAR")
    rig.ok("TM1000 X1")
    rig.ok("CLOSE")
    rig.ok("&3 B5 R")
    rig.ok("&2 B5 R")
    error, message = _refusal(rig, "OPEN PROG 6")
    assert (error, message) == ("ERR001", "CS 2 is running a program")


def test_a_prog_line_may_take_the_last_free_word(rig):
    """A fixed-program line fits while buffer memory has its words free: with one word left
    ``X1`` is stored, the next line is ERR006."""
    rig.ok("&1 DEFINE ROT 65535")
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("X1")
    assert rig.cmd("X2").error == "ERR006"
    rig.ok("CLOSE")
    assert rig.c.program_lines(1) == ["X1"]
    assert rig.ok("SIZE") == "0"


# -- load_lines: the REST rotary-lines resource -------------------------------------------------


def test_a_halted_card_refuses_rotary_lines(make_rig):
    """TSRM p57: after a watchdog trip the card takes nothing — a line POST is refused and
    nothing is stored."""
    rig = make_rig(i40=10)
    rig.rotary_setup()
    rig.c.plcs.load(0, "\n".join(["P10=P10+1"] * 500))  # ≈ 1.66 ms of the 1.33 ms RTI
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.05)
    assert rig.c.halted
    for lines in (["X1"], ["X1", "X2"]):
        with pytest.raises(Halted):
            rig.c.load_lines(1, lines)
    assert rig.c.rotary(1)["used_words"] == 0


@pytest.mark.parametrize("cs", [17, 0, [1], "1"])
def test_lines_for_no_such_cs_are_not_found(rig, cs):
    """A line POST for a CS that does not exist is 404 ``not_found``, whatever the path
    parameter's type."""
    rig.rotary_setup()
    with pytest.raises(NotFound):
        rig.c.load_lines(cs, ["X1"])
    assert rig.c.rotary(1)["used_words"] == 0


def test_lines_for_a_cs_without_a_rotary_buffer_are_not_found(rig):
    rig.rotary_setup(cs=2)
    with pytest.raises(NotFound):
        rig.c.load_lines(1, ["X1"])


@pytest.mark.parametrize("texts", [["X1"], ["X1", "X2"]])
@pytest.mark.parametrize("make", [tuple, iter, lambda t: (x for x in t)])
def test_lines_may_come_as_any_iterable(rig, texts, make):
    """``load_lines`` takes any iterable of line texts, one line or several, in order."""
    rig.rotary_setup()
    result = rig.c.load_lines(1, make(texts))
    assert (result.accepted, result.stored) == (len(texts), len(texts))
    assert [line.text for _, line in rig.c.coord_system(1).rotary.pending] == texts


def test_an_empty_batch_stores_nothing(rig):
    rig.rotary_setup()
    result = rig.c.load_lines(1, [])
    assert (result.accepted, result.stored, result.lines_ahead) == (0, 0, 0)
    assert result.free_words == 600
    assert rig.events("line_loaded") == []


def test_one_line_reports_what_the_api_documents(rig):
    """API.md: ``{"accepted", "lines_ahead", "free_words", "breq"}`` — one line POSTed alone
    is accepted and stored, one line ahead, the buffer's words less its own."""
    rig.rotary_setup(words=600)
    result = rig.c.load_lines(1, ["X1 Y2"])
    assert (result.accepted, result.stored, result.lines_ahead) == (1, 1, 1)
    assert result.free_words == 598
    result = rig.c.load_lines(1, ["X3"])
    assert (result.accepted, result.lines_ahead, result.free_words) == (1, 2, 597)


@pytest.mark.parametrize("batch", [[["X1"]], ["X1", {"X": 2}], [None], ["X1", None]])
def test_a_line_that_is_not_text_is_refused_naming_its_index(rig, batch):
    """A batch entry that is not a string is 422 ``validation_error`` on ``lines`` with its
    0-based ``index``; nothing of the batch is stored."""
    rig.rotary_setup()
    with pytest.raises(InvalidValue) as refused:
        rig.c.load_lines(1, batch)
    assert refused.value.details == {"field": "lines", "index": len(batch) - 1}
    assert rig.c.rotary(1)["used_words"] == 0


@pytest.mark.parametrize("batch", [
    ["X1 Q"], ["X1", "X2 Q"], ["X1", "X2", "X3 Q"], ["X1"] * 3 + ["X4 Q"],
])
def test_a_batch_parse_error_names_the_index_and_the_line(rig, batch):
    """API.md: a parse error carries ``index`` (0-based in the batch) and ``line`` (1-based,
    the same line counted from 1), the ``column`` and ERR003; nothing is stored."""
    rig.rotary_setup()
    with pytest.raises(ParseError) as refused:
        rig.c.load_lines(1, batch)
    e = refused.value
    assert (e.index, e.line, e.pmac_error) == (len(batch) - 1, len(batch), "ERR003")
    assert (e.details["index"], e.details["line"]) == (len(batch) - 1, len(batch))
    assert rig.c.rotary(1)["used_words"] == 0


@pytest.mark.parametrize("index", [0, 3])
def test_an_overlong_line_names_its_index_line_and_column(rig, index):
    """A line over the 255 characters a command line holds is ERR003 at column 256, with its
    batch ``index``, its 1-based ``line`` and its first 80 characters as ``text``."""
    rig.rotary_setup()
    long = "X1 " * 100
    with pytest.raises(ParseError) as refused:
        rig.c.load_lines(1, ["X1"] * index + [long])
    e = refused.value
    assert (e.index, e.line, e.column, e.pmac_error) == (index, index + 1, 256, "ERR003")
    assert e.text == long[:80] + "..."


def test_a_batch_of_more_distinct_lines_than_the_parse_cache_holds_is_stored_whole(rig):
    """The batch is atomic and unbounded but for memory: 8193 lines never sent before (more
    than the 8192 texts the parse cache keeps) are all stored, in order."""
    rig.rotary_setup(words=20_000)
    lines = [f"X{i}.5 Y-{i}.25" for i in range(8193)]
    result = rig.c.load_lines(1, lines)
    assert (result.accepted, result.stored, result.lines_ahead) == (8193, 8193, 8193)
    pending = rig.c.coord_system(1).rotary.pending
    assert [line.text for _, line in pending] == lines


# -- ports --------------------------------------------------------------------------------------


def test_a_port_that_goes_away_with_a_plc_open_drops_the_edit(rig):
    """A host that disconnects while it holds ``OPEN PLC 3`` loses the edit: the old program
    stays, and another port may open the PLC."""
    host = rig.c.open_port("host")
    rig.c.plcs.load(3, "P1=1")
    rig.ok("OPEN PLC 3 CLEAR", host)
    rig.ok("P2=2", host)
    rig.c.close_port(host)
    plc = rig.c.plcs.describe(3)
    assert (plc["state"], plc["program"]) == ("disabled", ["P1=1"])
    other = rig.c.open_port("other")
    assert rig.cmd("OPEN PLC 3", other).error is None


def test_plc_cmd_addressing_starts_at_motor_1(rig):
    """TSRM p422: each ``CMD"..."`` starts addressed to motor 1 — ``CMD"J:50"`` after
    ``CMD"#2J:100"`` jogs motor 1, not motor 2."""
    rig.ok("OPEN PLC 0 CLEAR")
    for line in ('CMD"#2J:100"', 'CMD"J:50"', "DISABLE PLC 0"):
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok("ENABLE PLC 0")
    rig.run_for(1.0)
    assert (rig.ok("#1P"), rig.ok("#2P")) == ("50", "100")


# -- motors -------------------------------------------------------------------------------------


def test_an_axis_definition_without_a_scale_is_one_count_per_unit(rig):
    """TSRM ``#n->{axis}``: the scale factor defaults to 1 — ``#2->X`` moves 1.5 counts for
    X1.5, ``#3->5X`` 7.5, ``#1->1000X`` 1500; ``P`` reports counts to 0.1 (TSRM p402); motor
    4 on the CS's Y axis, never commanded, stays at 0."""
    rig.ok("&1 #1->1000X #2->X #3->5X #4->1000Y")
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 X0.01234"])
    rig.ok("R")
    rig.run_until_idle()
    assert [rig.ok(f"#{n}P") for n in (1, 2, 3, 4)] == ["12.3", "0", "0.1", "0"]
    rig.c.load_lines(1, ["X1.5"])
    rig.run_until_idle()
    assert [rig.ok(f"#{n}P") for n in (1, 2, 3, 4)] == ["1500", "1.5", "7.5", "0"]


@pytest.mark.parametrize("motor", [2, 32])
def test_writing_mxx62_moves_the_position_reference_of_motor_xx(rig, motor):
    """Mxx62 (actual position, 1/(Ixx08·32) counts, D:$00008B + $80·(xx−1)) written after a
    jog: motor xx now reports the written position, without motion (backup tools restore
    positions this way)."""
    address = 0x8B + 0x80 * (motor - 1)
    rig.ok(f"M{motor}62->D:${address:06X}")
    rig.ok(f"#{motor}J=1000")
    rig.run_for(1.0)
    assert rig.ok(f"#{motor}P") == "1000"
    since = rig.c.log.last_seq
    rig.ok(f"M{motor}62={-75 * 96 * 32}")
    assert rig.ok(f"#{motor}P") == "-75"
    rig.run_for(0.1)
    assert rig.ok(f"#{motor}P") == "-75"
    assert rig.events("move_start", "jog", since=since) == []


def test_f_reports_no_following_error_while_a_motor_jogs(rig):
    """``F`` (TSRM p402) reports the following error; the simulated loop tracks perfectly
    (``[INF]``), so it is 0 also while the motor moves and ``V`` is not."""
    rig.ok("#1J+")
    rig.run_for(0.5)
    assert float(rig.ok("#1V")) > 1
    assert rig.ok("#1F") == "0"


# -- variables ----------------------------------------------------------------------------------


def test_enabling_plcs_with_i5_over_rest_starts_the_scans_at_once(make_rig):
    """I5 = 0 runs no PLC (TSRM I5); an enabled PLC 1 starts scanning in the first background
    cycle after a REST write of I5 = 2."""
    rig = make_rig(i5=0)
    rig.c.plcs.load(1, "M1=M1+1")
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.1)
    assert rig.events("mvar") == []
    t = rig.c.now
    rig.c.set_variable("I5", 2)
    rig.run_for(0.01)
    first = rig.events("mvar")[0]
    assert first[0] * rig.period - t < rig.period


@pytest.mark.parametrize("command", ["&1 B1.5", "&1 B0.5"])
def test_b_with_a_line_label_is_refused(rig, command):
    """``B{n}.{label}`` points into a PROG at a line label (TSRM p295); labels are not
    simulated, so it is ERR003 and the CS stays pointed where it was."""
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("TM10 X1")
    rig.ok("CLOSE")
    rig.ok("&1 B1")
    assert rig.cmd(command).error == "ERR003"
    assert rig.c.coord_system(1).program == 1


@pytest.mark.parametrize("prog", [1, 1000])
def test_r_after_q_continues_a_fixed_program_where_it_stopped(rig, prog):
    """TSRM Q / R: a PROG quit mid-way stops after the moves already calculated; ``R`` then
    runs on from the next line, not from the top (PROG 1 and PROG 1000 alike)."""
    rig.ok(f"OPEN PROG {prog} CLEAR")
    for line in ["TM100 TA10 TS0"] + [f"X{i}" for i in range(1, 9)]:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok(f"&1 B{prog} R")
    rig.run_for(0.05)
    rig.ok("&1 Q")
    rig.run_until_idle()
    assert [e["n"] for _, _, e in rig.events("move_start")] == [2, 3, 4]
    rig.ok("&1 R")
    rig.run_until_idle()
    assert [e["n"] for _, _, e in rig.events("move_start")] == [2, 3, 4, 5, 6, 7, 8, 9]
    assert rig.c.positions(1)["X"] == 8.0


# -- the controller resource --------------------------------------------------------------------


def test_the_controller_resource_lists_plcs_holding_a_program_or_ever_scanned(make_rig):
    """API.md: ``"plcs"`` has an entry for each PLC holding a program or ever scanned — PLC 1
    scanned then cleared, PLC 2 loaded but never enabled, not the PLCs that are neither."""
    rig = make_rig(i5=3)
    assert rig.c.status()["plcs"] == {}
    rig.c.plcs.load(1, "P1=P1+1")
    rig.c.plcs.load(2, "P2=P2+1")
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.01)
    rig.ok("OPEN PLC 1 CLEAR")
    rig.ok("CLOSE")
    plcs = rig.c.status()["plcs"]
    assert set(plcs) == {"1", "2"}
    assert plcs["1"]["scans"] > 0 and plcs["2"] == {"statements_last_scan": 0, "scans": 0}


def test_the_controller_resource_lists_coordinate_systems_with_a_buffer_or_running(rig):
    """The controller resource's ``coord`` map: the state of each CS that has a rotary buffer
    or is not idle — CS 2 (buffer, idle) and CS 3 (running PROG 5), no other."""
    assert rig.c.status()["coord"] == {}
    rig.ok("&2 DEFINE ROT 100")
    rig.ok("OPEN PROG 5 CLEAR")
    rig.ok("TM1000 X1")
    rig.ok("CLOSE")
    rig.ok("&3 B5 R")
    rig.run_for(0.01)
    status = rig.c.status()
    assert status["coord"] == {"2": "idle", "3": "running"}
    assert set(status["watchdog"]) == {"tripped", "t", "reload_s", "limit_cycles", "cycles_left"}
    rig.ok("&3 A")
    rig.run_for(0.01)
    assert rig.c.status()["coord"] == {"2": "idle", "3": "aborted"}


# -- the terminal and streaming ---------------------------------------------------------------


def test_a_prompt_reply_is_not_announced_as_a_terminal_reply_event(rig):
    """API.md: only a reply later than the 1 s terminal wait is a ``terminal_reply`` event —
    also for a command sent after the first simulated second."""
    rig.run_for(2.5)
    assert rig.ok("I16") == "5"
    assert rig.events("terminal_reply") == []


def _lookahead_stream(rig, first_seq: int | None) -> int:
    """CS 1 in the special lookahead (Isx13 = 10 ms, Isx20 = 45 segments, TM100 moves):
    three moves running, then one more line; the cycles from its arrival to its calculation."""
    rig.ok("&1 #1->1000X")
    for cmd in ("I5113=10", "I5120=45", "I117=1000", "&1 DEFINE LOOKAHEAD 50,10"):
        rig.ok(cmd)
    rig.rotary_setup()
    seq = None if first_seq is None else 0
    rig.c.load_lines(1, ["LINEAR ABS TA10 TS0 TM100", "X0.01", "X0.02", "X0.03"], first_seq=seq)
    rig.ok("R")
    rig.run_for(0.05)
    since = rig.c.log.last_seq
    k = rig.c.scheduler.clock.index(rig.c.now)  # the cycle at or before now
    rig.c.load_lines(1, ["X0.04"], first_seq=first_seq)
    rig.run_for(0.3)
    (calc,) = [e for e in rig.events("line_calculated", since=since) if e[2]["n"] == 5]
    return calc[0] - k


@pytest.mark.parametrize("first_seq", [None, 4])
def test_a_line_streamed_into_the_special_lookahead_is_calculated_at_the_next_rti(
    rig, first_seq
):
    """TSRM p181: with the special lookahead the CS calculates Isx20 segments (here 450 ms)
    ahead, so a line that arrives while less than that is calculated is calculated at the next
    RTI (I8+1 = 3 servo cycles) — whether it comes alone or numbered with ``first_seq``."""
    assert 0 < _lookahead_stream(rig, first_seq) <= 3
