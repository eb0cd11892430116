"""The MultiBots browser viewer: serve a replay or a live run (``Viewer``), and its CLI
commands (``viewer.cli.register``)."""

from .server import Viewer, ReplaySource, LiveSource

__all__ = ["Viewer", "ReplaySource", "LiveSource"]
