"""The Trio Motion Coordinator kind: MTYPE / NTYPE / process buffers and Trio BASIC.

Modules, one idea each: ``lexer`` / ``parser`` (text -> ``statements``), ``compiler``
(statements -> operations), ``expressions`` (closures, number format), ``profile`` (speed
profiles), ``moves`` (a move and its path), ``axis`` (parameters and position), ``buffers``
(THE placement rule), ``process`` (BASIC processes), ``terminal`` (the command line),
``controller`` (``TrioController``).
"""

from motionsim.sim.trio.controller import TrioController

__all__ = ["TrioController"]
