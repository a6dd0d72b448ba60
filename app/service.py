"""What a service runs at start: plugin modules, then the configured controllers.

With no ``controllers`` in the settings the embedded defaults are used: ``pmac`` (kind pmac)
and ``trio`` (kind trio) on the service's clock. A default whose kind is not installed is
skipped with a warning (the service still starts); a controller the user configured
explicitly with an unknown kind is an error.
"""

from __future__ import annotations

import importlib
import logging

from .kinds import broken_kinds, kinds
from .registry import Registry
from .settings import ControllerSpec, Settings

log = logging.getLogger("motionsim")

DEFAULT_CONTROLLERS = (
    ControllerSpec(id="pmac", kind="pmac"),
    ControllerSpec(id="trio", kind="trio"),
)


def import_plugins(settings: Settings) -> None:
    """Import each module in ``settings.plugins`` (they may call ``register_kind``)."""
    for name in settings.plugins:
        importlib.import_module(name)


def build_registry(settings: Settings) -> Registry:
    """A registry holding the controllers ``settings`` asks for (clocks not yet started)."""
    import_plugins(settings)
    registry = Registry(log_capacity=settings.log_capacity,
                        max_controllers=settings.max_controllers)
    specs = settings.controllers
    defaults = specs is None
    if specs is None:
        installed = kinds()
        specs = []
        for spec in DEFAULT_CONTROLLERS:
            if spec.kind in installed:
                specs.append(spec)
            else:
                why = broken_kinds().get(spec.kind, "not installed")
                msg = (f"controller kind {spec.kind!r}: {why}; "
                       f"default controller {spec.id!r} skipped")
                log.warning(msg)
    for spec in specs:
        clock = spec.clock or settings.clock
        try:
            registry.add(spec.kind, spec.id, clock=clock.mode, factor=clock.factor,
                         paused=clock.paused, config=spec.config,
                         reaction_s=clock.reaction_s)
        except Exception:
            if defaults:
                log.exception("default controller %r could not be created", spec.id)
                continue
            raise
    return registry


__all__ = ["DEFAULT_CONTROLLERS", "build_registry", "import_plugins"]
