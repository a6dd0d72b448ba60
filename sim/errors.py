"""One error tree for the simulation core.

Every error the core raises is a :class:`MotionSimError` with a stable, snake_case ``code``
class attribute. ``api/errors.py`` maps ``code`` to an HTTP status in one table; the sim core
never knows about HTTP. Where the real controller would answer ``ERRnnn`` the error carries
``pmac_error`` so the terminal and the REST body can both report it.
"""

from __future__ import annotations

from typing import Any, ClassVar


class MotionSimError(Exception):
    """Root of every error raised by the simulation core.

    Args:
        message: what went wrong, for a person.
        pmac_error: the controller's own answer (``"ERR006"``) where it has one.
        **details: extra JSON-able fields for the error body (``index``, ``line``, ``column``,
            ``text``, ``field`` ...). ``None`` values are dropped.
    """

    code: ClassVar[str] = "error"

    def __init__(self, message: str, *, pmac_error: str | None = None, **details: Any) -> None:
        super().__init__(message)
        self.message = message
        self.pmac_error = pmac_error
        self.details = {k: v for k, v in details.items() if v is not None}

    def to_dict(self) -> dict[str, Any]:
        """The JSON error body: ``{"code", "message", "pmac_error"?, ...details}``."""
        body: dict[str, Any] = {"code": self.code, "message": self.message}
        if self.pmac_error is not None:
            body["pmac_error"] = self.pmac_error
        body.update(self.details)
        return body


class NotFound(MotionSimError):
    """An unknown controller, coordinate system, axis, program, variable or process."""

    code = "not_found"


class BufferFull(MotionSimError):
    """A batch does not fit in a rotary buffer or a process buffer; nothing of it was stored."""

    code = "buffer_full"


class Conflict(MotionSimError):
    """The controller's state forbids the request (the controller's ERR code, where it has one)."""

    code = "conflict"


class InvalidValue(MotionSimError):
    """A field has a value the controller cannot take; ``field`` names it."""

    code = "validation_error"


class ParseError(MotionSimError):
    """Program text that does not parse; nothing was changed.

    Args:
        message: what is wrong.
        line: 1-based line number in a program text.
        column: 1-based column of the offending character.
        index: 0-based position of the line in a batch of lines.
        text: the offending line.
    """

    code = "parse_error"

    def __init__(
        self,
        message: str,
        *,
        line: int | None = None,
        column: int | None = None,
        index: int | None = None,
        text: str | None = None,
        pmac_error: str | None = None,
        **details: Any,
    ) -> None:
        super().__init__(
            message,
            pmac_error=pmac_error,
            index=index,
            line=line,
            column=column,
            text=text,
            **details,
        )
        self.line = line
        self.column = column
        self.index = index
        self.text = text

    def at(self, *, index: int | None = None, line: int | None = None) -> ParseError:
        """A copy of this error placed at a batch index / program line."""
        return ParseError(
            self.message,
            line=line if line is not None else self.line,
            column=self.column,
            index=index if index is not None else self.index,
            text=self.text,
            pmac_error=self.pmac_error,
        )


class NotSimulated(MotionSimError):
    """A valid controller command that motionsim does not simulate (not a typo)."""

    code = "not_simulated"


class Halted(MotionSimError):
    """The controller does not answer: a PMAC whose watchdog tripped, until it is reset."""

    code = "watchdog"


__all__ = [
    "BufferFull",
    "Conflict",
    "Halted",
    "InvalidValue",
    "MotionSimError",
    "NotFound",
    "NotSimulated",
    "ParseError",
]
