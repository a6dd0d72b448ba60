"""Parsing PMAC program lines to statements, against bare ``re`` tokenising of the same lines.

The lines are what a streaming host sends (axis words with fractional values, move modes and
times, synchronous M writes, P-variable arithmetic, DWELL, CIRCLE with its vector), all
distinct so that no cache helps. The measured path is the one every line the card has never
seen takes: text -> tokens -> statements -> the compiled line (:func:`compile_line`, words
counted). The reference splits the same lines into tokens with one compiled regex and does
nothing else: the least any parser must do.

Run: ``.venv/bin/python bench/bench_parse.py [n_lines] [repeat]``; writes
``bench/results/parse.json``.
"""

from __future__ import annotations

import random
import re
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from motionsim.sim.pmac.buffers.program import compile_line  # noqa: E402

from bench.results import write  # noqa: E402

_BARE = re.compile(r"\s*(?:(\$[0-9A-Fa-f]+|\d*\.\d+|\d+)|([A-Za-z]+)|(==|->|[=+\-*/()]))")


def corpus(n: int, seed: int = 1) -> list[str]:
    rnd = random.Random(seed)
    shapes = (
        lambda: f"X{rnd.uniform(-500, 500):.4f} Y{rnd.uniform(-500, 500):.4f}",
        lambda: f"X{rnd.uniform(0, 99):.3f} Y{rnd.uniform(0, 99):.3f} Z{rnd.uniform(0, 9):.3f}",
        lambda: f"INC LINEAR TA{rnd.randint(1, 50)} TS0 TM{rnd.randint(2, 200)}",
        lambda: f"M{rnd.randint(1, 64)}=={rnd.randint(0, 1)}",
        lambda: f"P{rnd.randint(1, 999)}=P{rnd.randint(1, 999)}+{rnd.uniform(0, 9):.2f}",
        lambda: f"DWELL{rnd.randint(1, 500)}",
        lambda: (f"CIRCLE1 X{rnd.uniform(0, 9):.3f} Y{rnd.uniform(0, 9):.3f} "
                 f"I{rnd.uniform(-5, 5):.3f} J{rnd.uniform(-5, 5):.3f}"),
        lambda: f"F{rnd.randint(1, 900)} X{rnd.uniform(0, 9):.2f}",
    )
    return [rnd.choice(shapes)() for _ in range(n)]


def _rate(fn, lines: list[str]) -> float:
    t0 = time.perf_counter()
    for text in lines:
        fn(text)
    return len(lines) / (time.perf_counter() - t0)


def _tokens(text: str) -> list[tuple[str, str, str]]:
    return _BARE.findall(text)


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    lines = corpus(n)
    parsed, bare = [], []
    for _ in range(repeat):  # interleaved, best of each: the machine is shared
        bare.append(_rate(_tokens, lines))
        parsed.append(_rate(compile_line, lines))
    ratio = max(parsed) / max(bare)
    print(f"parse      : {max(parsed):>12,.0f} lines/s  (text -> statements -> compiled line)")
    print(f"bare regex : {max(bare):>12,.0f} lines/s  (one findall per line)")
    print(f"ratio      : {ratio:.3f}  (target >= 0.4); {n:,} distinct lines, best of {repeat}")
    path = write("parse", figures={"lines": n, "lines_per_s": max(parsed), "runs": parsed},
                 references={"bare_regex_lines_per_s": max(bare), "runs": bare},
                 ratios={"program_lines": ratio})
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
