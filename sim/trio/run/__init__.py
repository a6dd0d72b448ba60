"""Running BASIC: what a statement sees (``context``) and one process per program (``process``).

Imports ``card``, ``language`` and ``motion``; ``controller`` and ``terminal`` (the command
line) sit above it at the top of sim/trio.
"""
