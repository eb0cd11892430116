"""Helpers shared by the viewer's tests (fixtures are in conftest.py)."""

from __future__ import annotations

import os
import shutil

import multibots

GROUP1 = list(multibots.PAPER_TASKS[1])


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
