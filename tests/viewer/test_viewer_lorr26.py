"""A League of Robot Runners 2026 replay in the viewer page (Debian's chromium through
Playwright): each robot drawn as its square of side ``agentSize`` where the replay puts it
(its cell's top-left corner, slid along its heading during a move), robots held by a delay
outlined and marked, the delays counted, and a held robot's panel naming the tick its delay
ends (docs/viewer.md, docs/lorr.md)."""

from __future__ import annotations

import io
import math

from PIL import Image

from multibots import lorr
from multibots.replay import Replay
from multibots.replay_state import EV_WAIT
from multibots.viewer.server import ReplaySource

from viewer_helpers import open_viewer

# The viewer's colours (draw.js COLOURS): the state groups and a delay's mark.
RGB = {"blue": (31, 119, 180), "red": (214, 39, 40), "green": (44, 160, 44), "wall": (27, 27, 27),
       "delay": (148, 103, 189)}
COLOUR_OF_STATE = {0: "green", 1: "blue", 3: "red"}  # IDLE, TO_PICKUP, TO_DROP

MAP = """type octile
height 8
width 10
map
..........
..........
..@@......
..........
......@@..
..........
..........
..........
"""
SIZE = 1.5  # agentSize: each square reaches half a cell into the cells right and below
TICKS = 150


def close_to(actual, expected, tol=3):
    return all(abs(int(a) - int(b)) <= tol for a, b in zip(actual[:3], expected))


def recorded(tmp_path):
    """A 2026 problem of 6 robots of side 1.5, moves of 3 ticks and frequent delays, run and
    recorded: (replay path, result)."""
    (tmp_path / "m.map").write_text(MAP)
    (tmp_path / "a.agents").write_text("6\n0\n4\n8\n60\n64\n68\n")
    (tmp_path / "t.tasks").write_text("8\n24,65\n44,10\n68,31\n18,54\n38,61\n50,5\n27,62\n16,40\n")
    (tmp_path / "p.json").write_text(
        '{"mapFile": "m.map", "agentFile": "a.agents", "taskFile": "t.tasks", "teamSize": 6, '
        '"numTasksReveal": 1.5, "version": "2026 LoRR", "agentCounter": 3, "agentSize": %s, '
        '"delayConfig": {"seed": 3, "minDelay": 3, "maxDelay": 6, "eventModel": "bernoulli", '
        '"pDelay": 0.04, "durationModel": "uniform", "gaussMeanRatio": 0.5, "gaussStdRatio": 0.22}}' % SIZE)
    path = tmp_path / "run.mbr"
    return path, lorr.run(tmp_path / "p.json", steps=TICKS, record=path)


def waits(rp, f):
    """The WAIT events up to frame f: (frame, robot, end tick), from the replay's events."""
    ev = rp.events(0, f + 1)
    return [(int(e[0]), int(e[2]), int(e[3])) for e in ev if int(e[1]) == EV_WAIT]


def squares(rp, f, side):
    """Each robot's square in frame f as the replay records it: (x0, y0) its top-left, in px."""
    fr = rp.frame(f)
    return [(float(x) - side / 2, float(y) - side / 2) for x, y in zip(fr["x"].tolist(), fr["y"].tolist())]


