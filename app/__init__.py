"""motionsim's composition layer: settings, the registry of controllers, clocks, the CLI."""

__version__ = "0.1.0"
