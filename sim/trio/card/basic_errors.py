"""Runtime errors of a Trio BASIC process, and how the controller words them.

A runtime error stops the process that hit it (other processes keep running). The message
format is a template: the real controller's numbered error table and wording were not found in
any source reachable here (spec §9.9/§9.10, ``[BK]``), so the texts below follow the style
recalled from Trio manuals — ``%[Process 1:Line 3] - Divide by zero`` — and live only here.
"""

from __future__ import annotations

#: How an error line is printed on channel 0 (process, 1-based program line, message).
ERROR_LINE_FORMAT = "%[Process {process}:Line {line}] - {message}"

DIVIDE_BY_ZERO = "Divide by zero"
VR_RANGE = "VR index out of range: {index}"
TABLE_RANGE = "TABLE index out of range: {index}"
AXIS_RANGE = "Axis number out of range: {axis}"
PROCESS_RANGE = "Process number out of range: {process}"
BAD_VALUE = "Parameter out of range: {name}={value}"
NO_PROGRAM = "Program not found: {name}"
PROCESS_BUSY = "Process {process} is already running a program"
RETURN_WITHOUT_GOSUB = "RETURN without GOSUB"
GOSUB_DEPTH = "Stack overflow: GOSUB nested too deep"
NOT_AT_COMMAND_LINE = "Command not allowed at the command line"
LOCALS_AT_COMMAND_LINE = "Local variables cannot be used at the command line"
TOO_MANY_STEPS = "Command line statement ran too long"
ON_GOTO_RANGE = "ON..GOTO value {value} is outside 1..{count}"
ARRAY_RANGE = "Array index out of range: {name}({index})"
OUT_OF_WORD = ("Value out of range: {what} = {value:g} is beyond what the {bits}-bit number "
               "format holds (±{limit:g})")
EDGES_RANGE = ("Parameter out of range: {name}({value:g}) is {edges:g} encoder edges, beyond "
               "the ±{limit:g} of the {bits}-bit position counter")
NOT_FINITE = "Parameter out of range: {name} is not a finite number ({value})"
TRAP_AT_COMMAND_LINE = "ON BASICERROR cannot be used at the command line"

#: RUN_ERROR of a process: 0 = no error. Only 31 ("normal stop": the program was stopped,
#: the handler idiom of spec §11.3) is sourced; the controller's numbered table was not found
#: (spec §11.12), so every other run-time error reads :data:`RUN_ERROR_ANY` ``[INF]``.
RUN_ERROR_ANY = 1
RUN_ERROR_STOPPED = 31


class BasicError(Exception):
    """A runtime error raised while a BASIC statement executes; ``number`` is its RUN_ERROR."""

    def __init__(self, message: str, number: int = RUN_ERROR_ANY) -> None:
        super().__init__(message)
        self.message = message
        self.number = number


def error_line(process: int, line: int, message: str) -> str:
    """The controller's one-line error report for ``process`` at program ``line``."""
    return ERROR_LINE_FORMAT.format(process=process, line=line, message=message)


__all__ = ["BasicError", "error_line"]
