"""Compiled expression readers are shared between equal expressions (issue 32's compile time,
sim/trio/language/expressions.py ``_SHARED``): a reader holds nothing but what it reads, so
sharing must change nothing a program does. Pinned here: the example programs and an
expression-heavy program run in virtual time with sharing and with every reader made afresh
give the same event log, byte for byte, and the same variables."""

from __future__ import annotations

from pathlib import Path

import pytest
from motionsim.sim.trio.language import expressions

from tests.sim.trio.conftest import make, run_to

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "trio"

EXPRESSIONS = """\
DIM label AS STRING(20)
DIM n AS INTEGER = 3
a = 0
FOR i = 1 TO 12
  VR(10 + i) = VR(10 + i - 1) * 2 + i - 0.5
  a = a + VR(10 + i) / 4 - -1 + (i MOD 3) * -0.0
  VR(60 + i) = (i + 2) * (i - 2) + (i * 2) - (i / 2) + (i > 2) + (i < 2) + (i = 2) - -i
  IF VR(10 + i) > 100 AND NOT (i = 7) THEN VR(40 + i) = VR(10 + i).1 + (i << 2) + (64 >> n)
  TABLE(i) = TABLE(i - 1) + SPEED AXIS(i MOD 4) * 0 + ABS(-i) ^ 2
  label = "n" + STR(i, 0) + "n"
  PRINT label; " "; a[2]; " "; VR(10 + i)
NEXT i
VR(99) = a
"""


class _Nothing(dict):
    """A cache that never holds a reader: every expression gets its own."""

    def get(self, key, default=None):
        return default


def _run(text: str, model: str, until: float) -> tuple[str, list[float]]:
    c = make(model=model, axes=4)
    if model == "mc6xx":  # the library mc6_station.bas calls
        c.store_program("MC6_MACHINE", (EXAMPLES / "mc6_machine.bal").read_text(encoding="utf-8"))
    c.store_program("P", text)
    c.run_program("P", 1)
    run_to(c, until)
    return c.log.to_jsonl(), list(c.vr[:100])


PROGRAMS = [("EXPRESSIONS", EXPRESSIONS, "mc4xx", 1.0)] + [
    (p.stem, p.read_text(encoding="utf-8"), "mc6xx" if p.stem.startswith("mc") else "mc2xx",
     3.0)
    for p in sorted(EXAMPLES.glob("*.bas"))
    if p.stem not in ("check_me",)  # a program made to fail the check tool
]


@pytest.mark.parametrize(("name", "text", "model", "until"), PROGRAMS,
                         ids=[p[0] for p in PROGRAMS])
def test_shared_readers_run_as_readers_made_afresh(name, text, model, until, monkeypatch):
    shared = _run(text, model, until)
    monkeypatch.setattr(expressions, "_SHARED", _Nothing())
    fresh = _run(text, model, until)
    assert shared == fresh
    if name == "EXPRESSIONS":
        assert "error" not in shared[0].splitlines()[-1] and shared[1][99] != 0.0
