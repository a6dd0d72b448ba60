"""The one error a bad scenario raises: what is wrong, which field, which line of which file."""

from __future__ import annotations

from typing import Any

from ...sim.errors import InvalidValue


def dotted(path: tuple[Any, ...] | list[Any]) -> str:
    """``("hosts", 0, "latency")`` -> ``"hosts[0].latency"``."""
    out = ""
    for part in path:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out


class ScenarioError(InvalidValue):
    """A scenario that cannot run; nothing was run.

    Args:
        message: what is wrong.
        file: the scenario file.
        line: 1-based line in ``file`` where the offending field starts.
        field: dotted path of the field (``hosts[0].latency.mean_ms``).
        errors: every problem found, each ``{"field", "line", "message"}``.
    """

    def __init__(
        self,
        message: str,
        *,
        file: str | None = None,
        line: int | None = None,
        field: str | None = None,
        errors: list[dict[str, Any]] | None = None,
    ) -> None:
        super().__init__(message, file=file, line=line, field=field, errors=errors)
        self.file = file
        self.line = line
        self.field = field
        self.errors = errors or [{"field": field, "line": line, "message": message}]

    def __str__(self) -> str:
        if len(self.errors) > 1:
            return "\n".join(_one(self.file, e) for e in self.errors)
        return _one(self.file, {"field": self.field, "line": self.line, "message": self.message})


def _one(file: str | None, e: dict[str, Any]) -> str:
    where = file or "<scenario>"
    if e.get("line"):
        where += f":{e['line']}"
    field = f" {e['field']}:" if e.get("field") else ""
    return f"{where}:{field} {e['message']}"


__all__ = ["ScenarioError", "dotted"]
