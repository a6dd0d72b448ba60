"""The Turbo PMAC command language: text to typed statements.

The lexer and parser of on-line commands and buffered lines (``parser``), the
statements they build (``statements``, ``motor_statements``, ``plc_statements``),
compiled arithmetic (``expressions``), the streamed-line fast path (``fast_line``) and
the PLC rules on what a PLC line may hold (``plc_parser``: PLC lines are read by the same
parser, ``conditions`` the comparators). Nothing here runs a statement.
"""
