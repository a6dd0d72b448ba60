"""A bare constant on-line is ``P0={constant}`` (TUM p244); a bare expression is not a
command: ERR003, and nothing changes."""

from __future__ import annotations

import pytest


def test_a_bare_constant_sets_p0(rig):
    assert rig.ok("342") == ""
    assert rig.ok("P0") == "342"
    assert rig.ok("$10") == ""  # a hex constant too
    assert rig.ok("P0") == "16"


@pytest.mark.parametrize("text", ["2+3", "(1+2)", "1.5*2", "P1+1"])
def test_a_bare_expression_is_err003_and_changes_nothing(rig, text):
    rig.ok("P0=7")
    reply = rig.cmd(text)
    assert reply.error == "ERR003"
    assert rig.ok("P0") == "7"
    assert rig.ok("P1") == "0"
