"""The layout figure, like the paper's Fig. 2, from the layout JSON of any layout."""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
from matplotlib.collections import LineCollection, PatchCollection, PathCollection, PolyCollection
from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties
from matplotlib.legend_handler import HandlerBase
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Polygon, Rectangle
from matplotlib.path import Path as MplPath
from matplotlib.textpath import TextPath

from multibots.plots._common import (
    _CHARGER_COLOR,
    _EDGE_COLOR,
    _PNG_DPI,
    _RC,
    _TEXT_LABEL_LIMIT,
    _VECTOR_CELL_LIMIT,
    _WALL_COLOR,
    _ZONE_COLOR,
    CELL_EMPTY_COLOR,
    CELL_FULL_COLOR,
    new_figure,
    save_atomic,
)

__all__ = ["draw_layout"]


class _GlyphHandler(HandlerBase):
    """Legend handler that draws one of the layout's map symbols."""

    def __init__(self, kind: str) -> None:
        super().__init__()
        self.kind = kind

    def create_artists(self, legend, orig_handle, xdescent, ydescent, width,
                       height, fontsize, trans):
        cx = width / 2 - xdescent
        cy = height / 2 - ydescent
        r = 0.55 * height
        artists: list[Any] = []
        if self.kind == "edge":
            x0, x1 = cx - 0.5 * width, cx + 0.5 * width
            head = 0.45 * height
            artists.append(Line2D([x0, x1 - head], [cy, cy], color=_EDGE_COLOR, lw=1.4))
            artists.append(Polygon(
                [[x1, cy], [x1 - 1.6 * head, cy + head * 0.75],
                 [x1 - 1.6 * head, cy - head * 0.75]],
                closed=True, facecolor=_EDGE_COLOR, edgecolor="none"))
        elif self.kind == "departure":
            artists.append(Circle((cx, cy), r, facecolor="white", edgecolor=_ZONE_COLOR, lw=1.2))
            d = r / math.sqrt(2)
            artists.append(Line2D([cx - d, cx + d], [cy - d, cy + d], color=_ZONE_COLOR, lw=1.2))
            artists.append(Line2D([cx - d, cx + d], [cy + d, cy - d], color=_ZONE_COLOR, lw=1.2))
        elif self.kind == "unloading":
            artists.append(Circle((cx, cy), r, facecolor="white", edgecolor=_ZONE_COLOR, lw=1.2))
            artists.append(Circle((cx, cy), 0.55 * r, facecolor="none", edgecolor=_ZONE_COLOR,
                                  lw=1.2))
        elif self.kind == "charger":
            bw, bh = 0.9 * height * 1.4, 0.9 * height
            bx = cx + 0.05 * width
            artists.append(Line2D([cx - 0.5 * width, bx - bw / 2], [cy, cy],
                                  color=_CHARGER_COLOR, lw=1.3, ls=(0, (2, 1.5))))
            artists.append(Rectangle((bx - bw / 2, cy - bh / 2), bw, bh,
                                     facecolor=_CHARGER_COLOR, edgecolor="#1b5e20", lw=0.8))
            artists.append(Rectangle((bx + bw / 2, cy - bh / 5), bw / 7, 2 * bh / 5,
                                     facecolor="#1b5e20", edgecolor="none"))
        for a in artists:
            a.set_transform(trans)
        return artists


def _as_cells_full(cells_full: Sequence[int] | None, n_cells: int) -> np.ndarray:
    """Validate ``cells_full`` and return it as a boolean array."""
    if cells_full is None:
        return np.zeros(n_cells, dtype=bool)
    arr = np.asarray(list(cells_full))
    if arr.shape != (n_cells,):
        raise ValueError(
            f"cells_full has {arr.size} entries but the layout has {n_cells} cells"
        )
    if not np.all((arr == 0) | (arr == 1)):
        raise ValueError("cells_full must hold only 0 and 1")
    return arr.astype(bool)


def _layout_extent(layout: Mapping[str, Any]) -> tuple[float, float, float, float]:
    """Data rectangle that holds the warehouse, its cells and all nodes."""
    x0, y0, x1, y1 = (float(v) for v in layout["bounds"])
    xs = [x0, x1] + [float(n["x"]) for n in layout["nodes"]]
    ys = [y0, y1] + [float(n["y"]) for n in layout["nodes"]]
    for c in layout["cells"]:
        xs += [float(c["x"]), float(c["x"]) + float(c["w"])]
        ys += [float(c["y"]), float(c["y"]) + float(c["h"])]
    return min(xs), min(ys), max(xs), max(ys)


