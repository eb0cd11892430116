"""``multibots layout``: draw a layout (the group's own command), ``layout generate`` and
``layout check``."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any, Optional, Union

import typer

from multibots._text import shown
from multibots.cli._common import FlagError, finite_flag, parse_cells, whole_flag
from multibots.exceptions import InputError, ScenarioError
from multibots.layouts import MAX_GROUPS

__all__ = ["app"]

app = typer.Typer(help="Draw or generate warehouse layouts.", invoke_without_command=True, no_args_is_help=False)


@app.callback(invoke_without_command=True)
def layout(
    ctx: typer.Context,
    out: Path = typer.Option(Path("layout.png"), "--out", help="Figure file: .png, .svg or .pdf."),
    name: str = typer.Option("paper", "--layout", help="Layout to draw: a name or a layout file."),
    goods: Optional[str] = typer.Option(
        None, "--goods", metavar="CELLS", help="Cells to draw full (red), such as 11,8,39.", show_default=False
    ),
    as_json: bool = typer.Option(False, "--json", help="Print the layout JSON instead of drawing."),
) -> None:
    """Draw a layout like the paper's Fig. 2: cells, highways, zones and chargers."""
    if ctx.invoked_subcommand is not None:
        return
    from multibots.simulation import layout_json

    data = layout_json(name)
    if as_json:
        print(json.dumps(data))
        return
    if out.suffix.lower() not in (".png", ".svg", ".pdf"):
        raise InputError(f"--out = '{out}': the figure must be .png, .svg or .pdf")
    full = None
    if goods is not None:
        cells = parse_cells(goods)
        n = len(data["cells"])
        bad = [c for c in cells if not 0 <= c < n]
        if bad:
            raise InputError(f"--goods = {bad[0]}: cell id out of range 0..{n - 1}")
        wanted = set(cells)
        full = [1 if i in wanted else 0 for i in range(n)]
    from multibots.plots import draw_layout

    path = draw_layout(data, out, cells_full=full)
    print(f"wrote {path}")


# What a size flag past its limit means.
_TOO_LARGE = "layout too large: "
# Engine field names of the generator and the flags that set them, for its error messages.
_FLAGS = {
    "group_rows": "--group-rows",
    "group_cols": "--group-cols",
    "group_width": "--group-size",
    "group_height": "--group-size",
    "aisle": "--aisle",
    "cell": "--cell",
    "chargers": "--chargers",
    "spur": "--spur",
    "unloading_rows": "--unloading-rows",
    "aisles": "--aisles",
    "charger_walls": "--charger-walls",
}


def _rows_or_auto(value: Any) -> Union[int, str]:
    """``--unloading-rows``: ``auto`` or a whole number."""
    text = str(value).strip()
    if text == "auto":
        return "auto"
    if not text.lstrip("-").isdigit():
        raise FlagError(f'--unloading-rows = {shown(value)!r}: "auto" or a whole number')
    return whole_flag("--unloading-rows", 0, MAX_GROUPS, _TOO_LARGE)(value)


@app.command("generate")
def generate(
    out: Path = typer.Option(Path("layout.toml"), "--out", help="Layout file to write (TOML)."),
    group_rows: int = typer.Option(2, "--group-rows", help="Rows of storage groups (R).",
                                   parser=whole_flag("--group-rows", 0, MAX_GROUPS, _TOO_LARGE), metavar="INT"),
    group_cols: int = typer.Option(5, "--group-cols", help="Columns of storage groups (C).",
                                   parser=whole_flag("--group-cols", 0, MAX_GROUPS, _TOO_LARGE), metavar="INT"),
    group_size: str = typer.Option("2x4", "--group-size", metavar="SIZE",
                                   help="Cells across x down a group (across: 1 or 2)."),
    aisle: float = typer.Option(50.0, "--aisle", help="Aisle width, px.", parser=finite_flag("--aisle"),
                                metavar="NUMBER"),
    cell: float = typer.Option(50.0, "--cell", help="Side of a storage cell, px.", parser=finite_flag("--cell"),
                               metavar="NUMBER"),
    chargers: Optional[int] = typer.Option(
        None, "--chargers", help="Chargers, spread evenly over the crossings of the walls --charger-walls names "
        "(default C + 1).", show_default=False,
        parser=whole_flag("--chargers", 0, 4 * (MAX_GROUPS + 1), _TOO_LARGE), metavar="INT",
    ),
    charger_walls: str = typer.Option("top", "--charger-walls", metavar="NAME",
                                      help="Walls with chargers, on spurs out of the "
                                      "warehouse, at crossings first, then midway between two of the top and bottom "
                                      "rows: top (the paper's, at most 2C + 1), top-bottom (at most 2(2C + 1)) or all "
                                      "(also left and right: at most 2(2C + 1) + 2(R + 1))."),
    spur: float = typer.Option(40.0, "--spur", help="Length of a charger's spur, px.", parser=finite_flag("--spur"),
                               metavar="NUMBER"),
    name: str = typer.Option("generated", "--name", metavar="TEXT", help="The layout's name."),
    unloading_rows: str = typer.Option(
        "auto", "--unloading-rows", help="Rows of crossings that are unloading zones, spread from the bottom up; "
        "auto: one per four rows of groups.", parser=_rows_or_auto, metavar="N|auto",
    ),
    aisles: str = typer.Option("auto", "--aisles", metavar="NAME",
                               help="Horizontal aisle directions: paper (every row east but "
                               "the bottom one), alternate (rows alternate east and west), or auto (paper up to "
                               "two rows of groups, alternate beyond)."),
) -> None:
    """Generate a grid warehouse layout file (the defaults give the paper's layout); every
    field of a scenario's [layout_generate] has its flag."""
    from multibots._io import atomic_write_text
    from multibots.layouts import check_layout_text, generate_layout

    try:
        text = generate_layout(group_rows, group_cols, group_size, aisle, cell, chargers, spur, name, unloading_rows,
                              aisles, charger_walls)
    except ScenarioError as e:
        # The engine names its field; the user set a flag, with this text.
        m = re.fullmatch(r"layout\.(\w+)(?: = (.*?))?: (.*)", str(e))
        if m is None or m.group(1) not in _FLAGS:
            raise
        flag = _FLAGS[m.group(1)]
        value = shown(group_size) if flag == "--group-size" else m.group(2)
        raise ScenarioError(f"{flag}: {m.group(3)}" if value is None else f"{flag} = {value}: {m.group(3)}") from None
    # Checked before writing: a layout the engine would refuse never reaches the disk.
    data = check_layout_text(text, str(out))
    path = atomic_write_text(out, text)
    highway = sum(1 for n in data["nodes"] if n["kind"] == "highway")
    print(
        f"wrote {path}: {highway} crossings, {len(data['edges'])} edges, {len(data['cells'])} cells, "
        f"{len(data['chargers'])} chargers"
    )


@app.command("check")
def check(path: Path = typer.Argument(..., help="A layout file (TOML).")) -> None:
    """Check a layout file: names, numbers, and that robots can reach and leave everything."""
    from multibots.layouts import check_layout_file

    data = check_layout_file(path)
    print(f"{path}: ok ({len(data['nodes'])} nodes, {len(data['edges'])} edges, {len(data['cells'])} cells)")
