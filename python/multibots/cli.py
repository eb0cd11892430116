"""The ``multibots`` command line.

Exit codes: 0 success, 2 bad input (one line on stderr naming the field and the value),
1 internal error.
"""

from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path
from typing import Any, Optional

import typer

from multibots.exceptions import EngineError, MultibotsError
from multibots.scenario import Scenario

__all__ = ["app", "main", "parse_cells", "parse_names", "BadInput", "quick_scenario"]

app = typer.Typer(
    name="multibots",
    help="Simulate warehouse robot fleets with the MultiBots paper's model.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


class BadInput(Exception):
    """Bad input from the command line: printed as one line, exit code 2."""


def parse_cells(value: str, flag: str = "--goods") -> list[int]:
    """Parses ``11,8,39`` into cell ids."""
    try:
        cells = [int(v) for v in value.split(",") if v.strip() != ""]
    except ValueError:
        raise BadInput(f"{flag} = {value!r}: not a comma-separated list of cell ids") from None
    if not cells:
        raise BadInput(f"{flag} = {value!r}: the task list is empty")
    return cells


def parse_names(value: str, flag: str = "--starts") -> list[str]:
    """Parses ``A,B,C`` into node names."""
    names = [v.strip() for v in value.split(",")]
    if not value.strip() or any(not n for n in names):
        raise BadInput(f"{flag} = {value!r}: not a comma-separated list of node names")
    return names


def _number(value: Optional[str], flag: str, kind: type) -> Any:
    if value is None:
        return None
    what = "an integer" if kind is int else "a number"
    try:
        number = kind(value)
    except ValueError:
        raise BadInput(f"{flag} = {value!r}: not {what}") from None
    if not math.isfinite(number):
        raise BadInput(f"{flag} = {value!r}: must be a finite number")
    return number


def quick_scenario(
    scenario: Optional[Path],
    robots: Optional[str],
    goods: Optional[str],
    starts: Optional[str],
    unload: Optional[str],
    margin: Optional[str],
    step_limit: Optional[str],
) -> Scenario:
    """A scenario from a file, from the quick-run flags, or a file with flags on top.

    Numeric flags arrive as text so that a bad one is reported with its value.
    """
    robots = _number(robots, "--robots", int)
    margin = _number(margin, "--margin", float)
    step_limit = _number(step_limit, "--step-limit", int)
    changes: dict[str, Any] = {}
    if robots is not None:
        changes["robots"] = robots
    if goods is not None:
        changes["tasks"] = parse_cells(goods)
    if starts is not None:
        changes["starts"] = parse_names(starts)
    if unload is not None:
        changes["unload"] = unload
    if margin is not None:
        changes["collision"] = {"margin": margin}
    if step_limit is not None:
        changes["step_limit"] = step_limit
    if scenario is not None:
        base = Scenario.from_toml(scenario)
        return base.replace(**changes) if changes else base
    if "tasks" not in changes:
        raise BadInput("give a SCENARIO.toml or the quick-run flags (at least --goods)")
    return Scenario.from_dict({"layout": "paper", **changes})


# Typer options shared by `run` and `view --live`.
ROBOTS = typer.Option(None, "--robots", help="Number of robots N.", show_default=False, metavar="N")
GOODS = typer.Option(None, "--goods", help="Cells to fetch, in order, such as 11,8,39.", show_default=False)
STARTS = typer.Option(None, "--starts", help="Start nodes, such as A,B,C (default A, B, C, ...).", show_default=False)
UNLOAD = typer.Option(None, "--unload", help="Unloading zone (default M).", show_default=False)
MARGIN = typer.Option(None, "--margin", help="Collision margin, px (default 0).", show_default=False, metavar="PX")
STEP_LIMIT = typer.Option(None, "--step-limit", help="Steps before the run ends incomplete (default 100000).", show_default=False, metavar="STEPS")


@app.command()
def run(
    scenario: Optional[Path] = typer.Argument(None, help="A scenario file (TOML).", show_default=False),
    robots: Optional[str] = ROBOTS,
    goods: Optional[str] = GOODS,
    starts: Optional[str] = STARTS,
    unload: Optional[str] = UNLOAD,
    margin: Optional[str] = MARGIN,
    step_limit: Optional[str] = STEP_LIMIT,
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object on stdout."),
    record: Optional[Path] = typer.Option(None, "--record", help="Write a replay of every step to this file.", show_default=False),
    allocator: Optional[str] = typer.Option(
        None, "--allocator", help="Task-allocation strategy: a built-in (in-turn, nearest, hungarian, auction, energy-aware, min-cost) or package.module:Class.", show_default=False
    ),
    horizon: Optional[int] = typer.Option(None, "--horizon", help="Lifelong scenarios: steps to run (overrides orders.horizon).", show_default=False),
) -> None:
    """Run one scenario, from a file or from the quick-run flags on the paper layout."""
    from multibots.simulation import simulate

    s = quick_scenario(scenario, robots, goods, starts, unload, margin, step_limit)
    if allocator is not None:
        s = s.replace(allocator=allocator)
    if horizon is not None or s.to_dict().get("orders") is not None:
        from multibots.layouts import run_lifelong

        run_lifelong(s, record=record, as_json=as_json, horizon=horizon)
        return
    result = simulate(s, record=record)
    if as_json:
        print(json.dumps(result.to_dict(), separators=(",", ":")))
        return
    t = "-" if result.T is None else str(result.T)
    print(f"outcome    {result.outcome}")
    print(f"T (steps)  {t}")
    print(f"S          {result.S}")
    print(f"C          {result.C}")
    print(f"delivered  {result.delivered}/{result.goods_total} in {result.steps} steps")
    if result.stranded:
        print(f"stranded   robots {', '.join(map(str, result.stranded))}")
    print()
    print("robot  delivered  distance  waits  S  C  energy used")
    for i in range(len(result.distance)):
        print(
            f"{i:>5}  {result.robot_delivered[i]:>9}  {result.distance[i]:>8.0f}  {result.wait_steps[i]:>5}"
            f"  {result.collisions[i]}  {result.charges[i]}  {result.energy_used[i]:>11.3f}"
        )
    if record is not None:
        print(f"\nreplay written to {record}")


@app.command()
def paper(
    out: Path = typer.Option(Path("out/paper"), "--out", help="Folder for results.csv and the figures."),
    margin: float = typer.Option(0.0, "--margin", help="Collision margin, px (the authors' code used 8)."),
    workers: int = typer.Option(0, "--workers", help="Threads (0: one per core)."),
) -> None:
    """Run the paper's 30 runs (N = 1..6 × TABLE III): table, results.csv, Fig. 6-8."""
    from multibots.experiments.paper import format_paper_table, run_paper, write_paper_csv
    from multibots.plots import draw_paper_figures

    if workers < 0:
        raise BadInput(f"--workers = {workers}: must be 0 or more")
    rows, seconds = run_paper(margin=margin, workers=workers)
    print(format_paper_table(rows))
    print(f"\n30 runs in {seconds * 1000:.1f} ms (wall clock, {workers or os.cpu_count()} threads)")
    csv_path = write_paper_csv(rows, out / "results.csv")
    figures = draw_paper_figures([r.as_dict() for r in rows], out)
    print(f"wrote {csv_path}")
    for f in figures:
        print(f"wrote {f}")


layout_app = typer.Typer(help="Draw or generate warehouse layouts.", invoke_without_command=True, no_args_is_help=False)
app.add_typer(layout_app, name="layout")


@layout_app.callback(invoke_without_command=True)
def layout(
    ctx: typer.Context,
    out: Path = typer.Option(Path("layout.png"), "--out", help="Figure file: .png, .svg or .pdf."),
    name: str = typer.Option("paper", "--layout", help="Layout to draw."),
    goods: Optional[str] = typer.Option(None, "--goods", help="Cells to draw full (red), such as 11,8,39.", show_default=False),
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
        raise BadInput(f"--out = '{out}': the figure must be .png, .svg or .pdf")
    full = None
    if goods is not None:
        cells = parse_cells(goods)
        n = len(data["cells"])
        bad = [c for c in cells if not 0 <= c < n]
        if bad:
            raise BadInput(f"--goods = {bad[0]}: cell id out of range 0..{n - 1}")
        full = [1 if i in set(cells) else 0 for i in range(n)]
    from multibots.plots import draw_layout

    path = draw_layout(data, out, cells_full=full)
    print(f"wrote {path}")


def _register_plugins() -> None:
    from multibots.viewer.cli import register as register_viewer

    register_viewer(app)
    from multibots.strategies.cli import register as register_strategies

    register_strategies(app)
    from multibots.layouts import register as register_layouts

    register_layouts(layout_app)


_register_plugins()


def main(argv: Optional[list[str]] = None) -> None:
    """Entry point: runs the app and turns errors into one line and an exit code."""
    prog = "multibots"
    try:
        rv = app(args=argv, prog_name=prog, standalone_mode=False)
    except BadInput as e:
        _fail(prog, f"error: {e}", 2)
    except EngineError as e:
        _fail(prog, f"internal error: {e}", 1)
    except MultibotsError as e:
        _fail(prog, f"error: {e}", 2)
    except (KeyboardInterrupt, typer.Abort):
        _fail(prog, "interrupted", 130)
    except typer.Exit as e:
        sys.exit(e.exit_code)
    except BrokenPipeError:
        sys.exit(1)
    except Exception as e:  # noqa: BLE001 - the last line of defence: no traceback for users
        # Usage errors of the (vendored) click parser carry these two attributes.
        if hasattr(e, "format_message") and isinstance(getattr(e, "exit_code", None), int):
            _fail(prog, f"error: {e.format_message()}", 2)
        if os.environ.get("MULTIBOTS_DEBUG"):
            raise
        _fail(prog, f"internal error: {type(e).__name__}: {e} (set MULTIBOTS_DEBUG=1 for the traceback)", 1)
    except BaseException as e:  # PyO3's PanicException derives from BaseException
        if isinstance(e, (SystemExit, GeneratorExit)):
            raise
        if os.environ.get("MULTIBOTS_DEBUG"):
            raise
        _fail(prog, f"internal error: {type(e).__name__}: {e}", 1)
    if rv == 130:  # typer turns Ctrl-C into a silent exit code
        _fail(prog, "interrupted", 130)
    if isinstance(rv, int) and rv != 0:
        sys.exit(rv)


def _fail(prog: str, message: str, code: int) -> None:
    print(f"{prog}: {message}", file=sys.stderr)
    sys.exit(code)