def _glyph_labels(labels: Sequence[str], xs: np.ndarray, ys: np.ndarray,
                  size: float) -> PathCollection:
    """Many short labels as one compound path, centred on (xs, ys).

    Drawing thousands of :class:`matplotlib.text.Text` artists takes seconds;
    stamping cached glyph outlines (one per character) into a single path is
    fast. ``size`` is the font size in data units; the y axis points down.
    """
    prop = FontProperties(family="DejaVu Sans")
    glyphs: dict[str, tuple[np.ndarray, np.ndarray, float]] = {}

    def glyph(ch: str) -> tuple[np.ndarray, np.ndarray, float]:
        if ch not in glyphs:
            one = TextPath((0, 0), ch, size=1.0, prop=prop)
            two = TextPath((0, 0), ch * 2, size=1.0, prop=prop)
            advance = two.get_extents().x1 - one.get_extents().x1
            glyphs[ch] = (one.vertices.copy(), one.codes.copy(), advance)
        return glyphs[ch]

    ref = TextPath((0, 0), "0", size=1.0, prop=prop).get_extents()
    mid_y = (ref.y0 + ref.y1) / 2
    verts, codes = [], []
    for label, x, y in zip(labels, xs, ys):
        parts = [glyph(ch) for ch in label]
        width = sum(p[2] for p in parts)
        pen = -width / 2
        for v, c, advance in parts:
            if len(v):
                out = np.empty_like(v)
                out[:, 0] = x + (v[:, 0] + pen) * size
                out[:, 1] = y - (v[:, 1] - mid_y) * size
                verts.append(out)
                codes.append(c)
            pen += advance
    if not verts:
        return PathCollection([])
    return PathCollection([MplPath(np.concatenate(verts), np.concatenate(codes))])


