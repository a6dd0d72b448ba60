"""Trio BASIC: text to typed statements to compiled operations. Nothing here moves an axis.

Tokens (``lexer``), the typed statements (``statements``), the parser (``parser``,
``declaration_parser``), the TRM command index (``keywords``), constants (``constants``),
compiled expressions (``expressions``), strings (``strings``), names in scope (``scope``)
and the compiler (``compiler``, ``branches``, ``declarations``). Imports only ``card``.
"""
