"""Factory I-variable defaults and hex reporting against the dump dls-pmacanalyse ships.

The dump (``factorySettings_pmac.pmc`` in the installed ``dls_pmacanalyse`` package, spec
pmac.md §11.6) holds I0..I8191 of a Turbo PMAC2 reset with ``$$$***``, taken with I9 = 2.
Every value must match ours except the documented manual and card overrides; every value
the dump writes with ``$`` must be one we report in hex with I9 bit 1 set, and no other.
"""

from __future__ import annotations

import re
from importlib.resources import files

import pytest
from motionsim.sim.pmac.card.factory import (
    CARD_OVERRIDES,
    FACTORY,
    HEX_IVARS,
    MANUAL_OVERRIDES,
)
from motionsim.sim.pmac.card.variables import format_ivar

_LINE = re.compile(r"^;?\s*I(\d+)\s*=\s*(\S+)\s*$", re.IGNORECASE)


def _dump() -> dict[int, str]:
    text = (files("dls_pmacanalyse") / "factorySettings_pmac.pmc").read_text()
    out: dict[int, str] = {}
    for line in text.splitlines():
        m = _LINE.match(line.strip())
        if m and int(m.group(1)) not in out:  # the I-variable part comes first
            out[int(m.group(1))] = m.group(2)
    return out


@pytest.fixture(scope="module")
def dump() -> dict[int, str]:
    d = _dump()
    assert sorted(d) == list(range(8192))
    return d


def _value(text: str) -> float:
    return float(int(text[1:], 16)) if text.startswith("$") else float(text)


def test_every_factory_value_matches_the_dump_except_documented_overrides(dump):
    overrides = MANUAL_OVERRIDES | CARD_OVERRIDES
    wrong = {
        n: (text, FACTORY[n])
        for n, text in dump.items()
        if n not in overrides and _value(text) != FACTORY[n]
    }
    assert wrong == {}


def test_overrides_are_real_departures_from_the_dump(dump):
    """An override that the dump already agrees with would be a stale exception."""
    for n, (value, _source) in (MANUAL_OVERRIDES | CARD_OVERRIDES).items():
        assert FACTORY[n] == value
        if n not in (4909,) and not (5111 <= n <= 6612 and n % 100 in (11, 12)):
            assert _value(dump[n]) != value, n


def test_manual_wins_where_dump_and_srm_disagree():
    """Spec §11.6: I5 (TSRM p39), I17 (TSRM p46), I64 (TSRM p67), Isx98 (TSRM p193)."""
    assert (FACTORY[5], FACTORY[17], FACTORY[64]) == (1, 10, 0)
    assert all(FACTORY[5000 + 100 * cs + 98] == 1000 for cs in range(1, 17))


def test_the_hex_reported_set_is_what_the_dump_wrote_with_a_dollar(dump):
    dollar = {n for n, text in dump.items() if text.startswith("$")}
    # MACRO ICs 1-3 (I6855.. etc.) are [INF] same offsets as IC 0; the dump left them 0.
    inferred = {6800 + 50 * ic + nn for ic in (1, 2, 3) for nn in (5, 6, 40, 41)}
    assert HEX_IVARS - inferred == dollar


def test_address_type_values_are_formatted_as_the_dump_does(dump):
    for n in (20, 124, 125, 5193, 8000, 8001, 1702, 5049, 116, 5199):
        ours = format_ivar(n, FACTORY[n], 2)
        if n in CARD_OVERRIDES or n in MANUAL_OVERRIDES:
            continue
        assert ours == dump[n], n
    assert format_ivar(20, FACTORY[20], 2) == "$0"
    assert format_ivar(124, FACTORY[124], 0) == str(0x40001)  # I9 bit 1 clear: decimal