def _layout_figure(layout: Mapping[str, Any], cells_full: Sequence[int] | None = None,
                   title: str | None = None) -> tuple[Figure, Any]:
    """Build the layout figure; :func:`draw_layout` saves it.

    The axes sit at a fixed place in the figure (no tight bounding box at save
    time), so ``ax.transData`` maps a layout point to the pixel it is drawn at in
    the saved PNG (``fig.dpi`` is the PNG's resolution).

    Args:
        layout: The layout JSON dict.
        cells_full: One 0/1 per cell, or None for all empty.
        title: Optional title above the map.

    Returns:
        The figure and its single map axes.
    """
    nodes = layout["nodes"]
    cells = layout["cells"]
    full = _as_cells_full(cells_full, len(cells))
    aisle = float(layout.get("aisle_width") or 50.0)

    ex0, ey0, ex1, ey1 = _layout_extent(layout)
    pad = min(0.6 * aisle, 0.05 * max(ex1 - ex0, ey1 - ey0))
    ex0, ey0, ex1, ey1 = ex0 - pad, ey0 - pad, ex1 + pad, ey1 + pad
    ew, eh = ex1 - ex0, ey1 - ey0

    # Map size: the paper's 800 px warehouse gets 8 inches; big layouts grow up to
    # 24 inches wide (or 18 tall) so their cells stay visible in a 150 dpi PNG.
    map_w = min(max(ew / 100.0, 7.0), 24.0)
    map_h = map_w * eh / ew
    max_h = max(9.0, min(eh / 100.0, 18.0))
    if map_h > max_h:
        map_h = max_h
        map_w = map_h * ew / eh
    margin = 0.25
    legend_h = 0.75
    title_h = 0.3 if title else 0.0
    fig_w = max(map_w, 7.0) + 2 * margin
    fig_h = map_h + legend_h + title_h + 2 * margin
    fig = new_figure(figsize=(fig_w, fig_h), dpi=_PNG_DPI)
    ax = fig.add_axes((
        (fig_w - map_w) / 2 / fig_w,
        (margin + legend_h) / fig_h,
        map_w / fig_w,
        map_h / fig_h,
    ))
    ax.set_gid("layout-map")
    ax.set_xlim(ex0, ex1)
    ax.set_ylim(ey1, ey0)  # screen coordinates: y grows down
    ax.set_aspect("equal", adjustable="box")
    ax.set_axis_off()

    pt_per_unit = map_w * 72.0 / ew  # points per layout px
    # Map symbols (zones, arrowheads, chargers, names) scale with the aisle, but never
    # beyond their size in the paper's figure (a 50 px aisle is 34 pt there).
    sym = min(aisle, 34.0 / pt_per_unit)
    lw_scale = min(1.0, max(0.3, sym * pt_per_unit / 34.0))

    # Warehouse outline.
    bx0, by0, bx1, by1 = (float(v) for v in layout["bounds"])
    ax.add_patch(Rectangle((bx0, by0), bx1 - bx0, by1 - by0, facecolor="#fafafa",
                           edgecolor=_WALL_COLOR, lw=2.0 * lw_scale, zorder=0))

    # Storage cells: one collection, slightly inset so neighbours stay apart.
    if cells:
        cx = np.array([float(c["x"]) for c in cells])
        cy = np.array([float(c["y"]) for c in cells])
        cw = np.array([float(c["w"]) for c in cells])
        ch = np.array([float(c["h"]) for c in cells])
        inset = 0.06 * np.minimum(cw, ch)
        verts = np.stack([
            np.stack([cx + inset, cy + inset], axis=1),
            np.stack([cx + cw - inset, cy + inset], axis=1),
            np.stack([cx + cw - inset, cy + ch - inset], axis=1),
            np.stack([cx + inset, cy + ch - inset], axis=1),
        ], axis=1)
        colors = np.where(full, CELL_FULL_COLOR, CELL_EMPTY_COLOR)
        cell_coll = PolyCollection(verts, facecolors=colors, edgecolors="none",
                                   zorder=2, antialiaseds=False)
        cell_coll.set_gid("cells")
        # Vector files of huge layouts would hold one path per cell: embed a bitmap.
        cell_coll.set_rasterized(len(cells) > _VECTOR_CELL_LIMIT)
        ax.add_collection(cell_coll)

        # Per-cell ids, only where they are readable (>= 4.5 pt).
        side_pt = float(np.min(np.minimum(cw, ch) - 2 * inset)) * pt_per_unit
        digits = len(str(max(int(c["id"]) for c in cells)))
        font = min(8.0, 0.42 * side_pt, 1.45 * side_pt / max(digits, 1))
        if font >= 4.5:
            labels = [str(c["id"]) for c in cells]
            if len(cells) <= _TEXT_LABEL_LIMIT:
                for label, x, y, w, h in zip(labels, cx, cy, cw, ch):
                    ax.text(x + w / 2, y + h / 2, label, color="white", fontsize=font,
                            ha="center", va="center_baseline", zorder=3,
                            gid=f"cell-{label}")
            else:
                glyphs = _glyph_labels(labels, cx + cw / 2, cy + ch / 2,
                                       font / pt_per_unit)
                glyphs.set(facecolor="white", edgecolor="none", zorder=3, gid="cell-ids")
                ax.add_collection(glyphs)

    # Highway edges: shafts in one LineCollection, heads in one PolyCollection.
    highway = [i for i, n in enumerate(nodes) if n.get("kind", "highway") != "charger"]
    pos = np.array([[float(n["x"]), float(n["y"])] for n in nodes]).reshape(-1, 2)
    edges = [(int(u), int(v)) for u, v in layout.get("edges", [])]
    edge_set = set(edges)
    zone_r = 0.25 * sym
    head_len = 0.30 * sym
    head_half = 0.12 * sym
    shafts, heads = [], []
    for u, v in edges:
        p, q = pos[u], pos[v]
        d = q - p
        length = float(np.hypot(*d))
        if length <= 0:
            continue
        t = d / length
        nrm = np.array([-t[1], t[0]])
        off = nrm * 0.14 * sym if (v, u) in edge_set else 0.0
        gap = min(zone_r + 0.08 * sym, 0.3 * length)
        a = p + t * gap + off
        b = q - t * gap + off
        shafts.append([a, b - t * head_len * 0.6])
        heads.append([b, b - t * head_len + nrm * head_half, b - t * head_len - nrm * head_half])
    if shafts:
        shaft_coll = LineCollection(shafts, colors=_EDGE_COLOR, linewidths=1.4 * lw_scale,
                                    zorder=4, capstyle="butt")
        shaft_coll.set_gid("edges")
        head_coll = PolyCollection(heads, facecolors=_EDGE_COLOR, edgecolors="none",
                                   zorder=4)
        for coll in (shaft_coll, head_coll):
            coll.set_rasterized(len(shafts) > _VECTOR_CELL_LIMIT)
            ax.add_collection(coll)

    # Chargers: the spur (two-way, dashed) and a battery symbol.
    charger_ids = [int(i) for i in layout.get("chargers", [])] or [
        i for i, n in enumerate(nodes) if n.get("kind") == "charger"]
    spurs = [(int(c), int(n)) for c, n in layout.get("spurs", [])]
    bat_w, bat_h = 0.42 * sym, 0.22 * sym
    if spurs:
        spur_lines = []
        for c, n in spurs:
            p, q = pos[c], pos[n]
            d = q - p
            length = float(np.hypot(*d))
            if length <= 0:
                continue
            t = d / length
            spur_lines.append([p, q - t * min(zone_r, 0.5 * length)])
        spur_coll = LineCollection(spur_lines, colors=_CHARGER_COLOR,
                                   linewidths=1.4 * lw_scale, linestyles=(0, (3, 2)),
                                   zorder=3)
        spur_coll.set_gid("spurs")
        ax.add_collection(spur_coll)
    if charger_ids:
        bodies, nubs = [], []
        for c in charger_ids:
            x, y = pos[c]
            bodies.append(Rectangle((x - bat_w / 2, y - bat_h / 2), bat_w, bat_h))
            nubs.append(Rectangle((x + bat_w / 2, y - bat_h / 5), bat_w / 7, 2 * bat_h / 5))
        body_coll = PatchCollection(bodies, facecolors=_CHARGER_COLOR, edgecolors="#1b5e20",
                                    linewidths=0.8 * lw_scale, zorder=5)
        body_coll.set_gid("chargers")
        ax.add_collection(body_coll)
        ax.add_collection(PatchCollection(nubs, facecolors="#1b5e20", edgecolors="none",
                                          zorder=5))

    # Zones: departure = circle with a cross, unloading = double circle.
    departure = [int(i) for i in layout.get("departure", [])]
    unloading = [int(i) for i in layout.get("unloading", [])]
    zone_lw = 1.2 * lw_scale
    if departure:
        circles = [Circle(tuple(pos[i]), zone_r) for i in departure]
        dep = PatchCollection(circles, facecolors="white", edgecolors=_ZONE_COLOR,
                              linewidths=zone_lw, zorder=6)
        dep.set_gid("departure")
        ax.add_collection(dep)
        d = zone_r / math.sqrt(2)
        crosses = []
        for i in departure:
            x, y = pos[i]
            crosses += [[(x - d, y - d), (x + d, y + d)], [(x - d, y + d), (x + d, y - d)]]
        ax.add_collection(LineCollection(crosses, colors=_ZONE_COLOR, linewidths=zone_lw,
                                         zorder=7))
    if unloading:
        outer = [Circle(tuple(pos[i]), zone_r * 1.05) for i in unloading]
        inner = [Circle(tuple(pos[i]), zone_r * 0.58) for i in unloading]
        unl = PatchCollection(outer, facecolors="white", edgecolors=_ZONE_COLOR,
                              linewidths=zone_lw, zorder=6)
        unl.set_gid("unloading")
        ax.add_collection(unl)
        ax.add_collection(PatchCollection(inner, facecolors="none", edgecolors=_ZONE_COLOR,
                                          linewidths=zone_lw, zorder=7))
    plain = [i for i in highway if i not in set(departure) | set(unloading)]
    if plain:
        ax.add_collection(PatchCollection(
            [Circle(tuple(pos[i]), 0.07 * sym) for i in plain],
            facecolors=_EDGE_COLOR, edgecolors="none", zorder=6))

    # Node names, in the upper-left corner of the aisle crossing.
    node_font = min(8.5, 0.26 * sym * pt_per_unit)
    if node_font >= 4.5 and len(nodes) <= 2000:
        # Upper-left of the node, just clear of its zone symbol; flipped to the
        # right when a long name would run into the west wall.
        off = 0.2 * sym
        char_w = 0.62 * node_font / pt_per_unit
        for i in highway:
            x, y = pos[i]
            name = str(nodes[i].get("name", i))
            left = x - off - len(name) * char_w >= bx0 + 0.05 * sym or x - off > bx1
            ax.text(x - off if left else x + off, y - off, name, fontsize=node_font,
                    ha="right" if left else "left", va="bottom", color="#111111",
                    fontweight="bold", zorder=8)
        # Charger names right of the battery, or left of it at the east edge; beside the
        # west and east walls (charger_walls = "all"), above it, clear of the crossing.
        for c in charger_ids:
            x, y = pos[c]
            name = str(nodes[c].get("name", c))
            if x < bx0 or x > bx1:
                ax.text(x, y - bat_h / 2 - 0.05 * sym, name, fontsize=node_font * 0.85, ha="center",
                        va="bottom", color="#1b5e20", zorder=8)
                continue
            gap = bat_w / 2 + bat_w / 7 + 0.08 * sym
            right = x + gap + 0.85 * len(name) * char_w <= ex1
            ax.text(x + gap if right else x - bat_w / 2 - 0.08 * sym, y, name,
                    fontsize=node_font * 0.85, ha="left" if right else "right",
                    va="center", color="#1b5e20", zorder=8)

    # Legend under the map.
    proxies = [
        Rectangle((0, 0), 1, 1, facecolor=CELL_EMPTY_COLOR, edgecolor="none"),
        Rectangle((0, 0), 1, 1, facecolor=CELL_FULL_COLOR, edgecolor="none"),
        Line2D([], []), Line2D([], []), Line2D([], []), Line2D([], []),
    ]
    labels = ["Storage cell, empty", "Storage cell, full", "Highway (one-way)",
              "Departure zone", "Unloading zone", "Charger and spur"]
    handler_map = {proxies[2]: _GlyphHandler("edge"), proxies[3]: _GlyphHandler("departure"),
                   proxies[4]: _GlyphHandler("unloading"), proxies[5]: _GlyphHandler("charger")}
    ncol = 3 if fig_w < 9.5 else 6
    fig.legend(proxies, labels, handler_map=handler_map, loc="center",
               bbox_to_anchor=(0.5, (margin + legend_h / 2) / fig_h), ncol=ncol,
               frameon=False, handlelength=2.4, handleheight=1.2, columnspacing=1.8)
    if title:
        fig.text(0.5, 1 - (margin / 2 + title_h / 2) / fig_h, title, ha="center",
                 va="center", fontsize=12)
    return fig, ax


