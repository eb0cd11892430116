"""The viewer page in a real browser (Debian's chromium through Playwright)."""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
from PIL import Image

import multibots
from multibots.replay import STATE_NAMES, Replay

from viewer_helpers import open_viewer, paper

RGB = {
    "blue": (31, 119, 180), "red": (214, 39, 40), "green": (44, 160, 44), "grey": (140, 140, 140),
    "cell_full": (214, 39, 40), "cell_empty": (17, 17, 17),
}
STATE_COLOUR = {0: "green", 1: "blue", 2: "blue", 3: "red", 4: "red", 5: "green", 6: "green", 7: "green",
                8: "green", 9: "grey", 10: "green"}


def close_to(actual, expected, tol=3):
    return all(abs(int(a) - int(b)) <= tol for a, b in zip(actual[:3], expected))


def text(pg, sel):
    return pg.locator(sel).inner_text().strip()


def test_replay_played_to_the_end_shows_the_engines_indicators(page, replay_viewer, paper_run):
    _, result = paper_run
    open_viewer(page, replay_viewer)
    assert text(page, "#c-T") == "\u2014"  # not done yet
    page.select_option("#speed", "64")
    page.click("#btn-play")
    page.wait_for_function("() => { const s = window.mbViewer.state(); return s.frame === s.last && !s.playing; }",
                           timeout=120_000)
    assert text(page, "#c-T") == str(result.T)
    assert text(page, "#c-S") == str(result.S)
    assert text(page, "#c-C") == str(result.C)
    assert text(page, "#c-delivered") == "10 / 10"
    assert text(page, "#c-step") == f"{result.steps} / {result.steps}"
    st = page.evaluate("() => window.mbViewer.state()")
    assert (st["T"], st["S"], st["C"], st["delivered"]) == (result.T, result.S, result.C, 10)


def _pick_frame(rp):
    """A frame where robot 0 drives inside the warehouse, away from the others."""
    for f in range(60, rp.frames, 7):
        fr = rp.frame(f)
        x, y = float(fr["x"][0]), float(fr["y"][0])
        d = np.hypot(fr["x"] - x, fr["y"] - y)
        d[0] = np.inf
        if fr["state"][0] in (1, 3) and 30 < y < 520 and d.min() > 60:
            return f
    raise AssertionError("no suitable frame")


def test_clicking_a_robot_opens_its_panel(page, replay_viewer, paper_run):
    with Replay(paper_run[0]) as rp:
        f = _pick_frame(rp)
        fr = rp.frame(f)
        st = rp.state_at(f)
    open_viewer(page, replay_viewer)
    assert page.evaluate(f"() => window.mbViewer.seek({f})") == f
    pt = page.evaluate("() => { const r = window.mbViewer.robot(0); return window.mbViewer.worldToClient(r.x, r.y); }")
    assert page.locator("#panel").is_hidden()
    page.mouse.click(pt["x"], pt["y"])
    page.wait_for_function(f"() => window.mbViewer.state().panelFrame === {f}")
    assert page.locator("#panel").is_visible()
    assert text(page, "#p-title") == "robot 0"
    assert text(page, "#p-state").startswith(STATE_NAMES[int(fr["state"][0])])
    task = int(st["task"][0])
    assert text(page, "#p-task") == (str(task) if task >= 0 else "\u2014")
    assert text(page, "#p-S") == str(int(st["robot_S"][0]))
    assert text(page, "#p-C") == str(int(st["robot_C"][0]))
    assert text(page, "#p-energy").startswith(f"{float(fr['energy'][0]):.3f}")
    assert page.evaluate("() => window.mbViewer.state().routePoints") >= 2
    page.click("#p-close")
    assert page.locator("#panel").is_hidden()


