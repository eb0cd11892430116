"""Figures: multibots.plots (layout figure, the paper's Fig. 6-8, strategy study).

The paper layout comes from the engine, ``multibots.layout_json("paper")``. The engine's
Python API names no other layout yet, so the other shapes its generator makes
(``Layout::generate``: more groups, one-cell-wide groups, other aisle and cell sizes, fewer
chargers, thousands of cells) come from ``grid_layout``, a port of that generator whose
defaults are checked equal to the engine's paper layout.
"""

from __future__ import annotations

import pathlib
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from matplotlib.image import imread

from multibots import plots

# ---------------------------------------------------------------------------------------
# Layouts
# ---------------------------------------------------------------------------------------


def _node_name(i: int) -> str:
    """Spreadsheet-style names, as the engine's: A..Z, AA..AZ, BA.., so the paper's are A..R."""
    out = []
    while True:
        out.append(chr(ord("A") + i % 26))
        if i < 26:
            break
        i = i // 26 - 1
    return "".join(reversed(out))


def grid_layout(rows: int = 2, cols: int = 5, *, width: int = 2, height: int = 4,
                aisle: float = 50.0, cell: float = 50.0, chargers: int | None = None,
                spur: float = 40.0, name: str = "paper") -> dict:
    """A grid warehouse in layout JSON.

    A port of the engine's generator (crates/multibots-core/src/world/layout.rs,
    ``Layout::generate``); the defaults give the paper layout of docs/model.md section 1.
    """
    kn = cols + 1
    chargers = kn if chargers is None else chargers
    pitch_x, pitch_y = width * cell + aisle, height * cell + aisle
    half = aisle / 2

    def nid(m, k):
        return m * kn + k

    def north(k):
        return k % 2 == 0 and not (k == cols and cols % 2 == 0)

    nodes = [{"name": _node_name(nid(m, k)), "x": half + k * pitch_x, "y": half + m * pitch_y,
              "kind": "highway"} for m in range(rows + 1) for k in range(kn)]
    edges = []  # grouped by tail, the horizontal edge first (the search order)
    for m in range(rows + 1):
        for k in range(kn):
            u = nid(m, k)
            if m < rows:
                if k + 1 < kn:
                    edges.append([u, nid(m, k + 1)])
            elif k > 0:
                edges.append([u, nid(m, k - 1)])
            if north(k):
                if m > 0:
                    edges.append([u, nid(m - 1, k)])
            elif m < rows:
                edges.append([u, nid(m + 1, k)])
    charger_ids, spurs = [], []
    for i in range(chargers):
        at = nid(0, i * kn // chargers)
        charger_ids.append(len(nodes))
        spurs.append([len(nodes), at])
        nodes.append({"name": f"CH{i}", "x": nodes[at]["x"], "y": nodes[at]["y"] - spur,
                      "kind": "charger"})
    cells = []
    for c in range(cols):
        for r in range(rows):
            for b in range(height):
                for a in range(width):
                    k = c + a
                    x, y = aisle + c * pitch_x + a * cell, aisle + r * pitch_y + b * cell
                    edge = [nid(r + 1, k), nid(r, k)] if north(k) else [nid(r, k), nid(r + 1, k)]
                    cells.append({"id": len(cells), "x": x, "y": y, "w": cell, "h": cell,
                                  "service": [half + k * pitch_x, y + cell / 2], "edge": edge})
    return {"name": name, "bounds": [0.0, 0.0, aisle + cols * pitch_x, aisle + rows * pitch_y],
            "aisle_width": aisle, "cell_size": cell, "nodes": nodes, "edges": edges,
            "spurs": spurs, "cells": cells,
            "departure": [nid(0, k) for k in range(kn)],
            "unloading": [nid(rows, k) for k in range(kn)], "chargers": charger_ids}


@pytest.fixture(scope="module")
def paper_layout() -> dict:
    """The engine's paper layout (skips while the engine cannot be imported)."""
    multibots = pytest.importorskip("multibots")
    return multibots.layout_json("paper")


def test_generator_port_matches_engine(paper_layout):
    """With its defaults, the port gives exactly the engine's paper layout."""
    assert grid_layout() == paper_layout


def test_generator_port_matches_spec():
    """The port agrees with docs/model.md section 1 (sizes, the worked example)."""
    lay = grid_layout()
    names = [n["name"] for n in lay["nodes"]]
    assert names[:18] == [chr(ord("A") + i) for i in range(18)]
    assert names[18:] == [f"CH{k}" for k in range(6)]
    assert len(lay["edges"]) == 27 and len(lay["cells"]) == 80
    out = {}
    for u, v in lay["edges"]:
        out.setdefault(names[u], "")
        out[names[u]] += names[v]
    assert out == {"A": "B", "B": "CH", "C": "D", "D": "EJ", "E": "F", "F": "L",
                   "G": "HA", "H": "IN", "I": "JC", "J": "KP", "K": "LE", "L": "R",
                   "M": "G", "N": "M", "O": "NI", "P": "O", "Q": "PK", "R": "Q"}
    c42 = lay["cells"][42]
    assert c42["service"] == [325.0, 375.0]
    assert [names[i] for i in c42["edge"]] == ["O", "I"]


# ---------------------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------------------


def _png(path: pathlib.Path) -> np.ndarray:
    assert path.is_file() and path.stat().st_size > 0
    img = imread(path)
    assert img.ndim == 3 and img.shape[2] in (3, 4)
    return img


def _svg(path: pathlib.Path) -> str:
    assert path.is_file() and path.stat().st_size > 0
    text = path.read_text(encoding="utf-8")
    ET.fromstring(text)  # well-formed XML
    return text


def _gids(svg: str, prefix: str) -> list[str]:
    return re.findall(r'<g id="(' + re.escape(prefix) + r'[^"]*)"', svg)


def _svg_texts(svg: str) -> list[str]:
    return [t.strip() for t in re.findall(r"<text[^>]*>([^<]*)</text>", svg)]


def _pixel_of(layout):
    """A function (cell index, fx, fy) -> (row, col) into draw_layout's PNG.

    (row, col) is the pixel of the point at fractions (fx, fy) of the cell's rectangle in
    the PNG that draw_layout writes for ``layout`` (same figure, same axes placement, same
    dpi; no title).
    """
    fig, ax = plots._layout_figure(layout)
    fig.canvas.draw()
    height = int(round(fig.get_figheight() * fig.dpi))

    def pixel(cell_index, fx=0.5, fy=0.5):
        c = layout["cells"][cell_index]
        px, py = ax.transData.transform((c["x"] + fx * c["w"], c["y"] + fy * c["h"]))
        return int(round(height - py)), int(round(px))

    return pixel


def _is_red(rgb) -> bool:
    r, g, b = rgb[:3]
    return r > 0.7 and g < 0.3 and b < 0.3


def _is_black(rgb) -> bool:
    return max(rgb[:3]) < 0.1


def _no_temp_files(folder: pathlib.Path) -> None:
    assert not [p.name for p in folder.iterdir() if p.name.endswith(".tmp")]


def _paper_rows(incomplete=()):
    rows = []
    for g in range(1, 6):
        for n in range(1, 7):
            t = None if (g, n) in incomplete else 6000 // n + 37 * g
            rows.append({"N": n, "group": g, "T": t, "S": (n - 1) * g, "C": max(0, 7 - n)})
    return rows


# ---------------------------------------------------------------------------------------
# draw_layout
# ---------------------------------------------------------------------------------------


def test_public_api():
    assert set(plots.__all__) >= {"draw_layout", "draw_paper_figures", "draw_strategy_comparison"}
    for name in plots.__all__:
        assert getattr(plots, name).__doc__ or not callable(getattr(plots, name))


@pytest.mark.parametrize("suffix", ["png", "svg", "pdf"])
def test_layout_formats(tmp_path, paper_layout, suffix):
    out = plots.draw_layout(paper_layout, tmp_path / "sub" / f"layout.{suffix}",
                            title="The paper's layout")
    assert out == tmp_path / "sub" / f"layout.{suffix}"
    assert out.stat().st_size > 1000
    head = out.read_bytes()[:8]
    if suffix == "png":
        fig, _ = plots._layout_figure(paper_layout, title="The paper's layout")
        img = _png(out)
        expected = (round(fig.get_figheight() * fig.dpi), round(fig.get_figwidth() * fig.dpi))
        assert img.shape[:2] == expected
        assert img.shape[1] >= 1000  # print quality for the 800 px warehouse
    elif suffix == "svg":
        _svg(out)
    else:
        assert head.startswith(b"%PDF")
    _no_temp_files(out.parent)


def test_layout_svg_has_ids_and_names(tmp_path, paper_layout):
    svg = _svg(plots.draw_layout(paper_layout, tmp_path / "layout.svg"))
    texts = _svg_texts(svg)
    for cell in paper_layout["cells"]:
        assert str(cell["id"]) in texts
    assert len(_gids(svg, "cell-")) == len(paper_layout["cells"])
    for node in paper_layout["nodes"]:
        assert node["name"] in texts
    for label in ("Departure zone", "Unloading zone", "Charger and spur", "Highway (one-way)"):
        assert label in texts
    for gid in ("cells", "edges", "spurs", "chargers", "departure", "unloading"):
        assert _gids(svg, gid), gid


def test_cell_red_when_full_black_when_empty(tmp_path, paper_layout):
    full = [0] * len(paper_layout["cells"])
    full[42] = 1
    png = _png(plots.draw_layout(paper_layout, tmp_path / "l.png", cells_full=full))
    pixel = _pixel_of(paper_layout)
    # Sample near the corners of the square, clear of the white id in its middle.
    for index, check in ((42, _is_red), (43, _is_black), (0, _is_black)):
        for fx, fy in ((0.2, 0.2), (0.8, 0.8), (0.2, 0.8)):
            row, col = pixel(index, fx, fy)
            assert check(png[row, col]), (index, fx, fy, png[row, col])
    # Outside any cell (the middle of the aisle west of cell 42) it is neither.
    row, col = pixel(42, -0.25, 0.5)
    assert not _is_red(png[row, col]) and not _is_black(png[row, col])


def test_cells_full_changes_only_that_cell(tmp_path, paper_layout):
    n = len(paper_layout["cells"])
    empty = _png(plots.draw_layout(paper_layout, tmp_path / "a.png"))
    full = [0] * n
    full[11] = 1
    one = _png(plots.draw_layout(paper_layout, tmp_path / "b.png", cells_full=full))
    assert empty.shape == one.shape
    diff = np.any(np.abs(empty[..., :3] - one[..., :3]) > 0.05, axis=2)
    rows, cols = np.nonzero(diff)
    assert rows.size > 100
    pixel = _pixel_of(paper_layout)
    r0, c0 = pixel(11, 0.0, 0.0)
    r1, c1 = pixel(11, 1.0, 1.0)
    assert r0 - 1 <= rows.min() and rows.max() <= r1 + 1
    assert c0 - 1 <= cols.min() and cols.max() <= c1 + 1
    # The default (None) is "all empty".
    zeros = _png(plots.draw_layout(paper_layout, tmp_path / "c.png", cells_full=[0] * n))
    assert np.array_equal(zeros, empty)


_VARIANTS = {
    "one-cell-wide groups": dict(rows=3, cols=4, width=1, height=6),
    "narrow aisles": dict(rows=2, cols=3, aisle=30.0, cell=60.0, spur=25.0),
    "wide aisles": dict(rows=2, cols=3, aisle=100.0, cell=20.0, spur=60.0),
    "two chargers": dict(rows=2, cols=6, chargers=2),
    "single group": dict(rows=1, cols=1),
}


@pytest.mark.parametrize("variant", sorted(_VARIANTS))
def test_generated_layout_variants(tmp_path, variant):
    """Every shape the engine's generator makes draws: colours at the cells, all ids."""
    lay = grid_layout(name=variant, **_VARIANTS[variant])
    n = len(lay["cells"])
    full = [i % 3 == 0 for i in range(n)]
    png = _png(plots.draw_layout(lay, tmp_path / "v.png", cells_full=[int(f) for f in full]))
    pixel = _pixel_of(lay)
    for i in (0, 1, n - 1):
        assert (_is_red if full[i] else _is_black)(png[pixel(i, 0.15, 0.15)]), i
    svg = _svg(plots.draw_layout(lay, tmp_path / "v.svg", title=variant))
    texts = set(_svg_texts(svg))
    assert {str(c["id"]) for c in lay["cells"]} <= texts
    assert {nd["name"] for nd in lay["nodes"]} <= texts
    assert variant in texts


def test_layout_rejects_bad_input(tmp_path, paper_layout):
    with pytest.raises(ValueError):
        plots.draw_layout(paper_layout, tmp_path / "x.png", cells_full=[1, 0])
    with pytest.raises(ValueError):
        plots.draw_layout(paper_layout, tmp_path / "x.png",
                          cells_full=[2] * len(paper_layout["cells"]))
    with pytest.raises(ValueError):
        plots.draw_layout(paper_layout, tmp_path / "x.gif")
    assert list(tmp_path.iterdir()) == []


def test_layout_overwrite_is_atomic(tmp_path, paper_layout):
    target = tmp_path / "layout.png"
    target.write_bytes(b"old")
    plots.draw_layout(paper_layout, target)
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["layout.png"]


def test_big_layout_draws_and_drops_unreadable_ids(tmp_path):
    # How long this takes is measured in benchmarks, not asserted here.
    big = grid_layout(10, 40, name="big")  # 3200 cells: ids still readable, as glyphs
    assert len(big["cells"]) == 3200
    png = _png(plots.draw_layout(big, tmp_path / "big.png", cells_full=[1, 0] * 1600))
    svg = _svg(plots.draw_layout(big, tmp_path / "big.svg"))
    assert png.shape[1] > 2000
    assert _gids(svg, "cell-ids") and not _gids(svg, "cell-1")
    pixel = _pixel_of(big)
    assert _is_red(png[pixel(0, 0.15, 0.15)])
    assert _is_black(png[pixel(1, 0.15, 0.15)])

    huge = grid_layout(20, 60, name="huge")  # 9600 cells: ids too small to read
    svg = _svg(plots.draw_layout(huge, tmp_path / "huge.svg"))
    _png(plots.draw_layout(huge, tmp_path / "huge.png"))
    assert not _gids(svg, "cell-")
    assert "<text" in svg  # the legend is still there


# ---------------------------------------------------------------------------------------
# draw_paper_figures
# ---------------------------------------------------------------------------------------


def test_paper_figures(tmp_path):
    out_dir = tmp_path / "new" / "figs"
    paths = plots.draw_paper_figures(_paper_rows(), out_dir)
    stems = ["fig6_task_time", "fig7_collisions", "fig8_charging"]
    assert paths == [out_dir / f"{s}.{x}" for s in stems for x in ("png", "svg")]
    for stem in stems:
        img = _png(out_dir / f"{stem}.png")
        assert img.shape[:2] == (round(4.3 * 150), 10 * 150)
        svg = _svg(out_dir / f"{stem}.svg")
        assert _gids(svg, "panel-a") == ["panel-a"] and _gids(svg, "panel-b") == ["panel-b"]
        assert len(_gids(svg, "group-line-")) == 5
        assert _gids(svg, "mean-line") == ["mean-line"]
        assert not _gids(svg, "missing-note")
        texts = _svg_texts(svg)
        assert "(a)" in " ".join(texts) and "(b)" in " ".join(texts)
        assert {f"Group {g}" for g in range(1, 6)} <= set(texts)
    _no_temp_files(out_dir)


def test_paper_figures_skip_incomplete_runs(tmp_path):
    rows = _paper_rows(incomplete={(2, 1), (4, 1), (4, 2)})
    plots.draw_paper_figures(rows, tmp_path)
    svg = _svg(tmp_path / "fig6_task_time.svg")
    note = " ".join(_svg_texts(svg))
    assert _gids(svg, "missing-note")
    assert "group 2 at N = 1" in note and "group 4 at N = 1, 2" in note
    assert len(_gids(svg, "group-line-")) == 5
    for other in ("fig7_collisions", "fig8_charging"):
        assert not _gids(_svg(tmp_path / f"{other}.svg"), "missing-note")


def test_paper_figures_group_with_no_complete_run(tmp_path):
    rows = _paper_rows(incomplete={(3, n) for n in range(1, 7)})
    plots.draw_paper_figures(rows, tmp_path)
    assert len(_gids(_svg(tmp_path / "fig6_task_time.svg"), "group-line-")) == 4
    assert len(_gids(_svg(tmp_path / "fig7_collisions.svg"), "group-line-")) == 5


def test_paper_figures_from_csv_strings(tmp_path):
    """Rows read back with csv.DictReader: every value a string, T empty when incomplete."""
    rows = [{k: "" if v is None else str(v) for k, v in r.items()}
            for r in _paper_rows(incomplete={(5, 6)})]
    plots.draw_paper_figures(rows, tmp_path)
    svg = _svg(tmp_path / "fig6_task_time.svg")
    assert "group 5 at N = 6" in " ".join(_svg_texts(svg))
    assert [t for t in _svg_texts(svg) if t in {str(n) for n in range(1, 7)}]  # N ticks
    assert len(_gids(svg, "group-line-")) == 5


def test_paper_figures_need_rows(tmp_path):
    with pytest.raises(ValueError):
        plots.draw_paper_figures([], tmp_path)


# ---------------------------------------------------------------------------------------
# draw_strategy_comparison
# ---------------------------------------------------------------------------------------


def _strategy_rows(strategies, ns=(1, 2, 4, 8)):
    rows = []
    for i, s in enumerate(strategies):
        for n in ns:
            for metric, base in (("T", 8000 / n), ("S", 3 * n), ("C", 9 / n), ("cost", 50 + n)):
                mean = base * (1 + 0.1 * i)
                rows.append({"strategy": s, "N": n, "metric": metric, "mean": mean,
                             "ci_low": mean * 0.9, "ci_high": mean * 1.1})
    return rows


def test_strategy_comparison(tmp_path):
    strategies = ["fifo", "nearest", "auction"]
    paths = plots.draw_strategy_comparison(_strategy_rows(strategies), tmp_path / "s")
    stems = ["strategy_task_time", "strategy_collisions", "strategy_charging", "strategy_cost"]
    assert paths == [tmp_path / "s" / f"{s}.{x}" for s in stems for x in ("png", "svg")]
    for stem in stems:
        _png(tmp_path / "s" / f"{stem}.png")
        svg = _svg(tmp_path / "s" / f"{stem}.svg")
        assert len(_gids(svg, "panel-")) == 1
        assert len(_gids(svg, "strategy-line-")) == len(strategies)
        assert len(_gids(svg, "strategy-band-")) == len(strategies)
        assert set(strategies) <= set(_svg_texts(svg))
    _no_temp_files(tmp_path / "s")


def test_strategy_comparison_partial_metrics_and_missing_ci(tmp_path):
    rows = [r for r in _strategy_rows(["a", "b"]) if r["metric"] == "S"]
    rows[0]["ci_low"] = rows[0]["ci_high"] = None  # one replicate: no band there
    rows.append({"strategy": "c", "N": 1, "metric": "S", "mean": None,
                 "ci_low": None, "ci_high": None})  # nothing to draw for c
    paths = plots.draw_strategy_comparison(rows, tmp_path)
    assert [p.name for p in paths] == ["strategy_collisions.png", "strategy_collisions.svg"]
    assert len(_gids(_svg(paths[1]), "strategy-line-")) == 2


def test_strategy_comparison_writes_no_empty_figure(tmp_path):
    # Lifelong runs never complete: T and cost have no mean anywhere, and get no figure.
    rows = [{**r, "mean": None, "ci_low": None, "ci_high": None} if r["metric"] in ("T", "cost") else r
            for r in _strategy_rows(["a", "b"])]
    paths = plots.draw_strategy_comparison(rows, tmp_path)
    assert [p.name for p in paths] == ["strategy_collisions.png", "strategy_collisions.svg",
                                       "strategy_charging.png", "strategy_charging.svg"]
