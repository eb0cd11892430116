"""Helpers shared by the viewer's tests (fixtures are in conftest.py)."""

from __future__ import annotations

import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import multibots

HERE = Path(__file__).resolve().parent
GROUP1 = [11, 8, 39, 28, 53, 1, 69, 42, 79, 6]


def paper(robots=3, goods=GROUP1, **kw):
    return multibots.Scenario.paper(robots=robots, goods=list(goods), **kw)


def chromium_exe() -> str:
    env = os.environ.get("MULTIBOTS_CHROMIUM")
    if env:
        return env
    return shutil.which("chromium") or "/usr/bin/chromium"


def open_viewer(pg, viewer, query: str = ""):
    pg.goto(viewer.url + query)
    pg.wait_for_function("() => window.mbViewer && window.mbViewer.ready && window.mbViewer.state().frame !== null")


def cli_command() -> list:
    """The `multibots` command line with the viewer's commands: the real one once the main
    cli registers them, else a minimal typer app that does (same register function)."""
    try:
        from multibots import cli as main_cli  # type: ignore[attr-defined]

        app = getattr(main_cli, "app", None)
        names = {c.name or (c.callback.__name__ if c.callback else "") for c in app.registered_commands} if app else set()
        if {"view", "render"} <= names and importlib.util.find_spec("multibots.__main__"):
            return [sys.executable, "-m", "multibots"]
    except Exception:
        pass
    return [sys.executable, str(HERE / "_cli.py")]


def run_cli(*args, timeout=180):
    return subprocess.run(cli_command() + [str(a) for a in args], capture_output=True, text=True,
                          timeout=timeout)
