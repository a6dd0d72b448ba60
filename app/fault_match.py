"""The ``match`` of a command fault, run by a linear-time engine (RE2).

A fault's pattern is searched in every command line that reaches its controller — over the
unauthenticated PMAC and Trio TCP ports too — on the service's event loop. A backtracking
engine (Python's :mod:`re`) takes exponential time on patterns such as ``(a+)+$`` against a
few dozen characters, so every client would wait. RE2 (the ``google-re2`` binding) runs in time
linear in the command's length whatever the pattern, and refuses what it cannot do that way:
back-references (``\\1``), look-around (``(?=…)``, ``(?<!…)``), possessive or atomic groups.
Such a pattern is refused at ``POST /faults`` with 422 naming ``match`` (nothing is added).
Matching ignores case, as before. [INF] RE2's own syntax is the contract: it is close to
Python's for classes, anchors, alternation and counted repetition (a count of at most 1000).
"""

from __future__ import annotations

import re2

#: Most memory RE2 may use to compile one pattern (bytes); a larger automaton is refused.
MAX_PATTERN_MEMORY = 1 << 20


def _options() -> re2.Options:
    options = re2.Options()
    options.case_sensitive = False
    options.log_errors = False
    options.max_mem = MAX_PATTERN_MEMORY
    return options


class CommandPattern:
    """A compiled ``match``: :meth:`search` tells whether it occurs in a command line.

    Raises:
        ValueError: ``pattern`` is not a pattern RE2 can run in linear time (the reason named).
    """

    __slots__ = ("pattern", "_regexp")

    def __init__(self, pattern: str) -> None:
        try:
            self._regexp = re2.compile(pattern, _options())
        except re2.error as exc:
            reason = exc.args[0] if exc.args else exc
            if isinstance(reason, bytes):
                reason = reason.decode("utf-8", "replace")
            raise ValueError(f"not a pattern a linear-time matcher can run: {reason} "
                             f"(back-references and look-around are refused)") from None
        self.pattern = pattern

    def search(self, command: str) -> bool:
        return self._regexp.search(command) is not None


__all__ = ["MAX_PATTERN_MEMORY", "CommandPattern"]
