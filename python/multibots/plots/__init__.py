"""Publication figures for MultiBots, drawn with matplotlib's Agg backend.

Three entry points:

* :func:`draw_layout` draws a warehouse layout like the paper's Fig. 2: storage
  cells with their ids (red when full, black when empty), the one-way highway
  edges, departure and unloading zones and the chargers on their spurs.
* :func:`draw_paper_figures` draws the paper's Fig. 6-8 (task time T, collisions S
  and charging count C against the number of robots N) from the 30 runs of the
  paper's experiment.
* :func:`draw_strategy_comparison` draws one figure per metric of a strategy
  study: the mean against N per strategy, with a shaded 95% confidence band.

Everything a layout figure shows comes from the layout JSON dict described in
``docs/replay-format.md``; no coordinate is hard-coded, so any layout the engine
produces draws, from the paper's 80 cells to generated layouts of thousands.

The module never imports :mod:`matplotlib.pyplot`: figures are plain
:class:`matplotlib.figure.Figure` objects on an Agg canvas, so nothing needs a
display, no global figure registry fills up, and the caller's pyplot backend is
left alone. Every file is written atomically, through ``multibots._io``.
"""

from multibots.plots._common import CELL_EMPTY_COLOR, CELL_FULL_COLOR
from multibots.plots.layout import _layout_figure, draw_layout  # noqa: F401 - _layout_figure: for the tests
from multibots.plots.paper import draw_paper_figures
from multibots.plots.strategies import draw_strategy_comparison

__all__ = [
    "draw_layout",
    "draw_paper_figures",
    "draw_strategy_comparison",
    "CELL_FULL_COLOR",
    "CELL_EMPTY_COLOR",
]
