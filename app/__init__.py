"""motionsim's composition layer: settings, the registry of controllers, clocks, the CLI."""

from motionsim import __version__

__all__ = ["__version__"]