def pick(rp, side):
    """A frame with a held robot and an unheld one standing on its cell, and (if there is one)
    an unheld robot half-way through a move, each with nothing drawn just outside its square
    (no other square, no goal marker): (frame, held, standing, moving or None)."""
    k = rp.layout["cell_size"]
    cols = rp.layout["grid"]["cols"]
    best = None
    for f in range(1, rp.frames):
        fr = rp.frame(f)
        sq = squares(rp, f, side)
        goals = [g for g in rp.state_at(f)["task"].tolist() if g >= 0]
        marks = [((g % cols + 0.5) * k, (g // cols + 0.5) * k) for g in goals]

        held = [i for i in range(rp.robots) if fr["marked"][i]]
        free = [i for i in range(rp.robots) if not fr["marked"][i] and clear(i, sq, marks, side, k)]
        standing = [i for i in free if sq[i][0] % k == 0 and sq[i][1] % k == 0]
        moving = [i for i in free if sq[i][0] % k != 0 or sq[i][1] % k != 0]
        if held and standing:
            cand = (f, held[0], standing[0], moving[0] if moving else None)
            if moving:
                return cand
            best = best or cand
    return best


def clear(i, sq, marks, side, k):
    """Whether no other robot and no goal is drawn just outside robot i's square (sq: the
    squares' top-left corners; marks: the goal markers' centres; k: a cell's side)."""
    x0, y0 = sq[i]
    for px, py in outside(x0, y0, side):
        if any(j != i and x <= px <= x + side and y <= py <= y + side for j, (x, y) in enumerate(sq)):
            return False
        if any(abs(px - mx) <= 0.35 * k and abs(py - my) <= 0.35 * k for mx, my in marks):
            return False
    return True


def inside(x0, y0, side):
    """Points well inside a square (near its corners, off the heading line)."""
    return [(x0 + a * side, y0 + b * side) for a in (0.12, 0.88) for b in (0.12, 0.88)]


def outside(x0, y0, side):
    """Points just outside a square's four sides."""
    return [(x0 - 0.12 * side, y0 + 0.3 * side), (x0 + 1.12 * side, y0 + 0.3 * side),
            (x0 + 0.3 * side, y0 - 0.12 * side), (x0 + 0.3 * side, y0 + 1.12 * side)]


def test_the_panel_data_says_until_which_tick_a_robot_is_held(tmp_path):
    path, _ = recorded(tmp_path)
    with Replay(path) as rp:
        src = ReplaySource(rp)
        assert src.meta["lorr"]["rules"] == "2026" and src.meta["lorr"]["agentSize"] == SIZE
        seen = 0
        for f in range(1, rp.frames):
            fr = rp.frame(f)
            ws = waits(rp, f)
            for i in range(rp.robots):
                p = src.robot(i, f)
                assert p["held"] == bool(fr["marked"][i])
                mine = [w for w in ws if w[1] == i]
                if fr["marked"][i]:
                    # held: its last delay began by now and ends after the tick this frame shows
                    assert mine and p["held_until"] == mine[-1][2] and mine[-1][0] <= f <= mine[-1][2]
                    seen += 1
                else:
                    assert p["held_until"] is None
                # the robot's own count of delays is its WAIT events
                assert p["S"] == len(mine)
        assert seen > 0


def test_other_replays_have_no_delays(paper_run, tmp_path):
    """A 2024 replay and a paper replay: no ``held`` in a robot's panel data, no delay end
    (their WAIT events are waits that began)."""
    from test_viewer_lorr import recorded as recorded24

    path, _ = recorded24(tmp_path, steps=20)
    for replay in (path, paper_run[0]):
        with Replay(replay) as rp:
            src = ReplaySource(rp)
            assert (src.meta["lorr"] or {}).get("agentSize") is None
            for f in (0, rp.frames - 1):
                for i in range(rp.robots):
                    assert "held" not in src.robot(i, f) and rp.delay_end(i, f) is None


def test_a_2026_replay_draws_footprints_and_delays(page, tmp_path):
    from multibots.viewer import Viewer

    path, result = recorded(tmp_path)
    with Replay(path) as rp:
        k = rp.layout["cell_size"]
        side = SIZE * k
        assert rp.header["lorr"]["agentSize"] == SIZE and rp.header["lorr"]["agentCounter"] == 3
        chosen = pick(rp, side)
        assert chosen, "no frame with a held robot beside a clear standing one"
        f, held, standing, moving = chosen
        fr = rp.frame(f)
        sq = squares(rp, f, side)
        ws = waits(rp, f)
        assert fr["C"] == len(ws) > 0  # the counter C: delays drawn so far
        end = [w for w in ws if w[1] == held][-1][2]
        own = len([w for w in ws if w[1] == held])
        total = rp.summary["C"]
        assert total == len(waits(rp, rp.frames - 1))
    with Viewer.for_replay(str(path)) as viewer:
        open_viewer(page, viewer)
        # The counters: the delays drawn so far under C's row, labelled so; the banner and
        # the legend say so too.
        rows = page.evaluate("() => [...document.querySelectorAll('#counters dt')]"
                             ".filter(e => e.checkVisibility()).map(e => e.textContent)")
        assert rows == ["step", "errors", "delays", "finished"]
        assert "held by a delay" in page.evaluate("() => window.mbViewer.legend()")
        assert page.evaluate(f"() => window.mbViewer.seek({f})") == f
        page.wait_for_function(f"() => window.mbViewer.state().frame === {f}")
        assert page.text_content("#c-C") == str(len(ws))
        assert page.evaluate(f"() => window.mbViewer.robot({held}).side") == side
        shot = Image.open(io.BytesIO(page.screenshot())).convert("RGB")

        def at(wx, wy):
            p = page.evaluate(f"() => window.mbViewer.worldToClient({wx}, {wy})")
            return shot.getpixel((int(math.floor(p["x"])), int(math.floor(p["y"]))))

        # The footprint: the whole square of side agentSize in the robot's colour, with its
        # top-left corner on its cell's (a disc at the centre, or a square centred on the cell,
        # leaves some of these points out or colours one outside).
        for i in [standing] + ([moving] if moving is not None else []):
            colour = RGB[COLOUR_OF_STATE[int(fr["state"][i])]]
            x0, y0 = sq[i]
            for x, y in inside(x0, y0, side):
                assert close_to(at(x, y), colour), (i, "inside", x, y, at(x, y), colour)
            for x, y in outside(x0, y0, side):
                assert not close_to(at(x, y), colour, tol=40), (i, "outside", x, y, at(x, y), colour)
            # its heading: a dark line from the centre towards the side it faces
            h = float(fr["heading"][i])
            cx, cy = x0 + side / 2, y0 + side / 2
            assert close_to(at(cx + math.cos(h) * 0.35 * side, cy + math.sin(h) * 0.35 * side), RGB["wall"])
            assert close_to(at(cx - math.cos(h) * 0.35 * side, cy - math.sin(h) * 0.35 * side), colour)
            # not held: no delay mark at the centre or along the sides
            assert not close_to(at(x0 + side / 2, y0 + side / 2), RGB["delay"], tol=40)
            assert close_to(at(x0 + 0.05 * side, y0 + 0.3 * side), colour)
        # A robot held by a delay: its square outlined in the delay colour, the pause mark at its
        # centre, its body still in its state's colour.
        x0, y0 = sq[held]
        assert close_to(at(x0 + side / 2, y0 + side / 2), RGB["delay"])
        for x, y in [(x0 + 0.05 * side, y0 + 0.3 * side), (x0 + 0.95 * side, y0 + 0.7 * side),
                     (x0 + 0.3 * side, y0 + 0.05 * side), (x0 + 0.7 * side, y0 + 0.95 * side)]:
            assert close_to(at(x, y), RGB["delay"]), (x, y, at(x, y))
        colour = RGB[COLOUR_OF_STATE[int(fr["state"][held])]]
        assert close_to(at(x0 + 0.2 * side, y0 + 0.2 * side), colour)
        # Its panel: delayed, until the tick its WAIT event names, and its own delays.
        p = page.evaluate(f"() => window.mbViewer.worldToClient({x0 + 0.2 * side}, {y0 + 0.2 * side})")
        page.mouse.click(p["x"], p["y"])
        page.wait_for_function(f"() => window.mbViewer.state().selected === {held} "
                               f"&& window.mbViewer.state().panelFrame === {f}")
        page.wait_for_function(f"() => document.getElementById('p-state').textContent.includes('until tick {end}')")
        assert "delayed" in page.text_content("#p-state")
        assert page.text_content("#p-S") == str(own)
        panel = page.evaluate("() => [...document.querySelectorAll('#panel dt')]"
                              ".filter(e => e.checkVisibility()).map(e => e.textContent)")
        assert panel == ["state", "task cell", "delays"]
        # Played to the end: the delays of the whole run.
        page.select_option("#speed", "64")
        page.click("#btn-play")
        page.wait_for_function("() => { const s = window.mbViewer.state(); return s.frame === s.last; }",
                               timeout=120_000)
        st = page.evaluate("() => window.mbViewer.state()")
        assert st["C"] == total and st["delivered"] == result.finished
