"""PMAC coordinate systems and their rotary buffers (API.md "PMAC resources")."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

from ..line_slices import MAX_BATCH_LINES
from .common import Int, int_in


class RotaryPublic(BaseModel):
    """A rotary program buffer. ``lines_ahead`` = lines stored but not yet calculated (``PR``),
    compared with I16 / I17 to drive ``breq``."""

    size_words: int
    used_words: int
    free_words: int
    lines_ahead: int
    breq: bool
    open: bool
    full: bool = Field(False, description="the rotary-buffer-full status bit (`??` word 2 bit "
                                          "16): set at I17 lines ahead, cleared below I16")


class ProgramPublic(BaseModel):
    """The CS's program: ``waiting`` = running but out of rotary lines."""

    state: Literal["idle", "running", "waiting", "stopped", "aborted"]
    line: int | None = Field(None, description="line number of the executing move, if any")
    error: Literal["run_time_error", "watchdog"] | None = Field(
        None, description="why the controller aborted the program itself: `run_time_error` = "
        "move calculation fell behind execution (TUM p339); `watchdog` = the watchdog tripped "
        "and killed the motors; cleared by the next run (or the reset)")
    feed_override: float | None = Field(
        None, description="the actual `%` feedrate override of the CS's time base, in percent "
        "(what `%` reports; slews to a new `%n` at Isx94, TSRM p191)")


class CoordPublic(BaseModel):
    cs: int
    program: ProgramPublic
    rotary: RotaryPublic | None


class RotaryIn(BaseModel):
    """``PUT .../rotary`` = ``&cs DEFINE ROT size_words``."""

    model_config = ConfigDict(extra="forbid", strict=True)

    size_words: Int = Field(gt=0, le=65_536)


class LinesIn(BaseModel):
    """A batch of program lines, stored atomically; ``first_seq`` numbers them."""

    model_config = ConfigDict(extra="forbid", strict=True)

    lines: list[Annotated[str, Field(json_schema_extra={"maxLength": 255})]] = Field(
        max_length=MAX_BATCH_LINES,
        description=f"program lines, e.g. ['X10 Y20', 'M1==1']; at most {MAX_BATCH_LINES} "
                    "per batch (422 naming `lines` above), each at most 255 characters")
    first_seq: Annotated[int_in(0), Field(  # type: ignore[valid-type]
        json_schema_extra={"maximum": 2**53 - 1})] | None = Field(
        None, description="the client's number of lines[0]: a resend of exactly the "
        "stored lines is acknowledged, a gap / different text / number beyond 2^53-1 is 409 "
        "`conflict` with `expected_seq` (API.md)")


class LinesAccepted(BaseModel):
    accepted: int = Field(description="lines of the batch acknowledged (now or earlier)")
    stored: int = Field(description="lines newly stored by this request")
    lines_ahead: int
    free_words: int
    breq: bool


__all__ = ["CoordPublic", "LinesAccepted", "LinesIn", "ProgramPublic", "RotaryIn",
           "RotaryPublic"]