def draw_layout(layout: Mapping[str, Any], path: str | os.PathLike[str], *,
                cells_full: Sequence[int] | None = None,
                title: str | None = None) -> Path:
    """Draw a warehouse layout like the paper's Fig. 2.

    The figure shows the warehouse outline; the storage cells as squares with
    their ids (red when full, black when empty); the directed highway edges as
    arrows with the node names; departure zones as a circle with a cross,
    unloading zones as a double circle; the chargers as battery symbols joined to
    their node by the dashed two-way spur; and a legend. On big layouts the
    per-cell ids (and node names) are left out when they would be too small to
    read; everything else is drawn with one collection per kind, so thousands of
    cells stay fast.

    Args:
        layout: The layout JSON dict (see "Layout JSON" in
            ``docs/replay-format.md``), e.g. ``multibots.layout_json("paper")``.
        path: Output file. The suffix picks the format: ``.png`` (150 dpi),
            ``.svg`` or ``.pdf``. Missing parent folders are created.
        cells_full: One 0/1 per cell, in the order of ``layout["cells"]``
            (1 = holds goods, drawn red). Default: every cell empty.
        title: Optional title above the map.

    Returns:
        The path written.

    Raises:
        ValueError: The suffix is not a supported format, or ``cells_full`` does
            not have one 0/1 per cell.
        KeyError: The layout lacks a required key.
    """
    with matplotlib.rc_context(_RC):
        fig, _ = _layout_figure(layout, cells_full, title)
        return save_atomic(fig, path, dpi=fig.dpi)
