"""Every command of sim/pmac/host/not_simulated.py's table answers ``not_simulated`` on the REST
terminal, not ``parse_error`` — also when its parse fails mid-word or after ``&n`` / ``#n``."""

from __future__ import annotations

import pytest
from motionsim.sim.pmac.host import not_simulated

pytestmark = pytest.mark.anyio

#: One valid Turbo PMAC command per table entry (by its pattern).
EXAMPLES = {
    r"OPEN\s*(BINARY\s*)?ROT": ["OPEN BINARY ROT"],
    r"MS\s*\d|MSR|MSW|MSSAVE|MSCLRERR|MSDATE|MACRO": ["MS0,I910", "MSSAVE0"],
    r"(DEFINE|DEF)\s*(CCBUF|COMP|TCOMP|BLCOMP)": ["&1DEFINE CCBUF 10"],
    r"(DELETE|DEL)\s*(CCBUF|COMP|TCOMP|BLCOMP|PLCC|TEMPS)": ["&1DEL CCBUF"],
    r"PASSWORD": ["PASSWORD=SECRET"],
    r"ENABLE\s*PLCC|ENA\s*PLCC|DISABLE\s*PLCC|DIS\s*PLCC|PLCC": ["ENABLE PLCC 1",
                                                                  "DISABLE PLCC 2"],
    r"(LIST)\s*(LDS|LINK|PE|PC|TCOMP|COMP|BLCOMP|CCBUF|LOOKAHEAD)": [
        "LIST LOOKAHEAD", "&1LIST PC", "&1 LIST PE", "LIST LDS"],
    r"CHECKSUM|CLEAR\s*ALL(?!\s*PLCS)|EAVERSION|DATE|TIME|IDNUMBER|IDC|SID|UPDATE|RESET": [
        "CHECKSUM", "CLEAR ALL", "DATE", "SID"],
    r"(MOVETIME|HOLD|STOP|BLKSTART|BLOCKSTART)": ["&1MOVETIME", "#1HOLD"],
    r"GATHER|ENDGATHER|ENDG\b": ["GATHER", "ENDGATHER"],
}


def test_every_table_entry_has_examples():
    assert set(EXAMPLES) == {p for p, _ in not_simulated._COMMANDS}


@pytest.mark.parametrize("command", [c for cs in EXAMPLES.values() for c in cs])
async def test_a_table_command_is_not_simulated_on_the_rest_terminal(pmac_api, command):
    r = await pmac_api.post("/controllers/p/terminal", json={"command": command})
    body = r.json()
    assert body["error"] == "ERR003", body
    assert body["not_simulated"] is True, body
    assert "does not simulate" in body["detail"]


async def test_a_typo_stays_a_parse_error(pmac_api):
    r = await pmac_api.post("/controllers/p/terminal", json={"command": "&1 LSIT PLC 1"})
    assert r.json()["not_simulated"] is False