def test_pixels_at_a_robot_and_at_cells(page, replay_viewer, paper_run):
    with Replay(paper_run[0]) as rp:
        f = _pick_frame(rp)
        fr = rp.frame(f)
        cells = rp.cells_at(f)
        layout = rp.layout
    open_viewer(page, replay_viewer)
    page.evaluate(f"() => window.mbViewer.seek({f})")
    shot = Image.open(io.BytesIO(page.screenshot())).convert("RGB")

    def at(wx, wy):
        p = page.evaluate(f"() => window.mbViewer.worldToClient({wx}, {wy})")
        return shot.getpixel((int(math.floor(p["x"])), int(math.floor(p["y"]))))

    # a robot: half a radius beside its centre, across its heading line
    h = float(fr["heading"][0])
    r = 12.5
    x = float(fr["x"][0]) - math.sin(h) * r * 0.5
    y = float(fr["y"][0]) + math.cos(h) * r * 0.5
    want = RGB[STATE_COLOUR[int(fr["state"][0])]]
    assert close_to(at(x, y), want), (at(x, y), want)
    # a cell with goods and an empty one, near their top-left corners (away from the id text)
    full = next(c for c in layout["cells"] if cells[c["id"]])
    empty = next(c for c in layout["cells"] if not cells[c["id"]])
    assert close_to(at(full["x"] + 7, full["y"] + 7), RGB["cell_full"])
    assert close_to(at(empty["x"] + 7, empty["y"] + 7), RGB["cell_empty"])
    # the page background between the warehouse and the top banner is not a robot colour
    assert not close_to(at(400, -3), RGB["blue"])


def test_live_mode_streams_pauses_and_resumes(page, live_viewer):
    runner = live_viewer.source.runner
    expect = multibots.simulate(paper(3))
    open_viewer(page, live_viewer)
    page.wait_for_function("() => window.mbViewer.state().frame > 5")  # it streams
    assert text(page, "#mode").lower() == "live"
    page.click("#btn-play")  # playing: the button pauses
    page.wait_for_function("() => window.mbViewer.state().paused")
    with runner.lock:
        t1 = runner.sim.t
    page.wait_for_function(f"() => window.mbViewer.state().frame === {t1}")
    page.click("#btn-step")
    page.wait_for_function(f"() => window.mbViewer.state().frame === {t1 + 1}")
    with runner.lock:
        assert runner.sim.t == t1 + 1  # paused: exactly one step was taken
    page.select_option("#speed", "64")
    page.wait_for_function("() => window.mbViewer.state().speed === 64")
    page.click("#btn-play")  # resume
    page.wait_for_function(f"() => window.mbViewer.state().frame > {t1 + 1}")
    page.wait_for_function("() => window.mbViewer.state().done", timeout=120_000)
    assert text(page, "#c-T") == str(expect.T)
    assert text(page, "#c-S") == str(expect.S)
    assert text(page, "#c-C") == str(expect.C)
    assert text(page, "#c-delivered") == "10 / 10"


def test_export_has_the_expected_frames_and_colours(small_run, tmp_path):
    from multibots.render import render

    path, result = small_run
    out = tmp_path / "clip.gif"
    info = render(path, out, fps=20, start=0, end=40, every=2, progress=False)
    assert info["frames"] == 21
    with Image.open(out) as im:
        assert im.n_frames == 21
        assert im.size == (info["width"], info["height"])
        im.seek(20)  # replay frame 40
        frame = im.convert("RGB")
    with Replay(path) as rp:
        fr = rp.frame(40)
        cells = rp.cells_at(40)
        layout = rp.layout
    ox, oy, s = info["origin"][0], info["origin"][1], info["scale"]

    def at(wx, wy):
        return frame.getpixel((int(math.floor(ox + wx * s)), int(math.floor(oy + wy * s))))

    for i in range(rp.robots):
        h = float(fr["heading"][i])
        x = float(fr["x"][i]) - math.sin(h) * 6.25
        y = float(fr["y"][i]) + math.cos(h) * 6.25
        assert close_to(at(x, y), RGB[STATE_COLOUR[int(fr["state"][i])]], tol=0)
    full = next(c for c in layout["cells"] if cells[c["id"]])
    assert close_to(at(full["x"] + 7, full["y"] + 7), RGB["cell_full"], tol=0)

    mp4 = tmp_path / "clip.mp4"
    info = render(path, mp4, fps=24, start=10, end=69, scale=0.5, progress=False)
    import imageio_ffmpeg

    frames, _secs = imageio_ffmpeg.count_frames_and_secs(str(mp4))
    assert info["frames"] == frames == 60


