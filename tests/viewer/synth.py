"""A synthetic replay writer, used only to develop the viewer before the engine exists and to
build malformed files; the viewer's tests use the real engine's replays."""

from __future__ import annotations

import json
import math
import os
import struct
import zlib

import numpy as np

from multibots.replay import pack_chunk, pack_state, quantize_energy, quantize_heading


def paper_layout() -> dict:
    names = [chr(ord("A") + i) for i in range(18)]
    nodes = [{"name": names[6 * m + k], "x": 25.0 + 150 * k, "y": 25.0 + 250 * m, "kind": "highway"}
             for m in range(3) for k in range(6)]
    nodes += [{"name": f"CH{k}", "x": 25.0 + 150 * k, "y": -15.0, "kind": "charger"} for k in range(6)]
    out = {"A": "B", "B": "CH", "C": "D", "D": "EJ", "E": "F", "F": "L", "G": "HA", "H": "IN",
           "I": "JC", "J": "KP", "K": "LE", "L": "R", "M": "G", "N": "M", "O": "NI", "P": "O",
           "Q": "PK", "R": "Q"}
    edges = [[names.index(a), names.index(b)] for a in names for b in out[a]]
    cells = []
    for g in range(10):
        c, r = divmod(g, 2)
        for b in range(4):
            for a in range(2):
                cid = 8 * g + 2 * b + a
                k = c + a
                top, bot = 6 * r + k, 6 * (r + 1) + k
                edge = [bot, top] if k % 2 == 0 else [top, bot]
                cells.append({"id": cid, "x": 50.0 + 150 * c + 50 * a, "y": 50.0 + 250 * r + 50 * b,
                              "w": 50.0, "h": 50.0, "service": [25.0 + 150 * k, 75.0 + 250 * r + 50 * b],
                              "edge": edge})
    return {"name": "paper", "bounds": [0, 0, 800, 550], "aisle_width": 50, "cell_size": 50,
            "nodes": nodes, "edges": edges, "spurs": [[18 + k, k] for k in range(6)], "cells": cells,
            "departure": list(range(6)), "unloading": list(range(12, 18)), "chargers": list(range(18, 24))}


def write_replay(path, layout, frames, chunk_steps=64, goods=(11, 8, 39), energy_full=10.0,
                 T=None, S=0, C=0, delivered=0):
    """frames: list of dicts with x, y, heading, state, marked, energy, S, C, delivered, events."""
    n = len(frames[0]["x"])
    header = {"format": "multibots-replay", "version": 1, "robots": n, "radius": [12.5] * n,
              "home": [18 + (i % 6) for i in range(n)], "energy_full": energy_full, "threshold": 3.5,
              "chunk_steps": chunk_steps,
              "cells_full": [1 if c["id"] in goods else 0 for c in layout["cells"]],
              "goods_total": len(goods), "layout": layout, "scenario": "# synthetic\n"}
    hb = json.dumps(header).encode()
    out = bytearray(b"MBREPLAY" + struct.pack("<II", 1, len(hb)) + hb)
    table = []
    for first in range(0, len(frames), chunk_steps):
        fr = frames[first:first + chunk_steps]
        ev = [e for f in fr for e in f.get("events", [])]
        raw = pack_chunk(first, [[f["S"], f["C"], f["delivered"]] for f in fr],
                         np.array([f["x"] for f in fr]), np.array([f["y"] for f in fr]),
                         np.array(ev, dtype=np.uint32).reshape(-1, 4),
                         quantize_energy(np.array([f["energy"] for f in fr]), energy_full),
                         quantize_heading(np.array([f["heading"] for f in fr])),
                         pack_state(np.array([f["state"] for f in fr]), np.array([f["marked"] for f in fr])))
        z = zlib.compress(raw, 6)
        table.append({"offset": len(out), "length": len(z), "first_frame": first, "frames": len(fr)})
        out += z
    footer = {"frames": len(frames), "T": T, "S": S, "C": C,
              "outcome": "complete" if T is not None else "incomplete", "delivered": delivered,
              "chunks": table}
    fb = json.dumps(footer).encode()
    off = len(out)
    out += fb + struct.pack("<QQ", off, len(fb))
    tmp = str(path) + ".tmp"
    with open(tmp, "wb") as fh:
        fh.write(out)
    os.replace(tmp, path)


def demo_frames(n_robots=3, steps=400):
    """Robots circling the warehouse's outer highway, with some state changes."""
    loop = [(25, 25), (775, 25), (775, 525), (25, 525)]
    per = sum(math.dist(loop[i], loop[(i + 1) % 4]) for i in range(4))
    frames = []
    for t in range(steps + 1):
        xs, ys, hs, st, mk, en = [], [], [], [], [], []
        for i in range(n_robots):
            d = (4.0 * t + i * per / n_robots) % per
            for j in range(4):
                a, b = loop[j], loop[(j + 1) % 4]
                L = math.dist(a, b)
                if d <= L:
                    xs.append(a[0] + (b[0] - a[0]) * d / L)
                    ys.append(a[1] + (b[1] - a[1]) * d / L)
                    hs.append(math.atan2(b[1] - a[1], b[0] - a[0]))
                    break
                d -= L
            st.append([1, 3, 5, 7][(t // 100 + i) % 4])
            mk.append(t > steps // 2 and i == 0)
            en.append(max(0.0, 10.0 - 0.02 * t))
        frames.append({"x": xs, "y": ys, "heading": hs, "state": st, "marked": mk, "energy": en,
                       "S": t // 50, "C": t // 200, "delivered": min(3, t // 120), "events": []})
    return frames


if __name__ == "__main__":
    import sys
    write_replay(sys.argv[1], paper_layout(), demo_frames(), T=None)
