"""Controller kinds as plug-ins.

A kind is a :class:`motionsim.sim.controller.Controller` subclass registered under the entry-point
group ``motionsim.kinds`` (``pmac = "sim.pmac:PmacController"`` in ``pyproject.toml``), or at run
time with :func:`register_kind`. Adding a third kind touches neither ``api/`` nor this module.
"""

from __future__ import annotations

import logging
from importlib.metadata import entry_points

from ..sim.controller import Controller
from ..sim.errors import InvalidValue

_registered: dict[str, type[Controller]] = {}
#: Entry points that failed to load: kind -> why (a kind still being written is not fatal).
_broken: dict[str, str] = {}

log = logging.getLogger("motionsim.kinds")


def register_kind(cls: type[Controller], name: str | None = None) -> type[Controller]:
    """Make ``cls`` available as ``kind`` ``name`` (default ``cls.kind``); usable as a decorator."""
    _registered[name or cls.kind] = cls
    return cls


#: The entry-point kinds, loaded once a process: scanning the installed packages' metadata
#: took ~80 ms, on every controller created (``refresh`` scans again).
_loaded: dict[str, type[Controller]] | None = None


def kinds(refresh: bool = False) -> dict[str, type[Controller]]:
    """Every known kind: entry points first, then run-time registrations (which win)."""
    global _loaded
    if _loaded is None or refresh:
        _loaded = _load_entry_points()
    return {**_loaded, **_registered}


def _load_entry_points() -> dict[str, type[Controller]]:
    found: dict[str, type[Controller]] = {}
    for ep in entry_points(group="motionsim.kinds"):
        try:
            found[ep.name] = ep.load()
        except Exception as exc:  # an installed kind that cannot be imported is "not installed"
            why = f"{type(exc).__name__}: {exc}"
            if _broken.get(ep.name) != why:
                log.warning("controller kind %r (%s) cannot be loaded: %s", ep.name, ep.value, why)
            _broken[ep.name] = why
        else:
            _broken.pop(ep.name, None)
    return found


def broken_kinds() -> dict[str, str]:
    """Kinds whose entry point failed to load at the last :func:`kinds` call, and why."""
    return dict(_broken)


def kind_class(name: str) -> type[Controller]:
    """The controller class of kind ``name``; an unknown kind is a validation error."""
    known = kinds()
    try:
        return known[name]
    except KeyError:
        if name in _broken:
            raise InvalidValue(f"controller kind {name!r} cannot be loaded: {_broken[name]}",
                               field="kind") from None
        raise InvalidValue(
            f"unknown controller kind {name!r}; known kinds: {', '.join(sorted(known))}",
            field="kind",
        ) from None


__all__ = ["broken_kinds", "kind_class", "kinds", "register_kind"]
