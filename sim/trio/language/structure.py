"""Compiling ``SELECT_CASE`` / ``CASE`` / ``CASE ELSE`` / ``END_CASE`` and ``EXIT_LOOP``
(MC4xx / MC6xx language, issue 32; the MC4 help pages were not reachable, the rules are
``[BK]`` / ``[INF]``):

* ``SELECT_CASE v`` evaluates ``v`` once; each ``CASE`` line, in order, tests it against its
  choices — a value (equal as ``=`` compares: within 1.19e-6 for numbers, exactly for strings)
  or a range ``lo TO hi`` (``lo <= v <= hi``) — and the first that matches runs its branch up
  to the next CASE, then goes on after ``END_CASE``; ``CASE ELSE`` (last) runs when none did;
  none matching and no CASE ELSE: nothing runs. Only CASE lines may follow SELECT_CASE; a
  CASE after CASE ELSE, a CASE outside SELECT_CASE and a SELECT_CASE left open are compile
  errors. Each CASE line tested costs one statement's time; the jump from the end of a branch
  to END_CASE costs none.
* ``EXIT_LOOP`` leaves the innermost ``FOR`` / ``WHILE`` / ``REPEAT`` loop it is in: the
  program goes on after that loop's NEXT / WEND / UNTIL. Outside a loop it is a compile error.

A mixin of :class:`motionsim.sim.trio.language.compiler._Compiler` (``blocks``, ``emit``,
``placeholder``, ``set_op``, ``error``).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from . import statements as s
from .expressions import FUZZ, compile_expr, kind_of

#: The blocks EXIT_LOOP leaves.
LOOPS = ("FOR", "WHILE", "REPEAT")


class Structure:
    """``st_SelectCase``, ``st_Case``, ``st_EndCase``, ``st_ExitLoop`` and the loop exits."""

    blocks: list[tuple[str, s.Stmt, dict[str, Any]]]
    ops: list[Any]
    scope: Any
    emit: Callable[..., int]
    placeholder: Callable[..., int]
    set_op: Callable[[int, Any], None]
    error: Callable[..., Any]

    def st_SelectCase(self, st: s.SelectCase) -> None:
        value = compile_expr(st.value, self.scope)
        info: dict[str, Any] = {"kind": kind_of(st.value, self.scope), "test": None,
                                "ends": [], "else": False, "cases": 0}
        key = len(self.ops)
        info["key"] = key

        def op(c: Any) -> None:
            c.selected[key] = value(c)

        self.emit(op, st)
        self.blocks.append(("SELECT", st, info))

    def _select(self, st: s.Stmt, word: str) -> dict[str, Any]:
        if not self.blocks or self.blocks[-1][0] != "SELECT":
            raise self.error(st, f"{word} without SELECT_CASE")
        return self.blocks[-1][2]

    def _end_branch(self, st: s.Stmt, info: dict[str, Any]) -> None:
        """The branch before a CASE / END_CASE ends: its jump to END_CASE, and the failed
        test of the CASE before goes on here."""
        if info["cases"]:
            info["ends"].append(self.placeholder(st, cost=0))
        if info["test"] is not None:
            pc, matches, key = info["test"]
            self.set_op(pc, _case_test(matches, key, len(self.ops)))
            info["test"] = None

    def st_Case(self, st: s.Case) -> None:
        info = self._select(st, "CASE ELSE" if st.is_else else "CASE")
        if info["else"]:
            raise self.error(st, "CASE after CASE ELSE (CASE ELSE is the last branch)")
        self._end_branch(st, info)
        info["cases"] += 1
        if st.is_else:
            info["else"] = True
            return
        tests = []
        for low, high in st.choices:
            for e in (low, high):
                if e is not None and kind_of(e, self.scope) != info["kind"]:
                    want = "a string" if info["kind"] == "str" else "a number"
                    raise self.error(st, f"type mismatch: the SELECT_CASE value is {want}, "
                                         "so is every CASE value")
            tests.append((compile_expr(low, self.scope),
                          compile_expr(high, self.scope) if high is not None else None))
        info["test"] = (self.placeholder(st), _matcher(tests, info["kind"] == "str"),
                        info["key"])

    def st_EndCase(self, st: s.EndCase) -> None:
        info = self._select(st, "END_CASE")
        self.blocks.pop()
        self._end_branch(st, info)
        end = len(self.ops)
        for pc in info["ends"]:
            self.set_op(pc, _to(end))

    def before_in_select(self, st: s.Stmt) -> None:
        """Only CASE lines (or END_CASE) may follow SELECT_CASE."""
        if (self.blocks and self.blocks[-1][0] == "SELECT" and not self.blocks[-1][2]["cases"]
                and not isinstance(st, (s.Case, s.EndCase))):
            raise self.error(st, "only a CASE line may follow SELECT_CASE")

    def st_ExitLoop(self, st: s.ExitLoop) -> None:
        for kind, _st, info in reversed(self.blocks):
            if kind in LOOPS:
                info.setdefault("exits", []).append(self.placeholder(st))
                return
        raise self.error(st, "EXIT_LOOP outside a loop (FOR, WHILE or REPEAT)")

    def close_exits(self, info: dict[str, Any], after: int) -> None:
        """A loop closed: its EXIT_LOOPs go on at ``after``, the first operation past it."""
        for pc in info.get("exits", ()):
            self.set_op(pc, _to(after))


def _to(target: int) -> Callable[[Any], int]:
    return lambda c: target


def _matcher(tests: list[tuple[Any, Any]], strings: bool) -> Callable[[Any, Any], bool]:
    def matches(c: Any, v: Any) -> bool:
        for low, high in tests:
            lo = low(c)
            if high is None:
                if (v == lo) if strings else abs(v - lo) < FUZZ:
                    return True
            else:
                hi = high(c)
                if strings and lo <= v <= hi:
                    return True
                if not strings and lo - FUZZ < v < hi + FUZZ:
                    return True
        return False

    return matches


def _case_test(matches: Callable[[Any, Any], bool], key: int, if_not: int
               ) -> Callable[[Any], int | None]:
    return lambda c: None if matches(c, c.selected[key]) else if_not


__all__ = ["LOOPS", "Structure"]
