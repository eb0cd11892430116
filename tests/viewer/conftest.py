"""Fixtures for the viewer's tests: servers on 127.0.0.1 (over the replays of tests/conftest.py), one
Chromium."""

from __future__ import annotations

import pytest

import multibots
from multibots.render import CHROMIUM_ARGS

from viewer_helpers import chromium_exe, paper


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
    try:
        yield pg
    finally:
        ctx.close()
    assert not errors, f"errors on the page: {errors}"
