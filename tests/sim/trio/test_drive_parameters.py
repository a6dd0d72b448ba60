"""Issue 22 item 3: the start-up and drive parameters real programs write, stored with their
power-up values and read back (spec §11.5, §11.7), and the set-up commands they call."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import fields, make, run_to


@pytest.mark.parametrize(("name", "power_up", "written"), [
    ("P_GAIN", "1.0000", "0.2500"),  # M206-363, TRM p. 8-173: 1.0, fractions allowed
    ("I_GAIN", "0.0000", "0.0100"),  # M206-355, TRM p. 8-165
    ("D_GAIN", "0.0000", "2.5000"),  # M216-349, TRM p. 8-159
    ("OV_GAIN", "0.0000", "-1.5000"),  # M206-361, TRM p. 8-171: negative = damping
    ("VFF_GAIN", "0.0000", "12.0000"),
    ("CLUTCH_RATE", "0.0000", "1000000.0000"),
    ("DATUM_IN", "-1.0000", "5.0000"),
    ("REP_OPTION", "0.0000", "1.0000"),
])
def test_trm_gains_and_start_up_parameters_power_up_and_read_back(name, power_up, written):
    c = make(model="mc4xx")
    assert c.terminal(f"? {name} AXIS(2)").reply == power_up
    value = float(written)
    assert c.terminal(f"{name} AXIS(2)={value:g}").error is None
    assert c.terminal(f"? {name} AXIS(2)").reply == written
    assert c.terminal(f"? {name} AXIS(1)").reply == power_up  # per axis


@pytest.mark.parametrize("name", ["DRIVE_STATUS", "FE_LATCH", "FE", "ENCODER"])
def test_m216_349_read_only_drive_parameters_read_0_and_refuse_a_write(name):
    c = make()
    assert c.terminal(f"PRINT {name} AXIS(0)").reply == "0.0000"
    r = c.terminal(f"{name}=1")
    assert r.error is not None and f"{name} cannot be written" in r.error


def test_m216_367_fe_is_an_axis_parameter_in_programs_and_at_the_command_line():
    c = make()
    c.store_program("FE", "MOVE(50)\nWA(10)\nVR(0)=FE AXIS(0)\nVR(1)=FE_LIMIT AXIS(0)\n"
                    "IF FE > FE_LIMIT THEN VR(2)=1\n")
    c.run_program("FE", 1)
    run_to(c, 0.2)
    assert [c.get_variable(f"VR({i})") for i in range(3)] == [0.0, 2000.0, 0.0]


@pytest.mark.parametrize(("cmd", "message"), [
    ("DATUM_IN=-2", "DATUM_IN"), ("REP_DIST=-1", "REP_DIST"), ("CLUTCH_RATE=-5", "CLUTCH_RATE"),
    ("LIMIT_BUFFERED=0", "LIMIT_BUFFERED"),
])
def test_out_of_range_values_are_refused_and_change_nothing(cmd, message):
    c = make(model="mc4xx")
    name = cmd.split("=")[0]
    before = c.terminal(f"? {name}").reply
    r = c.terminal(cmd)
    assert r.error is not None and message in r.error
    assert c.terminal(f"? {name}").reply == before


def test_set_up_commands_of_a_start_up_program_run_and_are_logged():
    c = make(model="mc4xx")
    prog = ("SETCOM(9600,8,1,2,2,4)\nETHERNET(1,-1,10,502)\nETHERCAT(0,0)\n"
            "ETHERCAT($22,0,50)\nUNIT_CLEAR\nTRIGGER\nSTEP_RATIO(-1,1) AXIS(1)\n"
            "ENCODER_RATIO(4,1) AXIS(1)\nINVERT_IN(3,ON)\n")
    c.store_program("STARTUP", prog)
    c.run_program("STARTUP", 1)
    run_to(c, 0.1)
    assert "error" not in fields(c, "process", process=1, state="stopped")[0][1]
    assert [f["command"] for _t, f in fields(c, "setup")] == [
        "SETCOM", "ETHERNET", "ETHERCAT", "ETHERCAT", "UNIT_CLEAR", "TRIGGER", "STEP_RATIO",
        "ENCODER_RATIO", "INVERT_IN"]
    assert c.get_variable("VR(50)") == 3.0  # the bus reads operational
    assert c.terminal("? IN(3)").reply == "1.0000"  # inverted: OFF reads ON
    assert c.system.comms.setcom[2] == (9600.0, 8.0, 1.0, 2.0, 2.0, 4.0)


def test_m216_547_ethernet_read_prints_the_default_ip_address():
    c = make()
    r = c.terminal("ETHERNET(0,-1,0)")
    assert r.error is None and r.reply == "192.168.0.250"


def test_tjcj159_encoder_ratio_scales_the_raw_encoder_count():
    """MPOS = num/den x encoder edges: with ENCODER_RATIO(4,1) and UNITS 10, MPOS 25 is
    25 x 10 x 4 encoder edges."""
    c = make(units=10)
    c.terminal("ENCODER_RATIO(4,1)")
    c.terminal("MOVE(25)")
    run_to(c, 1.0)
    assert c.terminal("? MPOS").reply == "25.0000"
    assert c.terminal("? ENCODER").reply == "1000.0000"


@pytest.mark.parametrize("cmd", ["ENCODER_RATIO(0,1)", "ENCODER_RATIO(1,16777216)",
                                 "SETCOM(9600,6,1,2,2)", "ETHERNET(3,-1,0)", "ADDAX(0)"])
def test_bad_set_up_command_arguments_are_an_error_naming_the_command(cmd):
    c = make()
    r = c.terminal(cmd)
    assert r.error is not None and cmd.split("(")[0] in r.error


def test_a_set_up_command_with_the_wrong_argument_count_is_refused_at_load():
    from motionsim.sim.errors import ParseError

    c = make()
    with pytest.raises(ParseError) as err:
        c.store_program("BAD", "MOVE(1)\nSETCOM(9600)\n")
    assert (err.value.details["line"], err.value.details["column"]) == (2, 7)
    assert c.program_names() == []


def _program_end(model: str, limit: int | None) -> tuple[float, float]:
    """When a program issuing six MOVE(10) (20 servo periods each) reaches its last line, and
    MOVES_BUFFERED there."""
    c = make(model=model)
    pre = f"LIMIT_BUFFERED={limit}\n" if limit is not None else ""
    c.store_program("Q", pre + "FOR i=1 TO 6\n  MOVE(10)\nNEXT i\nVR(0)=MOVES_BUFFERED\n")
    c.run_program("Q", 1)
    run_to(c, 1.0)
    (t_end, _f), = fields(c, "process", process=1, state="stopped")
    return t_end, c.get_variable("VR(0)")


def test_tj2h57_limit_buffered_is_the_look_ahead_size_of_each_axis():
    """MC4xx: six MOVE(10) find room in a look-ahead of 64, so the program only waits for
    each servo interrupt to empty its process buffer (M206-320) and ends within 8 ms with five
    moves on the axis (the sixth still in its process buffer); with LIMIT_BUFFERED=2 the
    look-ahead holds two and the program waits for two moves to end (20 periods each) before
    its last MOVE is buffered; the MC2xx (NTYPE only) waits for three."""
    t_end, buffered = _program_end("mc4xx", None)
    assert t_end < 0.008 and buffered == 5.0
    t_end, buffered = _program_end("mc4xx", 2)
    assert 0.040 < t_end < 0.046 and buffered == 3.0  # MTYPE and two in the look-ahead
    t_end, buffered = _program_end("mc2xx", None)
    assert 0.060 < t_end < 0.066 and buffered == 2.0  # MTYPE and NTYPE


def test_tn20_mc2xx_has_one_ntype_and_refuses_a_deeper_limit_buffered():
    c = make()
    assert c.terminal("? LIMIT_BUFFERED").reply == "1.0000"
    r = c.terminal("LIMIT_BUFFERED=8")
    assert r.error is not None and "LIMIT_BUFFERED" in r.error
    assert c.terminal("? LIMIT_BUFFERED").reply == "1.0000"
    assert c.terminal("? LIMIT_BUFFERED").reply == "1.0000"


def test_limit_buffered_moves_run_in_order_and_end_where_they_add_up():
    c = make(model="mc4xx")
    for d in (10, 20, 30, 40):
        c.terminal(f"MOVE({d})")
        run_to(c, c.now + 0.001)
    assert c.terminal("? MOVES_BUFFERED").reply == "4.0000"
    c.env.run()
    starts = [t for t, _ in fields(c, "move_start", axis=0)]
    ends = [t for t, _ in fields(c, "move_end", axis=0)]
    assert len(starts) == 4 and all(e < s for e, s in zip(ends, starts[1:], strict=False))
    assert c.axis(0)["dpos"] == 100.0


def test_docs_trio_md_lists_every_stored_parameter_and_set_up_command():
    """docs/trio.md says for each parameter and set-up command what the simulator does."""
    from pathlib import Path

    from motionsim.sim.trio.card.parameters import STORED
    from motionsim.sim.trio.card.setup_commands import COMMANDS

    doc = (Path(__file__).resolve().parents[3] / "docs" / "trio.md").read_text()
    missing = [n for n in [*(p.name for p in STORED), *COMMANDS, "LIMIT_BUFFERED", "FE",
                           "ENCODER"] if f"`{n}" not in doc]
    assert missing == []


@pytest.mark.parametrize(("model", "accepted", "refused"), [
    ("mc2xx", [1], [0, 2, 1.5]),
    ("mc4xx", [1, 2, 64], [0, 65, 2.5, -1]),
])
def test_tj2h57_limit_buffered_takes_a_whole_number_of_moves_up_to_the_models_largest(
        model, accepted, refused):
    """LIMIT_BUFFERED (TJ2H-57) counts moves: 1..64 on the MC4xx (up to 64 buffers per axis,
    TJ2P-20), 1 only on the MC2xx (NTYPE, TN20 ``[INF]``); a fraction of a move is refused,
    as a number beyond the range, and the look-ahead keeps its size."""
    c = make(model=model)
    for n in accepted:
        assert c.terminal(f"LIMIT_BUFFERED={n}").error is None, n
        assert float(c.terminal("? LIMIT_BUFFERED").reply) == n
        assert c.buffers.depth == n
    for value in refused:
        r = c.terminal(f"LIMIT_BUFFERED={value}")
        assert r.error is not None and "LIMIT_BUFFERED" in r.error, value
        assert float(c.terminal("? LIMIT_BUFFERED").reply) == accepted[-1]
        assert c.buffers.depth == accepted[-1]
