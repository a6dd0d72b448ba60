"""The Trio Motion Coordinator kind: MTYPE / NTYPE / process buffers and Trio BASIC.

In parts, each importing only the parts before it (``tests/app/test_layers.py`` checks it):

* ``card/`` — the card's own facts: parameter names, models, I/O, output channels, errors;
* ``language/`` — Trio BASIC text -> ``statements`` -> compiled operations (``parser``,
  ``compiler``, ``expressions``, the statement table ``commands``);
* ``motion/`` — speed profiles, moves, axes, THE placement rule (``buffers``), linked moves;
* ``run/`` — a running statement's ``context`` and the BASIC ``process``es;
* ``terminal`` (the command line) and ``controller`` (``TrioController``) on top.

The modules used to sit side by side here (``motionsim.sim.trio.parser`` ...): those names
stay importable, as the same module objects, for code written before the split
(:data:`MOVED`); new code imports the part (``motionsim.sim.trio.language.parser``).
"""

import importlib
import sys

from .card.io import CHANNELS, PATTERN_FIRST
from .card.models import MODELS
from .controller import TrioController

#: Old module name -> the part it lives in now.
MOVED: dict[str, str] = {
    **{m: "card" for m in ("axis_status", "basic_errors", "io", "models", "output", "parameters",
                           "scaling", "setup_commands", "system")},
    **{m: "language" for m in ("branches", "compiler", "constants", "declaration_parser",
                               "declarations", "expressions", "keywords", "lexer", "parser",
                               "scope", "statements", "strings")},
    **{m: "motion" for m in ("axis", "buffers", "datum", "link_options", "link_run", "linked",
                             "moves", "mtypes", "profile")},
    **{m: "run" for m in ("context", "process")},
}

for _old, _part in MOVED.items():
    sys.modules[f"{__name__}.{_old}"] = importlib.import_module(f"{__name__}.{_part}.{_old}")

__all__ = ["CHANNELS", "MODELS", "MOVED", "PATTERN_FIRST", "TrioController"]
