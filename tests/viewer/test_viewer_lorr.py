"""A League of Robot Runners replay in the viewer page (Debian's chromium through Playwright):
the grid's obstacles, the robots in their state's colour, each robot's goal, and play to the
end with the score (docs/lorr.md)."""

from __future__ import annotations

import io
import math
from collections import Counter

from PIL import Image

from multibots import lorr
from multibots.replay import Replay

from viewer_helpers import open_viewer

# The viewer's colours (draw.js COLOURS): the state groups, obstacles and the floor.
RGB = {"blue": (31, 119, 180), "red": (214, 39, 40), "green": (44, 160, 44), "wall": (27, 27, 27),
       "floor": (255, 255, 255)}
COLOUR_OF_STATE = {0: "green", 1: "blue", 3: "red"}  # IDLE, TO_PICKUP, TO_DROP

MAP = """type octile
height 6
width 9
map
.........
.@@...@@.
.........
....@....
.@@...@@.
.........
"""


def close_to(actual, expected, tol=3):
    return all(abs(int(a) - int(b)) <= tol for a, b in zip(actual[:3], expected))


def recorded(tmp_path, steps=120):
    """A 2024 problem of 5 robots with two-errand tasks, run and recorded: (replay, result)."""
    (tmp_path / "m.map").write_text(MAP)
    (tmp_path / "a.agents").write_text("5\n0\n8\n27\n45\n53\n")
    (tmp_path / "t.tasks").write_text("# version for LoRR 2024\n6\n4,49\n18,26\n36,2\n22,30\n9,44\n32,0\n")
    (tmp_path / "p.json").write_text('{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", '
                                     '"teamSize": 5, "numTasksReveal": 1.2, "version": "2024 LoRR"}')
    path = tmp_path / "run.mbr"
    result = lorr.run(tmp_path / "p.json", steps=steps, record=path)
    return path, result


def test_a_lorr_replay_is_drawn_and_played(page, tmp_path):
    from multibots.viewer import Viewer

    path, result = recorded(tmp_path)
    assert result.finished > 0
    with Replay(path) as rp:
        grid, k = rp.layout["grid"], rp.layout["cell_size"]
        # a frame where some robot heads for a goal cell that no robot stands on and no
        # other robot heads for
        for f in range(10, rp.frames):
            fr = rp.frame(f)
            goals = rp.state_at(f)["task"].tolist()
            stand = {(int(y // k), int(x // k)) for x, y in zip(fr["x"].tolist(), fr["y"].tolist())}
            count = Counter(goals)
            free = [i for i, g in enumerate(goals) if g >= 0 and count[g] == 1 and divmod(g, grid["cols"]) not in stand]
            if free:
                break
        assert free
    with Viewer.for_replay(str(path)) as viewer:
        open_viewer(page, viewer)
        assert page.evaluate("() => window.mbViewer.meta().layout.grid.cols") == 9
        # The side panel names what a grid's counters count, and has no row that would mean
        # nothing here (no charging, no task time).
        rows = page.evaluate("() => [...document.querySelectorAll('#counters dt')]"
                             ".filter(e => e.checkVisibility()).map(e => e.textContent)")
        assert rows == ["step", "errors", "finished"]
        # Discs, as before the 2026 rules: no footprint, no delay in the legend.
        assert page.evaluate("() => window.mbViewer.robot(0).side") == 0
        assert "held by a delay" not in page.evaluate("() => window.mbViewer.legend()")
        assert page.evaluate(f"() => window.mbViewer.seek({f})") == f
        page.wait_for_function(f"() => window.mbViewer.state().frame === {f}")
        shot = Image.open(io.BytesIO(page.screenshot())).convert("RGB")

        def at(wx, wy):
            p = page.evaluate(f"() => window.mbViewer.worldToClient({wx}, {wy})")
            return shot.getpixel((int(math.floor(p["x"])), int(math.floor(p["y"]))))

        # obstacles dark, an empty free cell white
        assert close_to(at(1.5 * k, 1.5 * k), RGB["wall"]) and close_to(at(4.5 * k, 3.5 * k), RGB["wall"])
        empty = next((r, c) for r in range(6) for c in range(9)
                     if grid["cells"][r][c] == "." and (r, c) not in stand and r * 9 + c not in goals)
        assert close_to(at((empty[1] + 0.5) * k, (empty[0] + 0.5) * k), RGB["floor"])
        # every robot in its state's colour, half a radius across its heading line
        for i in range(rp.robots):
            h = float(fr["heading"][i])
            x = float(fr["x"][i]) - math.sin(h) * 0.2 * k
            y = float(fr["y"][i]) + math.cos(h) * 0.2 * k
            want = RGB[COLOUR_OF_STATE[int(fr["state"][i])]]
            assert close_to(at(x, y), want), (i, at(x, y), want)
        # a goal: a square in its robot's colour on the goal cell
        i = free[0]
        row, col = divmod(goals[i], grid["cols"])
        assert close_to(at((col + 0.5) * k, (row + 0.5) * k), RGB[COLOUR_OF_STATE[int(fr["state"][i])]])
        # played to the end, the page shows the run's score
        page.select_option("#speed", "64")
        page.click("#btn-play")
        page.wait_for_function("() => { const s = window.mbViewer.state(); return s.frame === s.last; }",
                               timeout=120_000)
        st = page.evaluate("() => window.mbViewer.state()")
        assert st["last"] == 120 and st["delivered"] == result.finished


def test_a_lorr_replay_exports_as_the_page_draws_it(tmp_path):
    """``multibots render``: a grid's cells are 16 px, so a small map exports at scale 1 with
    obstacles and robots where the replay has them."""
    from multibots.render import render

    path, _ = recorded(tmp_path, steps=30)
    out = tmp_path / "clip.gif"
    info = render(path, out, fps=10, start=0, end=30, every=3, progress=False)
    assert info["frames"] == 11
    with Image.open(out) as im:
        assert im.n_frames == 11 and im.size == (info["width"], info["height"])
        im.seek(10)  # replay frame 30
        frame = im.convert("RGB")
    with Replay(path) as rp:
        fr = rp.frame(30)
        k = rp.layout["cell_size"]
    ox, oy, s = info["origin"][0], info["origin"][1], info["scale"]
    assert info["width"] >= 9 * k * s

    def at(wx, wy):
        return frame.getpixel((int(math.floor(ox + wx * s)), int(math.floor(oy + wy * s))))

    assert close_to(at(1.5 * k, 1.5 * k), RGB["wall"], tol=0)
    for i in range(rp.robots):
        h = float(fr["heading"][i])
        x = float(fr["x"][i]) - math.sin(h) * 0.2 * k
        y = float(fr["y"][i]) + math.cos(h) * 0.2 * k
        assert close_to(at(x, y), RGB[COLOUR_OF_STATE[int(fr["state"][i])]], tol=0), i
