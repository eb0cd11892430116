"""Viewer benchmark: frame rate with 1,000 robots, and time to open a 1,000 x 10,000 replay.

    .venv/bin/python benchmarks/viewer_fps.py [--robots 1000] [--steps 10000] [--seconds 5]

1. Records a replay of ROBOTS robots x STEPS steps with the engine (kept in out/bench/,
   reused if present): a lifelong run on a generated 10 x 50-group warehouse, robots
   spread over parking slots, shared chargers (BIG_SCENARIO below).
2. Open time: from starting the server (``Replay(path)`` opens the file) to the page having
   drawn its first frame in headless Chromium.
3. Frame rate: the page plays the replay at 1x and 8x for SECONDS each; frames drawn per
   second (requestAnimationFrame-paced, so 60 is the ceiling) and the mean time to draw one.

Prints the figures; it is not a test. Chromium: $MULTIBOTS_CHROMIUM or /usr/bin/chromium.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from multibots.replay import Replay  # noqa: E402

#: A lifelong run of 1,000 robots on a generated 10 x 50-group warehouse (1,000 x 10,000).
BIG_SCENARIO = """\
robots = {robots}
placement = "spread"
step_limit = {steps}
unload = "nearest"
tasks = {{ random = 1000, seed = 1 }}

[layout_generate]
group_rows = 10
group_cols = 50
chargers = 51

[charging]
chargers = "shared"

[orders]
rate = 5.0
horizon = {steps}

[robot]
consumption = 0.0004
"""


def engine_replay(path: Path, robots: int, steps: int) -> None:
    """Record the replay with the engine (BIG_SCENARIO)."""
    import multibots

    toml = path.with_suffix(".toml")
    toml.write_text(BIG_SCENARIO.format(robots=robots, steps=steps))
    result = multibots.simulate(multibots.Scenario.from_toml(str(toml)), record=str(path))
    print(f"  engine run: {result.steps} steps, S = {result.S}, delivered {result.delivered} ({result.outcome})")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=10000)
    ap.add_argument("--seconds", type=float, default=5.0)
    ap.add_argument("--out", default=str(ROOT / "out" / "bench"))
    args = ap.parse_args()

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"viewer-engine-{args.robots}x{args.steps}.mbr"
    if not path.exists():
        t0 = time.perf_counter()
        engine_replay(path, args.robots, args.steps)
        print(f"wrote {path} in {time.perf_counter() - t0:.1f} s")
    size = path.stat().st_size
    t0 = time.perf_counter()
    rp = Replay(path)
    t_open = time.perf_counter() - t0
    print(f"replay: {rp.robots} robots x {rp.frames - 1} steps, {rp.chunk_count} chunks, "
          f"{size / 1e6:.1f} MB on disk ({rp.robots * rp.frames * 12 / 1e6:.0f} MB decompressed)")
    print(f"Replay(path) opens in {t_open * 1000:.1f} ms (header + footer only)")
    rp.close()

    from playwright.sync_api import sync_playwright

    from multibots.render import CHROMIUM_ARGS, chromium_path
    from multibots.viewer import Viewer

    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium_path(), args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        page.goto("about:blank")
        t0 = time.perf_counter()
        viewer = Viewer.for_replay(str(path)).start()
        try:
            page.goto(viewer.url)
            page.wait_for_function(
                "() => window.mbViewer && window.mbViewer.ready && window.mbViewer.state().drawn > 0", polling=10
            )
            t_page = time.perf_counter() - t0
            print(f"open to first frame drawn in the browser: {t_page:.2f} s")
            t0 = time.perf_counter()
            page.evaluate(f"() => window.mbViewer.seek({rp.frames - 1})")
            print(f"seek to the last frame: {(time.perf_counter() - t0) * 1000:.0f} ms")
            page.evaluate("() => window.mbViewer.seek(0)")
            runs = [(1, "whole warehouse in view", None), (8, "whole warehouse in view", None),
                    (1, "zoomed: robots 5 px in radius, drawn in full", 0.4),
                    (1, "zoomed to the paper's scale (1 px per px)", 1.0)]
            for speed, view, target in runs:
                if target:
                    scale = page.evaluate("() => window.mbViewer.worldToClient(0, 0).scale")
                    box = page.locator("#view").bounding_box()
                    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
                    page.mouse.wheel(0, -math.log(target / scale) / 0.0015)
                    page.wait_for_function(f"() => window.mbViewer.worldToClient(0, 0).scale > {target * 0.95}")
                    visible = page.evaluate("""() => { const v = window.mbViewer; const n = v.meta().robots;
                        const b = document.getElementById('view').getBoundingClientRect(); let k = 0;
                        for (let i = 0; i < n; i++) { const r = v.robot(i); const p = v.worldToClient(r.x, r.y);
                          if (p.x >= b.left && p.x <= b.right && p.y >= b.top && p.y <= b.bottom) k++; }
                        return k; }""")
                    view += f", {visible} robots in view"
                page.evaluate(f"() => {{ window.mbViewer.setSpeed({speed}); window.mbViewer.play(); }}")
                page.wait_for_timeout(1000)  # warm up
                d0 = page.evaluate("() => window.mbViewer.stats().drawn")
                t0 = time.perf_counter()
                page.wait_for_timeout(args.seconds * 1000)
                st = page.evaluate("() => window.mbViewer.stats()")
                dt = time.perf_counter() - t0
                fps = (st["drawn"] - d0) / dt
                print(f"{rp.robots} robots, {speed}x, {view}: {fps:.1f} frames per second drawn, "
                      f"{st['drawMs']:.2f} ms of script per frame (1280x800 viewport, headless Chromium, no GPU)")
                page.evaluate("() => window.mbViewer.pause()")
        finally:
            viewer.close()
            browser.close()


if __name__ == "__main__":
    main()
