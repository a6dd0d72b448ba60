"""Idioms of real Turbo PMAC programs and hosts (issue 37 item 6) not covered elsewhere.

* ``COMMAND"..."`` is a program command (motion program or PLC, TSRM p421-424): on-line with
  no buffer open it is "allowed only with a buffer open", ERR005 (TUM p46: commands that
  cannot be on-line are rejected with ERR005), also after ``&n`` (``&1COMMAND"J+"``).
* ``{axis}{data}^{data}`` (TSRM program command, move until trigger) is valid Turbo PMAC and
  not simulated: answered by name, never "unexpected '^'", and the buffer is unchanged.
"""

from __future__ import annotations

import pytest


@pytest.mark.parametrize("line", ['&1COMMAND"J+"', 'COMMAND"#1J+"', 'CMDS"&2B1R"'])
def test_tum_p46_a_command_statement_on_line_is_err005(rig, line):
    r = rig.cmd(line)
    assert r.error == "ERR005"
    assert rig.events("jog", "program") == []


@pytest.mark.parametrize("line", ["RAPID X10^5", "X10^-5 Y2", "X(P1)^(P2)"])
def test_tsrm_move_until_trigger_is_answered_by_name_and_stores_nothing(rig, line):
    rig.rotary_setup()
    port = rig.c.open_port("host")
    rig.ok("OPEN ROT", port)
    since = rig.c.log.last_seq
    r = rig.cmd(line, port)
    assert r.error == "ERR003"
    assert r.detail[0] == "not_simulated" and "move until trigger" in r.detail[1]
    assert rig.c.rotary(1)["used_words"] == 0
    assert rig.events("line_loaded", since=since) == []
