"""Controller kinds as plug-ins.

A kind is a :class:`sim.controller.Controller` subclass registered under the entry-point group
``motionsim.kinds`` (``pmac = "sim.pmac:PmacController"`` in ``pyproject.toml``), or at run time
with :func:`register_kind`. Adding a third kind touches neither ``api/`` nor this module.
"""

from __future__ import annotations

from importlib.metadata import entry_points

from sim.controller import Controller
from sim.errors import InvalidValue

_registered: dict[str, type[Controller]] = {}


def register_kind(cls: type[Controller], name: str | None = None) -> type[Controller]:
    """Make ``cls`` available as ``kind`` ``name`` (default ``cls.kind``); usable as a decorator."""
    _registered[name or cls.kind] = cls
    return cls


def kinds() -> dict[str, type[Controller]]:
    """Every known kind: entry points first, then run-time registrations (which win)."""
    found: dict[str, type[Controller]] = {}
    for ep in entry_points(group="motionsim.kinds"):
        found[ep.name] = ep.load()
    found.update(_registered)
    return found


def kind_class(name: str) -> type[Controller]:
    """The controller class of kind ``name``; an unknown kind is a validation error."""
    known = kinds()
    try:
        return known[name]
    except KeyError:
        raise InvalidValue(
            f"unknown controller kind {name!r}; known kinds: {', '.join(sorted(known))}",
            field="kind",
        ) from None


__all__ = ["kind_class", "kinds", "register_kind"]
