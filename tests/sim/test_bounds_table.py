"""Every bound of ``sim/bounds.py`` at its edges: a value at each end is accepted (not the low
end of an open bound), one beyond is refused with ``InvalidValue`` naming the field, a
fraction is refused where whole numbers are required, and only real numbers pass.

The limits are those API.md states ("Every time and rate has bounds": ``factor``
0.001..10000, ``seconds`` / ``timeout_s`` 0..1e6 simulated s, Trio move arguments ±1e12, rates
≤ 1e12, 0 < rate), the Turbo SRM's (I8 0..255, I10 > 0, 24 bits) and the ``[INF]`` limits the
controller ``config`` description lists; the table below is written out by hand so that a
changed limit fails here.
"""

from __future__ import annotations

import math

import pytest
from motionsim.sim import bounds
from motionsim.sim.errors import InvalidValue

#: name, bound, low, high, low end open, whole numbers only
TABLE = [
    ("factor", bounds.CLOCK_FACTOR, 1e-3, 1e4, False, False),
    ("seconds", bounds.ADVANCE_SECONDS, 0, 1e6, False, False),
    ("timeout_s", bounds.TIMEOUT_SECONDS, 0, 1e6, False, False),
    ("servo_hz", bounds.PMAC_CONFIG["servo_hz"], 100, 100_000, False, False),
    ("background_cycles", bounds.PMAC_CONFIG["background_cycles"], 1, 100_000, False, True),
    ("i10", bounds.PMAC_CONFIG["i10"], 0, 8_388_607, True, True),
    ("i8", bounds.PMAC_CONFIG["i8"], 0, 255, False, True),
    ("cpu_us", bounds.PMAC_CPU_COST, 0, 10_000, False, False),
    ("servo_period_ms", bounds.TRIO_CONFIG["servo_period_ms"], 0.05, 10, False, False),
    ("axes", bounds.TRIO_CONFIG["axes"], 1, 64, False, True),
    ("processes", bounds.TRIO_CONFIG["processes"], 1, 32, False, True),
    ("statement_us", bounds.TRIO_CONFIG["statement_us"], 0, 100_000, True, False),
    ("vr_count", bounds.TRIO_CONFIG["vr_count"], 1, 65_536, False, True),
    ("table_size", bounds.TRIO_CONFIG["table_size"], 1, 4_000_000, False, True),
    ("ethercat_slaves", bounds.TRIO_CONFIG["ethercat_slaves"], 0, 256, False, True),
    ("speed", bounds.TRIO_RATE, 0, 1e12, True, False),
    ("distance", bounds.TRIO_DISTANCE, -1e12, 1e12, False, False),
]


def _refused(bound: bounds.Bound, value: object, field: str) -> None:
    with pytest.raises(InvalidValue) as exc:
        bound.check(value, field)
    assert exc.value.to_dict()["field"] == field


@pytest.mark.parametrize(("name", "bound", "low", "high", "low_open", "integer"), TABLE,
                         ids=[row[0] for row in TABLE])
def test_each_bound_accepts_its_range_and_refuses_beyond_it(name, bound, low, high, low_open,
                                                            integer):
    # the nearest numbers beyond each end (whole numbers: one beyond)
    below = low - 1 if integer else math.nextafter(low, -math.inf)
    above = high + 1 if integer else math.nextafter(high, math.inf)
    if low_open:
        _refused(bound, low, name)
        just_in = low + 1 if integer else math.nextafter(low, math.inf)
        assert bound.check(just_in, name) == just_in
    else:
        assert bound.check(low, name) == float(low)
    _refused(bound, below, name)
    assert bound.check(high, name) == float(high)
    _refused(bound, above, name)
    middle = low + 1.5 if low + 1.5 < high else (low + high) / 2
    if integer:
        _refused(bound, low + 1.5, name)
        assert bound.check(low + 1, name) == low + 1  # a whole float or int is fine
        assert bound.check(float(high), name) == float(high)
    else:
        assert bound.check(middle, name) == pytest.approx(middle)
    for bad in (True, False, "1", None, math.inf, -math.inf, math.nan):
        _refused(bound, bad, name)


def test_the_description_shows_an_open_low_end_and_whole_numbers():
    assert bounds.PMAC_CONFIG["i10"].describe() == "0 < x <= 8388607 1/8388608 ms"
    assert bounds.ADVANCE_SECONDS.describe() == "0 <= x <= 1000000 s simulated"
    assert bounds.TRIO_CONFIG["servo_period_ms"].describe() == "0.05 <= x <= 10 ms"


def test_finite_takes_any_finite_number_of_either_sign():
    for value in (-1e308, -1.0, 0, 2.5, 1e308):
        assert bounds.FINITE.check(value, "x") == float(value)
    for bad in (math.inf, -math.inf, math.nan, True, "1"):
        _refused(bounds.FINITE, bad, "x")
