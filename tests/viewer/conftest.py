"""Fixtures for the viewer's tests: real engine replays, servers on 127.0.0.1, one Chromium."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import multibots
from multibots.render import CHROMIUM_ARGS

HERE = Path(__file__).resolve().parent
GROUP1 = [11, 8, 39, 28, 53, 1, 69, 42, 79, 6]


def paper(robots=3, goods=GROUP1, **kw):
    return multibots.Scenario.paper(robots=robots, goods=list(goods), **kw)


@pytest.fixture(scope="session")
def paper_run(tmp_path_factory):
    """The paper's group 1 with 3 robots, recorded: (path, Result)."""
    path = tmp_path_factory.mktemp("replays") / "group1-3.mbr"
    result = multibots.simulate(paper(3), record=str(path))
    assert path.is_file()
    return path, result


@pytest.fixture(scope="session")
def small_run(tmp_path_factory):
    """Two robots, three goods: a short replay for export tests."""
    path = tmp_path_factory.mktemp("replays") / "small.mbr"
    result = multibots.simulate(paper(2, [11, 8, 39]), record=str(path))
    return path, result


@pytest.fixture()
def replay_viewer(paper_run):
    from multibots.viewer import Viewer

    v = Viewer.for_replay(str(paper_run[0]))  # default host: 127.0.0.1
    v.start()
    try:
        yield v
    finally:
        v.close()


@pytest.fixture()
def live_viewer():
    from multibots.viewer import Viewer

    sim = multibots.Simulation(paper(3))
    v = Viewer.for_simulation(sim, name="group 1, 3 robots", speed=1.0)
    v.start()
    try:
        yield v
    finally:
        v.close()


def chromium_exe() -> str:
    env = os.environ.get("MULTIBOTS_CHROMIUM")
    if env:
        return env
    return shutil.which("chromium") or "/usr/bin/chromium"


@pytest.fixture(scope="session")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=chromium_exe(), args=CHROMIUM_ARGS)
        try:
            yield b
        finally:
            b.close()


@pytest.fixture()
def page(browser):
    ctx = browser.new_context(viewport={"width": 1280, "height": 800}, device_scale_factor=1)
    pg = ctx.new_page()
    pg.set_default_timeout(60_000)
    errors = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.page_errors = errors  # type: ignore[attr-defined]
    try:
        yield pg
    finally:
        ctx.close()
    assert not errors, f"errors on the page: {errors}"


def open_viewer(pg, viewer, query: str = ""):
    pg.goto(viewer.url + query)
    pg.wait_for_function("() => window.mbViewer && window.mbViewer.ready && window.mbViewer.state().frame !== null")


def cli_command() -> list:
    """The `multibots` command line with the viewer's commands: the real one once the lead's
    cli registers them, else a minimal typer app that does (same register function)."""
    try:
        from multibots import cli as main_cli  # type: ignore[attr-defined]

        app = getattr(main_cli, "app", None)
        names = {c.name or (c.callback.__name__ if c.callback else "") for c in app.registered_commands} if app else set()
        import importlib.util

        if {"view", "render"} <= names and importlib.util.find_spec("multibots.__main__"):
            return [sys.executable, "-m", "multibots"]
    except Exception:
        pass
    return [sys.executable, str(HERE / "_cli.py")]


def run_cli(*args, timeout=180):
    return subprocess.run(cli_command() + [str(a) for a in args], capture_output=True, text=True,
                          timeout=timeout)