def test_a_generated_layout_is_drawn_from_its_data(page, tmp_path):
    """Not the paper's warehouse: 3 x 4 groups of 1 x 3 cells of 30 px, 40 px aisles."""
    from multibots.viewer import Viewer

    scenario = multibots.Scenario.from_dict({
        "robots": 3, "tasks": [0, 5, 20, 33], "unload": "nearest",
        "layout_generate": {"group_rows": 3, "group_cols": 4, "group_width": 1, "group_height": 3,
                            "chargers": 5, "aisle": 40, "cell": 30}})
    path = tmp_path / "generated.mbr"
    result = multibots.simulate(scenario, record=str(path))
    with Replay(path) as rp:
        layout = rp.layout
        assert len(layout["cells"]) == 36 and layout["cell_size"] == 30
        f = next(g for g in range(40, rp.frames) if rp.frame(g)["state"][0] == 1 and rp.frame(g)["y"][0] > 60)
        fr = rp.frame(f)
        cells = rp.cells_at(f)
    with Viewer.for_replay(str(path)) as viewer:
        open_viewer(page, viewer)
        page.evaluate(f"() => window.mbViewer.seek({f})")
        shot = Image.open(io.BytesIO(page.screenshot())).convert("RGB")

        def at(wx, wy):
            p = page.evaluate(f"() => window.mbViewer.worldToClient({wx}, {wy})")
            return shot.getpixel((int(math.floor(p["x"])), int(math.floor(p["y"]))))

        for c in layout["cells"]:
            want = RGB["cell_full"] if cells[c["id"]] else RGB["cell_empty"]
            assert close_to(at(c["x"] + 4, c["y"] + 4), want), c["id"]
        h = float(fr["heading"][0])
        x = float(fr["x"][0]) - math.sin(h) * 6.25
        y = float(fr["y"][0]) + math.cos(h) * 6.25
        assert close_to(at(x, y), RGB["blue"])
        page.select_option("#speed", "64")
        page.click("#btn-play")
        page.wait_for_function("() => { const s = window.mbViewer.state(); return s.frame === s.last; }",
                               timeout=120_000)
        assert text(page, "#c-T") == str(result.T)


def test_the_throughput_over_time_is_drawn_as_bars(page, tmp_path):
    # A lifelong run of 3,500 steps: three complete windows of deliveries, drawn as three bars
    # whose heights follow the engine's counts.
    from multibots.viewer import Viewer

    s = multibots.Scenario.from_dict({
        "robots": 6, "tasks": [], "orders": {"rate": 0.05, "horizon": 3500, "seed": 2},
        "metrics": {"window": 1000},
    })
    path = tmp_path / "flow.mbr"
    result = multibots.simulate(s, record=path)
    assert len(result.windows) == 3 and sum(result.windows) > 0
    v = Viewer.for_replay(str(path))
    v.start()
    try:
        open_viewer(page, v)
        page.wait_for_selector("#flow:not([hidden])")
        heights = page.evaluate(
            "() => [...document.querySelectorAll('#flow-bars rect')].map(r => Number(r.getAttribute('height')))")
        assert len(heights) == 3
        top = max(result.windows)
        assert [round(h, 1) for h in heights] == [round(38 * w / top, 1) for w in result.windows]
    finally:
        v.close()


def test_people_are_drawn_and_their_zones_on_demand(page, tmp_path):
    """A replay with people: each person's head (skin colour) is drawn at its recorded place,
    and `z` draws the zones of robots near people."""
    from multibots.viewer import Viewer

    path = tmp_path / "people.mbr"
    root = Path(__file__).resolve().parents[2]
    multibots.simulate(multibots.Scenario.from_toml(root / "scenarios" / "people.toml"), record=path)
    with Replay(path) as rp:
        assert rp.humans == 10
        f = 300
        fr = rp.frame(f)
    v = Viewer.for_replay(str(path))
    v.start()
    try:
        open_viewer(page, v)
        assert page.evaluate("() => window.mbViewer.meta().humans.count") == 10
        page.evaluate(f"() => window.mbViewer.seek({f})")
        shot = Image.open(io.BytesIO(page.screenshot())).convert("RGB")
        heads = 0
        for k in range(10):
            wx, wy = float(fr["people_x"][k]), float(fr["people_y"][k])
            p = page.evaluate(f"() => window.mbViewer.worldToClient({wx}, {wy})")
            if close_to(shot.getpixel((int(p["x"]), int(p["y"]))), (0xF2, 0xC9, 0xA0), tol=12):
                heads += 1
        assert heads >= 8, heads  # a robot may stand over a person's edge; most heads show
        before = page.screenshot()
        page.keyboard.press("z")
        page.wait_for_timeout(150)
        assert page.screenshot() != before, "the zones are drawn"
    finally:
        v.close()
