"""What every figure shares: colours, the rc settings, a figure outside pyplot, the atomic save,
and the helpers of the N axis."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator, NullFormatter

from multibots._io import atomic_open

#: Fill colour of a storage cell that holds goods.
CELL_FULL_COLOR = "#d62728"
#: Fill colour of an empty storage cell.
CELL_EMPTY_COLOR = "#000000"

_EDGE_COLOR = "#3b6ea8"
_ZONE_COLOR = "#222222"
_CHARGER_COLOR = "#2ca02c"
_WALL_COLOR = "#444444"
_SERIES_COLORS = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
    "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf",
]
_SERIES_MARKERS = ["o", "s", "^", "D", "v", "P", "X", "<", ">", "h"]

_FORMATS = ("png", "svg", "pdf")
# Up to this many cells, ids are real text (searchable in SVG/PDF); beyond, glyph paths.
_TEXT_LABEL_LIMIT = 600
# Above this many cells (or edges), SVG/PDF embed the cells (edges) as a bitmap.
_VECTOR_CELL_LIMIT = 5000
_PNG_DPI = 150

# Text stays text in SVG and PDF (searchable, editable), files are reproducible.
_RC = {
    "svg.fonttype": "none",
    "svg.hashsalt": "multibots",
    "pdf.fonttype": 42,
    "font.size": 10,
    "axes.titlesize": 11,
    "axes.labelsize": 10,
    "legend.fontsize": 9,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "axes.grid": True,
    "grid.color": "#dddddd",
    "grid.linewidth": 0.6,
    "lines.linewidth": 1.6,
    "lines.markersize": 5,
}


def save_atomic(fig: Figure, path: str | os.PathLike[str], **kwargs: Any) -> Path:
    """Save ``fig`` to ``path`` atomically (``multibots._io``); the format comes from the suffix.

    Args:
        fig: The figure to save.
        path: Target file; its suffix (``.png``, ``.svg`` or ``.pdf``) picks the
            format. The parent folder is created if missing.
        **kwargs: Passed on to :meth:`matplotlib.figure.Figure.savefig`.

    Returns:
        The target path.

    Raises:
        ValueError: The suffix is not a supported format.
        multibots.OutputError: ``path`` is a directory or not a regular file.
    """
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in _FORMATS:
        raise ValueError(
            f"cannot tell the figure format from {str(path)!r}: "
            f"use one of the suffixes {', '.join('.' + f for f in _FORMATS)}"
        )
    metadata = {"png": {"Software": None}, "svg": {"Date": None},
                "pdf": {"CreationDate": None, "ModDate": None}}[fmt]
    with atomic_open(path) as fh:
        fig.savefig(fh, format=fmt, dpi=kwargs.pop("dpi", _PNG_DPI), metadata=metadata, **kwargs)
    return path


def new_figure(**kwargs: Any) -> Figure:
    """A figure on an Agg canvas, outside pyplot's figure registry."""
    fig = Figure(**kwargs)
    FigureCanvasAgg(fig)
    return fig


def is_missing(value: Any) -> bool:
    """True for None and NaN."""
    if value is None:
        return True
    try:
        return math.isnan(float(value))
    except (TypeError, ValueError):
        return True


def as_number(value: Any) -> int | float:
    """N as a number (CSV readers give strings): an int when it is whole."""
    x = float(value)
    return int(x) if x.is_integer() else x


def series_style(i: int) -> dict[str, Any]:
    return {"color": _SERIES_COLORS[i % len(_SERIES_COLORS)],
            "marker": _SERIES_MARKERS[i % len(_SERIES_MARKERS)]}


def int_axis(ax: Any, xs: Iterable[float], log_if_wide: bool = False) -> None:
    """Integer ticks on the x axis, one per N when there are few.

    With ``log_if_wide``, N values spanning a factor of 32 or more (a scaling
    study: 1, 2, 4, ..., 1000 robots) get a logarithmic axis.
    """
    xs = sorted(set(xs))
    log = bool(log_if_wide and xs and xs[0] > 0 and xs[-1] / xs[0] >= 32)
    if log:
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlim(xs[0] / 1.15, xs[-1] * 1.15)
    if xs and len(xs) <= 12 and all(float(x).is_integer() for x in xs):
        ax.set_xticks(xs, [str(int(x)) for x in xs])
    elif not log:
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    if xs and not log:
        span = (xs[-1] - xs[0]) or 1.0
        ax.set_xlim(xs[0] - 0.06 * span, xs[-1] + 0.06 * span)
