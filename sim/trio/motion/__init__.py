"""Moves and axes: speed profiles, a move's path, MTYPE / NTYPE and the process buffer.

Speed profiles (``profile``), a move and its geometry (``moves``), MTYPE codes (``mtypes``),
an axis (``axis``), THE placement rule (``buffers``), moves linked to another axis
(``linked``, ``link_options``, ``link_run``) and the homing sequences (``datum``). Imports
``card`` and ``language`` (the shape of the linked-move commands) only.
"""
