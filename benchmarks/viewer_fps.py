"""Viewer benchmark: frame rate with 1,000 robots, and time to open a 1,000 x 10,000 replay.

    .venv/bin/python benchmarks/viewer_fps.py [--robots 1000] [--steps 10000] [--seconds 5]

1. Records a replay of ROBOTS robots x STEPS steps with the engine (kept in out/bench/,
   reused if present): a lifelong run on a generated 10 x 50-group warehouse, robots
   spread over parking slots, shared chargers (BIG_SCENARIO below). ``--synthetic`` writes
   a synthetic one instead (robots circling storage blocks, in the documented format).
2. Open time: from starting the server (``Replay(path)`` opens the file) to the page having
   drawn its first frame in headless Chromium.
3. Frame rate: the page plays the replay at 1x and 8x for SECONDS each; frames drawn per
   second (requestAnimationFrame-paced, so 60 is the ceiling) and the mean time to draw one.

Prints the figures; it is not a test. Chromium: $MULTIBOTS_CHROMIUM or /usr/bin/chromium.
"""

from __future__ import annotations

import argparse
import json
import math
import struct
import sys
import time
import zlib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "python"))

from multibots._io import atomic_open  # noqa: E402
from multibots.replay import Replay, pack_chunk, pack_state, quantize_energy, quantize_heading  # noqa: E402


def grid_layout(rows: int, cols: int, gw: int = 2, gh: int = 4, aisle: float = 50.0, cell: float = 50.0) -> dict:
    """A layout JSON like the engine's generator's (docs/replay-format.md), R x C groups."""
    kn = cols + 1
    px, py = gw * cell + aisle, gh * cell + aisle
    half = aisle / 2

    def name(i: int) -> str:
        s = ""
        i += 1
        while i:
            i, r = divmod(i - 1, 26)
            s = chr(65 + r) + s
        return s

    def north(k: int) -> bool:
        return k % 2 == 0 and not (k == cols and cols % 2 == 0)

    nodes = [{"name": name(m * kn + k), "x": half + k * px, "y": half + m * py, "kind": "highway"}
             for m in range(rows + 1) for k in range(kn)]
    node = lambda m, k: m * kn + k  # noqa: E731
    edges = []
    for m in range(rows + 1):
        for k in range(kn):
            if m < rows and k + 1 < kn:
                edges.append([node(m, k), node(m, k + 1)])
            elif m == rows and k > 0:
                edges.append([node(m, k), node(m, k - 1)])
            if north(k) and m > 0:
                edges.append([node(m, k), node(m - 1, k)])
            elif not north(k) and m < rows:
                edges.append([node(m, k), node(m + 1, k)])
    chargers, spurs = [], []
    for k in range(kn):
        cid = len(nodes)
        nodes.append({"name": f"CH{k}", "x": nodes[k]["x"], "y": nodes[k]["y"] - 40, "kind": "charger"})
        chargers.append(cid)
        spurs.append([cid, k])
    cells = []
    for c in range(cols):
        for r in range(rows):
            for b in range(gh):
                for a in range(gw):
                    x = aisle + c * px + a * cell
                    y = aisle + r * py + b * cell
                    k = c + a
                    e = [node(r + 1, k), node(r, k)] if north(k) else [node(r, k), node(r + 1, k)]
                    cells.append({"id": len(cells), "x": x, "y": y, "w": cell, "h": cell,
                                  "service": [half + k * px, y + cell / 2], "edge": e})
    return {"name": f"grid-{rows}x{cols}", "bounds": [0, 0, aisle + cols * px, aisle + rows * py],
            "aisle_width": aisle, "cell_size": cell, "nodes": nodes, "edges": edges, "spurs": spurs,
            "cells": cells, "departure": list(range(kn)), "unloading": [node(rows, k) for k in range(kn)],
            "chargers": chargers}


def synthetic_replay(path: Path, robots: int, steps: int, chunk_steps: int = 1024) -> None:
    """Robots circling storage blocks (on the aisle centre lines) with changing states."""
    rows, cols = 8, 30
    layout = grid_layout(rows, cols)
    aisle, cell = 50.0, 50.0
    pxs, pys = 2 * cell + aisle, 4 * cell + aisle
    rng = np.random.default_rng(7)
    block = rng.integers(0, rows * cols, robots)
    bx = (block % cols) * pxs + aisle / 2
    by = (block // cols) * pys + aisle / 2
    w, h = pxs, pys
    per = 2 * (w + h)
    phase = rng.uniform(0, per, robots)
    state_phase = rng.integers(0, 1000, robots)
    n_cells = len(layout["cells"])
    full = np.zeros(n_cells, dtype=np.uint8)
    full[rng.choice(n_cells, n_cells // 3, replace=False)] = 1
    header = {"format": "multibots-replay", "version": 1, "robots": robots, "radius": [12.5] * robots,
              "home": [len(layout["nodes"]) - 1] * robots, "energy_full": 10.0, "threshold": 3.5,
              "chunk_steps": chunk_steps, "cells_full": full.tolist(), "goods_total": int(full.sum()),
              "layout": layout, "scenario": "# synthetic benchmark replay\n"}
    hb = json.dumps(header).encode()
    table = []
    with atomic_open(path) as fh:
        fh.write(b"MBREPLAY" + struct.pack("<II", 1, len(hb)) + hb)
        pos = fh.tell()
        for first in range(0, steps + 1, chunk_steps):
            t = np.arange(first, min(steps + 1, first + chunk_steps))[:, None]
            d = (4.0 * t + phase[None, :]) % per
            x = np.where(d < w, bx + d, np.where(d < w + h, bx + w, np.where(d < 2 * w + h, bx + w - (d - w - h), bx)))
            y = np.where(
                d < w, by, np.where(d < w + h, by + (d - w), np.where(d < 2 * w + h, by + h, by + h - (d - 2 * w - h)))
            )
            hd = np.where(d < w, 0.0, np.where(d < w + h, math.pi / 2, np.where(d < 2 * w + h, math.pi, -math.pi / 2)))
            st = np.array([1, 2, 3, 4, 5, 6, 7, 0], dtype=np.uint8)[((t + state_phase[None, :]) // 300) % 8]
            en = 10.0 - ((t + state_phase[None, :]) % 1300) * 0.005
            k = len(t)
            counters = np.stack([t[:, 0] // 3, t[:, 0] // 500, t[:, 0] // 20], axis=1)
            raw = pack_chunk(first, counters, x, y, np.zeros((0, 4)), quantize_energy(en, 10.0),
                             quantize_heading(hd), pack_state(st, en < 3.5))
            z = zlib.compress(raw, 1)
            table.append({"offset": pos, "length": len(z), "first_frame": first, "frames": k})
            fh.write(z)
            pos += len(z)
        footer = {"frames": steps + 1, "T": None, "S": steps // 3, "C": steps // 500,
                  "outcome": "incomplete", "delivered": steps // 20, "chunks": table}
        fb = json.dumps(footer).encode()
        fh.write(fb + struct.pack("<QQ", pos, len(fb)))


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
    ap.add_argument("--synthetic", action="store_true",
                    help="use a synthetic replay (robots circling blocks) instead of the engine's")
    args = ap.parse_args()

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    tag = "synthetic" if args.synthetic else "engine"
    path = out / f"viewer-{tag}-{args.robots}x{args.steps}.mbr"
    if not path.exists():
        t0 = time.perf_counter()
        if args.synthetic:
            synthetic_replay(path, args.robots, args.steps)
        else:
            engine_replay(path, args.robots, args.steps)
        print(f"wrote {path} ({tag}) in {time.perf_counter() - t0:.1f} s")
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
