"""The MultiBots browser viewer: serve a replay or a live run (:class:`Viewer`). Its command
is ``multibots view`` (:mod:`multibots.cli.view`)."""

from multibots.viewer.server import LiveSource, ReplaySource, Viewer

__all__ = ["Viewer", "ReplaySource", "LiveSource"]
