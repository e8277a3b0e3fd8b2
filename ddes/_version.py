"""The version of ddes (bottom layer: anything may read it)."""

__version__ = "0.1.0"
