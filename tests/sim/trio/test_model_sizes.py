"""Each model's sizes (issue 32 item 4): processes, VR() and TABLE() per model, and the
``mc6xx`` model (MC664 / MC6N class) speaking the MC4xx / MC6xx language.

Sources: TJ1P-26 (VR(0)..VR(1023) on the MC2xx generation's twin), TJ2P-16 (TJ2, the MC4xx's
OEM twin: 64 000 VRs, 500 000 TABLE entries), TJ2H-39 / M206-184 (processes); the MC6xx
sizes are the host library's (TPCNET: VR 65 536, TABLE 512 000) ``[INF]``
(sim/trio/card/models.py).
"""

from __future__ import annotations

import pytest
from motionsim.sim import trio as trio_pkg
from motionsim.sim.errors import InvalidValue, NotFound

from tests.sim.trio.conftest import fields, make, run_to

SIZES = [  # model, processes, VR count, TABLE size
    ("series2", 14, 1024, 16384),
    ("mc2xx", 7, 1024, 16384),
    ("mc4xx", 22, 64_000, 500_000),
    ("mc6xx", 22, 65_536, 512_000),
]


@pytest.mark.parametrize(("model", "processes", "vrs", "table"), SIZES)
def test_each_model_has_its_processes_vr_and_table_sizes(model, processes, vrs, table):
    c = make(model=model)
    assert c.status()["processes"] == processes
    c.store_program("T", f"VR({vrs - 1}) = 7\nTABLE({table - 1}) = 8\nVR(0) = VR({vrs - 1}) + "
                         f"TABLE({table - 1})\n")
    c.run_program("T", processes)  # the highest process exists
    run_to(c, 0.01)
    assert "error" not in fields(c, "process", process=processes)[-1][1]
    assert (c.vr[0], c.get_variable(f"VR({vrs - 1})"), c.get_variable(f"TABLE({table - 1})")) \
        == (15.0, 7.0, 8.0)


@pytest.mark.parametrize(("model", "processes", "vrs", "table"), SIZES)
def test_one_past_each_size_is_out_of_range(model, processes, vrs, table):
    c = make(model=model)
    c.store_program("V", f"VR({vrs}) = 1\n")
    c.store_program("W", f"TABLE({table}) = 1\n")
    c.run_program("V", 1)
    c.run_program("W", 2)
    run_to(c, 0.01)
    assert f"VR index out of range: {vrs}" in fields(c, "process", process=1)[-1][1]["error"]
    assert f"TABLE index out of range: {table}" in \
        fields(c, "process", process=2)[-1][1]["error"]
    with pytest.raises(NotFound, match=rf"VR\({vrs}\) is out of range 0..{vrs - 1}"):
        c.get_variable(f"VR({vrs})")
    with pytest.raises(InvalidValue, match=f"process must be 1..{processes}"):
        c.run_program("V", processes + 1)


def test_the_mc4xx_sizes_real_programs_use_are_accepted():
    """Issue 32: ``VR(63999)`` and ``TABLE(499999)`` were refused on mc4xx."""
    c = make(model="mc4xx")
    c.store_program("T", "VR(63999) = 1\nTABLE(499999) = 2\n")
    c.run_program("T", 1)
    run_to(c, 0.01)
    assert (c.vr[63999], c.table[499999]) == (1.0, 2.0)


def test_the_config_still_sets_the_sizes_of_any_model():
    c = make(model="mc6xx", vr_count=100, table_size=50, processes=3)
    assert (len(c.vr), c.table_size, c.status()["processes"]) == (100, 50, 3)


def test_mc6xx_speaks_the_mc4_language_and_has_its_buffers():
    c = make(model="mc6xx")
    c.store_program("LIB", "FUNCTION twice(x AS INTEGER) AS INTEGER\n  RETURN x * 2\nENDFUNC\n")
    c.store_program("T", """\
DIM s AS INTEGER(2, 2) : DIM n AS INTEGER = 3
s(1, 1) = twice(n)
SELECT_CASE s(1, 1)
  CASE 6
    VR(0) = 1 << 4
END_CASE
VR(1) = VR(0).4
VR(2) = LIMIT_BUFFERED
VR(3) = CONTROL
""")
    c.run_program("T", 1)
    run_to(c, 0.01)
    assert "error" not in fields(c, "process", process=1)[-1][1]
    assert c.vr[:4] == [16.0, 1.0, 64.0, 664.0]


def test_the_models_are_re_exported_where_the_api_reads_them():
    assert trio_pkg.MODELS["mc6xx"].processes == 22
    assert set(trio_pkg.MODELS) == {"series2", "mc2xx", "mc4xx", "mc6xx"}


def test_an_unknown_model_is_refused_naming_the_known_ones():
    with pytest.raises(InvalidValue, match="series2, mc2xx, mc4xx, mc6xx") as err:
        make(model="mc7xx")
    assert err.value.details["field"] == "model"
