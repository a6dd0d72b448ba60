"""Compiling the multi-way branches and the error trap: ``ON expr GOSUB / GOTO`` and
``ON BASICERROR GOTO label``.

* ``ON expr GOSUB l1, l2, ...``: the integer part of ``expr`` picks the label (1 -> the first);
  below 1 or above the number of labels no jump happens and the next statement runs
  (TJ2P5-138);
* ``ON expr GOTO l1, l2, ...``: the same pick; out of range is a run-time error (TJ2P5-138);
* ``ON BASICERROR GOTO label`` (TRM p. 8-118, spec §11.3): when it has run, a run-time error
  of this process — and a ``STOP "prog"`` of it from another program or the command line,
  with RUN_ERROR 31 (spec §11.3 ``[INF]``) — continues at ``label`` with RUN_ERROR and
  ERROR_LINE set (:mod:`motionsim.sim.trio.run.process`). It is a compile error without its label.

A mixin of :class:`motionsim.sim.trio.language.compiler._Compiler` (``patches``, ``placeholder``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..card.basic_errors import GOSUB_DEPTH, ON_GOTO_RANGE, BasicError
from . import statements as s

Op = Callable[[Any], Any]

#: GOSUB nesting the interpreter allows before a stack overflow error (``[BK]``).
GOSUB_LIMIT = 64


class Branches:
    """ON ... GOSUB / GOTO and ON BASICERROR GOTO."""

    patches: list[tuple[int, tuple[str, ...], s.Stmt, Callable[[list[int]], Op]]]
    placeholder: Callable[..., int]
    num: Callable[[s.Expr], Callable[[Any], Any]]

    def st_OnError(self, st: s.OnError) -> None:
        self.patches.append((self.placeholder(st), (st.label,), st, _trap))

    def st_OnBranch(self, st: s.OnBranch) -> None:
        value = self.num(st.value)
        pc = self.placeholder(st)
        build = (lambda t: _on_gosub(value, t, pc + 1)) if st.gosub else (
            lambda t: _on_goto(value, t))
        self.patches.append((pc, st.labels, st, build))


def _trap(targets: list[int]) -> Op:
    target = targets[0]
    return lambda c: c.set_trap(target)


def _on_goto(value: Callable[[Any], Any], targets: list[int]) -> Op:
    n = len(targets)

    def op(c: Any) -> int:
        v = value(c)
        k = int(v)
        if not 1 <= k <= n:
            raise BasicError(ON_GOTO_RANGE.format(value=f"{v:g}", count=n))
        return targets[k - 1]

    return op


def _on_gosub(value: Callable[[Any], Any], targets: list[int], ret: int) -> Op:
    n = len(targets)

    def op(c: Any) -> int | None:
        k = int(value(c))
        if not 1 <= k <= n:
            return None
        if len(c.gosub_stack) >= GOSUB_LIMIT:
            raise BasicError(GOSUB_DEPTH)
        c.gosub_stack.append(ret)
        return targets[k - 1]

    return op


__all__ = ["GOSUB_LIMIT", "Branches"]
