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
