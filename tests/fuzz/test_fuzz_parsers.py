"""Fuzzing every parser and codec: no exception escapes, and a rejected input changes nothing.

Targets: PMAC command lines and rotary program lines, Trio BASIC programs and command lines,
scenario YAML, PMAC Ethernet frames, the Trio telnet stream, Modbus TCP frames. "Changes
nothing" is checked by comparing the controller's observable state and its event log before
and after the rejected input. Budgets: ``tests/fuzz/conftest.py``.
"""

from __future__ import annotations

import contextlib

import yaml
from hypothesis import example, given, settings
from hypothesis import strategies as st
from motionsim.api.pmac_ethernet.protocol import (
    EXECUTES,
    NEED_DATA,
    VR,
    Answer,
    PmacEthernetCodec,
    PortWrite,
    pack_request,
)
from motionsim.api.trio_modbus.protocol import ModbusCodec
from motionsim.api.trio_modbus.server import answer as modbus_answer
from motionsim.api.trio_terminal.protocol import TrioTerminalCodec
from motionsim.api.wire import ProtocolError
from motionsim.app.scenarios.errors import ScenarioError
from motionsim.app.scenarios.model import loads_scenario
from motionsim.sim.errors import MotionSimError
from motionsim.sim.pmac import PmacController
from motionsim.sim.trio import TrioController

from tests.fuzz.conftest import counted

PROFILE = settings.get_profile("motionsim-fuzz")

PMAC_WORDS = ["I16", "I17=3", "P1=", "P5", "Q1=2", "M1==1", "M1->Y:$78800,0", "&1", "&2", "#1",
              "B0", "R", "S", "A", "Q", "H", "K", "OPEN ROT", "OPEN PLC 1", "CLOSE", "CLEAR",
              "DEFINE ROT 100", "DEFINE ROT", "DELETE ROT", "DEFINE GATHER", "DELETE GATHER",
              "X10", "Y-2.5", "TM100", "TA10", "F50", "LINEAR", "RAPID", "INC", "ABS", "DWELL10",
              "PR", "??", "?", "LIST", "LIST ROT", "ENABLE PLC 1", "DISABLE PLC 0..31", "IF(",
              "P1>2)", "ENDIF", "WHILE", "ENDWHILE", "CMD\"#1J+\"", "SEND\"x\"", "$$$", "SAVE",
              "SIZE", "VER", "CID", "1e308", "-0", "(", ")", "=", "==", "..", ",", "$FF", "\x01",
              "\x18", "\r", "'comment", ";"]
TRIO_WORDS = ["MOVE(10)", "MOVEABS(1,2)", "MOVECIRC(1,1,0,1,0)", "FORWARD", "REVERSE",
              "CANCEL", "RAPIDSTOP", "BASE(0,1)", "AXIS(1)", "SPEED=100", "ACCEL=1e3",
              "VR(5)=2", "VR(70000)", "TABLE(3)=1", "PRINT", "?", "MTYPE", "NTYPE AXIS(1)",
              "WAIT IDLE", "WAIT UNTIL", "IF", "THEN", "ELSE", "ENDIF", "WHILE", "WEND",
              "REPEAT", "UNTIL", "FOR i=1 TO 3", "NEXT i", "GOSUB lab", "RETURN", "lab:",
              "GOTO lab", "STOP", "RUN \"P\"", "1/0", "1e400", "-", "(", ")", ",", "\"", ":",
              "'x", "AND", "OR", "NOT", "=", "<>", ">="]


def _line(words: list[str]) -> st.SearchStrategy[str]:
    tokens = st.one_of(st.sampled_from(words), st.text(max_size=6))
    return st.lists(tokens, max_size=8).map(" ".join) | st.text(max_size=40)


def _pmac() -> PmacController:
    c = PmacController("pmac", {})
    for cmd in ("&1 DEFINE ROT 200", "&1 B0"):
        _answer(c, cmd)
    return c


def _answer(c: PmacController, text: str):
    reply = c.terminal(text)
    end = c.env.now + 2.0
    while not reply.done and c.env.peek() <= end:
        c.env.step()
    return reply


def _pmac_state(c: PmacController) -> tuple:
    return (c.log.last_seq, c.rotary(1), c.coord(1)["program"])


@PROFILE
@given(lines=st.lists(_line(PMAC_WORDS), min_size=1, max_size=6))
def test_pmac_command_lines_never_raise_anything_but_a_controller_error(lines):
    c = _pmac()
    for text in lines:
        counted("pmac command line")
        with contextlib.suppress(MotionSimError):
            _answer(c, text)


@PROFILE
@given(batch=st.lists(_line(PMAC_WORDS), min_size=1, max_size=5),
       first_seq=st.none() | st.integers(-2, 2**64))
def test_pmac_program_lines_are_stored_whole_or_change_nothing(batch, first_seq):
    c = _pmac()
    c.load_lines(1, ["X1"], first_seq=1)
    before = _pmac_state(c)
    counted("pmac program lines")
    try:
        c.load_lines(1, batch, first_seq=first_seq)
    except MotionSimError:
        assert _pmac_state(c) == before
    else:
        assert c.log.last_seq > before[0] or c.rotary(1)["lines_ahead"] >= 1


