"""Scenario text shared by the runner and sweep tests: one Turbo PMAC streaming 1 ms moves from
one BREQ-interrupt host (I8=0 puts the RTI on every servo cycle, so the moves run as written)."""

from __future__ import annotations

PMAC_1MS_MOVES = """\
controllers:
  pmac:
    kind: pmac
    config: {i8: 0, i16: 5, i17: 10}  # RTI every servo cycle: 1 ms moves
    rotary:
      - {cs: 1, size_words: 400}
"""


def breq_stream(head: str, *, latency: str, moves: int, host: str | None = None,
                tail: str = "") -> str:
    """``head`` (name, seed, duration), :data:`PMAC_1MS_MOVES`, then one ``breq_interrupt`` host
    (named ``host`` if given) feeding ``moves`` generated 1 ms two-axis moves, 10 lines per
    interrupt, then ``tail``."""
    first = f"  - name: {host}\n    type:" if host else "  - type:"
    return (
        head
        + PMAC_1MS_MOVES
        + "hosts:\n"
        + first + " breq_interrupt\n"
        + f"    latency: {latency}\n"
        + "    lines_per_interrupt: 10\n"
        + "    program:\n"
        + f"      generate: {{moves: {moves}, move_ms: 1, axes: 2}}\n"
        + tail
    )
