"""How the keyword table's derived matchers choose between overlapping spellings.

* The lexer reads the *longest* command word at a position (TSRM p23: blanks inside a word
  are not significant, so ``END IF`` is ``ENDIF``); a spelling with a blank can share its start
  with a shorter one: the longer must win whichever of them the trie tries first.
* A not-simulated word that begins another one (TSRM program commands ``NOFRAX`` and
  ``NOFRAX2``) is named by the longer when the longer is written.
* ``ENABLE PLCC`` is simulated (TUM p376: compiled PLCs), so it is answered, not refused.
"""

from __future__ import annotations

import re

import pytest
from motionsim.sim.pmac.host import not_simulated
from motionsim.sim.pmac.language.keywords import lexer_pattern


@pytest.mark.parametrize("words", [["AB", "A BCDE"], ["A BCDE", "AB"], ["AB", "ABC", "A BCDE"]])
@pytest.mark.parametrize(("text", "word"), [
    ("ABCDE", "ABCDE"), ("A  BCDE", "A  BCDE"), ("AB", "AB"), ("ABX", "AB")])
def test_tsrm_p23_the_lexer_pattern_reads_the_longest_word_blanks_or_not(words, text, word):
    assert re.match(lexer_pattern(words), text).group() == word


def test_nofrax2_is_named_nofrax2_not_nofrax(rig):
    for command in ("NOFRAX2", "NOFRAX"):
        reply = rig.cmd(command)
        assert reply.error == "ERR003"
        assert reply.detail is not None and reply.detail[0] == "not_simulated"
        assert reply.detail[1].startswith(f"{command} is a valid Turbo PMAC command")


def test_tum_p376_enable_plcc_is_simulated(rig):
    rig.ok("OPEN PLCC 3 CLEAR")
    rig.ok("P1=1")
    rig.ok("CLOSE")
    reply = rig.cmd("ENABLE PLCC 3")
    assert (reply.error, reply.detail) == (None, None)
    assert rig.c.plcs.compiled[3].enabled


#: Valid commands (TSRM on-line and program command lists) that motionsim does not simulate,
#: written out by hand, and the name the terminal gives each: the object forms come after a
#: simulated object of the same command (DEFINE ROTARY, OPEN PROG, LIST PLC ...).
NOT_SIMULATED = [
    ("DEFINE CCBUF 1", "DEFINE CCBUF"), ("DEF TCOMP", "DEFINE TCOMP"),
    ("DEFINE BLCOMP", "DEFINE BLCOMP"), ("DELETE CCBUF", "DELETE CCBUF"),
    ("DELETE TEMPS", "DELETE TEMPS"), ("OPEN BINARY ROTARY", "OPEN BINARY"),
    ("OPEN SERVO", "OPEN SERVO"), ("LIST LDS", "LIST LDS"), ("LIST LINK", "LIST LINK"),
    ("LIST TCOMP", "LIST TCOMP"), ("LIST COMP", "LIST COMP"),
    ("LIST LOOKAHEAD", "LIST LOOKAHEAD"),  # GATHER TRIGGER is simulated (tasks/gather.py)
    ("NOFRAX2", "NOFRAX2"), ("NOFRAX", "NOFRAX"),
]


@pytest.mark.parametrize(("text", "name"), NOT_SIMULATED)
def test_which_names_each_not_simulated_command_by_its_longest_form(text, name):
    assert not_simulated.which(text, 1) == name


def test_tum_p376_enable_plcc_without_a_list_is_a_parse_error_not_a_missing_feature(rig):
    reply = rig.cmd("ENABLE PLCC")
    assert reply.error == "ERR003"
    assert reply.detail is not None and reply.detail[0] == "parse_error"
