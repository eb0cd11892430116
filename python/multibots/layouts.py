"""Layouts as data: generate layout files, check them, and run lifelong scenarios.

The layout file's schema belongs to the engine (``docs/layout-format.md``); this module only
passes parameters in and text out.

Example:
    >>> text = generate_layout(group_rows=2, group_cols=5, group_size="2x4")
    >>> text.startswith("# MultiBots layout file")
    True
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Optional

from multibots import _core
from multibots._io import atomic_write_text
from multibots.exceptions import ScenarioError

__all__ = ["generate_layout", "parse_group_size", "check_layout_file", "run_lifelong", "lifelong_lines", "register"]

# Engine field names of the generator and the command-line flags that set them.
_FLAGS = {
    "group_rows": "--group-rows",
    "group_cols": "--group-cols",
    "group_width": "--group-size",
    "group_height": "--group-size",
    "aisle": "--aisle",
    "cell": "--cell",
    "chargers": "--chargers",
    "spur": "--spur",
}


def parse_group_size(value: str) -> tuple[int, int]:
    """``"2x4"`` -> (2, 4): cells across and down a storage group."""
    parts = value.lower().replace(" ", "").split("x")
    try:
        w, h = (int(p) for p in parts)
    except ValueError:
        raise ScenarioError(f"--group-size = {value!r}: expected WxH, such as 2x4") from None
    return w, h


def generate_layout(
    group_rows: int = 2,
    group_cols: int = 5,
    group_size: str = "2x4",
    aisle: float = 50.0,
    cell: float = 50.0,
    chargers: Optional[int] = None,
    spur: float = 40.0,
    name: str = "generated",
) -> str:
    """The layout file text of a generated grid warehouse (checked by the engine).

    The defaults are the paper's warehouse; ``chargers`` defaults to one per top-aisle
    crossing (``group_cols + 1``).
    """
    w, h = parse_group_size(group_size)
    params = {
        "group_rows": group_rows,
        "group_cols": group_cols,
        "group_width": w,
        "group_height": h,
        "aisle": float(aisle),
        "cell": float(cell),
        "chargers": group_cols + 1 if chargers is None else chargers,
        "spur": float(spur),
    }
    for key in ("group_rows", "group_cols", "group_width", "group_height", "chargers"):
        if params[key] < 0:
            raise ScenarioError(f"{_FLAGS[key]} = {params[key]}: must be at least 1")
    return _core.generate_layout_toml(json.dumps(params), name)


def check_layout_file(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Reads and checks a layout file; returns its layout JSON (``docs/replay-format.md``)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ScenarioError(f"{p}: no such file") from None
    except (OSError, UnicodeDecodeError) as e:
        raise ScenarioError(f"{p}: cannot read ({e})") from None
    return json.loads(_core.layout_file_json(text, str(p)))


def lifelong_lines(raw: dict[str, Any]) -> list[str]:
    """The lifelong figures of a result dictionary, as aligned lines."""
    ll = raw["lifelong"]

    def opt(v: Any, fmt: str = "{}") -> str:
        return "-" if v is None else fmt.format(v)

    return [
        f"outcome      {raw['outcome']} after {raw['steps']} steps, {len(raw['distance'])} robots",
        f"throughput   {ll['throughput']:.2f} deliveries per 1,000 steps",
        f"orders       {ll['ordered']} = {raw['delivered']} delivered + {ll['in_flight']} in flight"
        f" + {ll['queued']} queued + {ll['waiting']} waiting for stock",
        f"latency      p50 {opt(ll['latency_p50'])}, p95 {opt(ll['latency_p95'])}, p99 {opt(ll['latency_p99'])} steps",
        f"utilisation  {ll['utilisation']:.1%} of robot-steps on orders",
        f"energy       {opt(ll['energy_per_delivery'], '{:.3f}')} per delivery",
        f"S, C         {raw['S']}, {raw['C']}",
    ]


def run_lifelong(scenario: Any, record: Optional[Path] = None, as_json: bool = False, horizon: Optional[int] = None) -> dict[str, Any]:
    """Runs a lifelong scenario and prints its figures (or one JSON object).

    ``horizon`` overrides ``orders.horizon``; it is an error on a scenario without orders.
    """
    if scenario.to_dict().get("orders") is None:
        raise ScenarioError(f"--horizon = {horizon}: only for lifelong scenarios (with [orders])")
    if horizon is not None:
        scenario = scenario.replace(orders={"horizon": horizon})
    raw = _core.simulate(scenario._core, None if record is None else os.fspath(record))
    if as_json:
        out = {k: (v.tolist() if hasattr(v, "tolist") else v) for k, v in raw.items() if k != "state_steps"}
        print(json.dumps(out, separators=(",", ":")))
    else:
        print("\n".join(lifelong_lines(raw)))
        if record is not None:
            print(f"\nreplay written to {record}")
    return raw


def register(layout_app: Any) -> None:
    """Adds ``generate`` and ``check`` to the ``multibots layout`` command group."""
    import typer

    @layout_app.command("generate")
    def generate(
        out: Path = typer.Option(Path("layout.toml"), "--out", help="Layout file to write (TOML)."),
        group_rows: int = typer.Option(2, "--group-rows", help="Rows of storage groups (R)."),
        group_cols: int = typer.Option(5, "--group-cols", help="Columns of storage groups (C)."),
        group_size: str = typer.Option("2x4", "--group-size", help="Cells across x down a group (across: 1 or 2)."),
        aisle: float = typer.Option(50.0, "--aisle", help="Aisle width, px."),
        cell: float = typer.Option(50.0, "--cell", help="Side of a storage cell, px."),
        chargers: Optional[int] = typer.Option(None, "--chargers", help="Chargers along the top aisle (default C + 1).", show_default=False),
        spur: float = typer.Option(40.0, "--spur", help="Length of a charger's spur, px."),
        name: str = typer.Option("generated", "--name", help="The layout's name."),
    ) -> None:
        """Generate a grid warehouse layout file (the defaults give the paper's layout)."""
        try:
            text = generate_layout(group_rows, group_cols, group_size, aisle, cell, chargers, spur, name)
        except ScenarioError as e:
            msg = str(e)
            for field, flag in _FLAGS.items():
                msg = msg.replace(f"layout.{field} =", f"{flag} =")
            raise ScenarioError(msg) from None
        path = atomic_write_text(out, text)
        data = json.loads(_core.layout_file_json(text, str(path)))
        highway = sum(1 for n in data["nodes"] if n["kind"] == "highway")
        print(f"wrote {path}: {highway} crossings, {len(data['edges'])} edges, {len(data['cells'])} cells, {len(data['chargers'])} chargers")

    @layout_app.command("check")
    def check(path: Path = typer.Argument(..., help="A layout file (TOML).")) -> None:
        """Check a layout file: names, numbers, and that robots can reach and leave everything."""
        data = check_layout_file(path)
        print(f"{path}: ok ({len(data['nodes'])} nodes, {len(data['edges'])} edges, {len(data['cells'])} cells)")