def _trio_state(c: TrioController) -> tuple:
    return (c.log.last_seq, tuple(c.program_names()), tuple(map(str, c.processes())))


@PROFILE
@given(program=st.lists(_line(TRIO_WORDS), max_size=8).map("\n".join),
       commands=st.lists(_line(TRIO_WORDS), max_size=4))
def test_trio_basic_programs_and_command_lines_parse_or_change_nothing(program, commands):
    c = TrioController("trio", {})
    c.store_program("KEEP", "VR(1)=1\n")
    before = _trio_state(c)
    counted("trio basic program")
    try:
        c.store_program("P", program)
    except MotionSimError:
        assert _trio_state(c) == before
        assert c.program("KEEP") == "VR(1)=1\n"
    for text in commands:
        counted("trio command line")
        try:
            c.terminal(text)
            c.env.run(until=c.env.now + 0.01)
        except MotionSimError:
            pass


_KEYS = st.sampled_from(["controllers", "hosts", "duration_s", "seed", "kind", "id", "i16",
                         "program", "lines", "rotary", "size_words", "period_ms", "jitter",
                         "config", "moves", "plcs", "faults", "servo_hz", "name", "type"])
_VALUES = st.recursive(
    st.none() | st.booleans() | st.integers(-10**6, 10**6) | st.floats() | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(_KEYS, inner, max_size=4),
    max_leaves=12)


@PROFILE
@given(doc=st.dictionaries(_KEYS, _VALUES, max_size=6).map(yaml.safe_dump)
       | st.text(max_size=200))
@example(doc="\x1f")  # found by this target: a control character escaped as a yaml ReaderError
def test_scenario_yaml_is_a_scenario_or_a_scenario_error(doc):
    counted("scenario yaml")
    try:
        loads_scenario(doc)
    except ScenarioError as exc:
        assert exc.message


_FRAMES = st.builds(
    pack_request,
    st.sampled_from([0x40, 0xC0]) | st.integers(0, 255),
    st.sampled_from([int(v) for v in VR]) | st.integers(0, 255),
    st.integers(0, 0xFFFF), st.integers(0, 0xFFFF),
    st.binary(max_size=40).map(bytes) | _line(PMAC_WORDS).map(lambda s: s.encode("latin-1",
                                                                               "replace")),
    st.none() | st.integers(0, 0xFFFF))


@PROFILE
@given(stream=st.lists(_FRAMES, max_size=6).map(b"".join) | st.binary(max_size=200),
       cut=st.integers(1, 64))
def test_pmac_ethernet_frames_decode_answer_or_are_a_protocol_error(stream, cut):
    counted("pmac ethernet frames")
    codec = PmacEthernetCodec()
    try:
        for pos in range(0, len(stream) + 1, cut):
            codec.receive_data(stream[pos:pos + cut])
            while (req := codec.next_request()) is not NEED_DATA:
                if isinstance(req, PortWrite):
                    codec.port_write(req.char)
                answers = [Answer(("1",), None)] if isinstance(req, EXECUTES) else []
                assert isinstance(codec.reply(req, answers), bytes)
    except ProtocolError:
        pass


@PROFILE
@given(stream=st.binary(max_size=200) | _line(TRIO_WORDS).map(
           lambda s: (s + "\r\n").encode("latin-1", "replace")),
       cut=st.integers(1, 32))
def test_the_trio_telnet_stream_decodes_to_lines_that_the_controller_answers(stream, cut):
    counted("trio telnet stream")
    codec = TrioTerminalCodec()
    c = TrioController("trio", {})
    for pos in range(0, len(stream) + 1, cut):
        codec.receive_data(stream[pos:pos + cut])
        while (line := codec.next_line()) is not NEED_DATA:
            codec.data_to_send()
            with contextlib.suppress(MotionSimError):
                c.terminal(line.text)


class _Handle:
    """The slice of a controller handle the Modbus answer uses, with no clock."""

    def __init__(self, controller: TrioController) -> None:
        self.controller = controller

    def apply(self, fn, *args):
        return fn(*args)


@PROFILE
@given(stream=st.binary(max_size=120) | st.lists(
           st.tuples(st.integers(0, 0xFFFF), st.integers(0, 3), st.integers(0, 0xFF),
                     st.sampled_from([3, 6, 16, 23]) | st.integers(0, 255),
                     st.binary(max_size=16)).map(
               lambda f: f[0].to_bytes(2, "big") + f[1].to_bytes(2, "big")
               + (len(f[4]) + 2).to_bytes(2, "big") + bytes([f[2], f[3]]) + f[4]),
           max_size=5).map(b"".join))
def test_modbus_frames_are_answered_or_a_protocol_error_and_reads_change_nothing(stream):
    counted("modbus frames")
    controller = TrioController("trio", {})
    handle = _Handle(controller)
    codec = ModbusCodec(1023)
    try:
        codec.receive_data(stream)
        while (req := codec.next_request()) is not NEED_DATA:
            before = list(controller.vr)
            out = modbus_answer(handle, codec, req)
            assert isinstance(out, bytes) and len(out) >= 9
            if getattr(req, "function", None) == 3:
                assert controller.vr == before
    except ProtocolError:
        pass
