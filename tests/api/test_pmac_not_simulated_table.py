"""Every not-simulated row and object of the keyword table (sim/pmac/language/keywords.py),
and every letter command of sim/pmac/host/not_simulated.py, answers ``not_simulated`` naming
it on the REST terminal, not ``parse_error`` — also after ``&n`` / ``#n`` addressing."""

from __future__ import annotations

import pytest
from motionsim.sim.pmac.host import not_simulated
from motionsim.sim.pmac.language import keywords

pytestmark = pytest.mark.anyio

#: One valid Turbo PMAC command per letter-command pattern.
LETTER_EXAMPLES = {
    "LIST PE / LIST PC": ["&1LIST PC", "&1 LIST PE"],
    "CLEAR ALL": ["CLEAR ALL"],
    "BLKSTART": ["BLKSTART"],
}  # (G/M/T/D codes are simulated since issue 37: tests/sim/pmac/test_rotary_gcode.py)
TABLE_EXAMPLES = keywords.examples()


def test_every_letter_command_has_examples():
    assert set(LETTER_EXAMPLES) == {name for _, name in not_simulated._LETTER_COMMANDS}


def test_every_not_simulated_row_has_an_example():
    rows = [k for k in keywords.TABLE if not k.simulated]
    assert rows and all(k.example for k in rows)


@pytest.mark.parametrize(("command", "name"), TABLE_EXAMPLES)
async def test_a_table_row_is_not_simulated_and_named(pmac_api, command, name):
    r = await pmac_api.post("/controllers/p/terminal", json={"command": command})
    body = r.json()
    assert body["error"] == "ERR003", body
    assert body["not_simulated"] is True, body
    assert "does not simulate" in body["detail"]
    assert name.split()[0] in body["detail"], body


@pytest.mark.parametrize("command", [c for cs in LETTER_EXAMPLES.values() for c in cs])
async def test_a_letter_command_is_not_simulated(pmac_api, command):
    r = await pmac_api.post("/controllers/p/terminal", json={"command": command})
    body = r.json()
    assert body["error"] == "ERR003", body
    assert body["not_simulated"] is True, body


async def test_a_typo_stays_a_parse_error(pmac_api):
    r = await pmac_api.post("/controllers/p/terminal", json={"command": "&1 LSIT PLC 1"})
    assert r.json()["not_simulated"] is False
