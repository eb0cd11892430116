"""The ``multibots`` command line: one module per command, sharing :mod:`._common`.

=========  ===============================================================
``run``      one scenario: its T, S, C (``cli/run.py``)
``paper``    the paper's 30 runs, table and figures (``cli/paper.py``)
``compare``  strategies against each other (``cli/compare.py``)
``sweep``    a study over any scenario fields (``cli/sweep.py``)
``capacity`` how much demand a warehouse and fleet carry (``cli/capacity.py``)
``layout``   draw, generate and check layouts (``cli/layout.py``)
``lorr``     a League of Robot Runners problem, scored as the competition does (``cli/lorr.py``)
``view``     the browser viewer (``cli/view.py``)
``render``   a replay to MP4 or GIF (``cli/render.py``, the ``render`` extra)
=========  ===============================================================

Exit codes: 0 done; 1 internal error; 2 bad input (one line on stderr naming the field and
the value); 3 ``run``: the run did not complete (incomplete, gridlock, stranded or stalled); 130 interrupted (Ctrl-C).
"""

from __future__ import annotations

from typing import Optional

import typer

from multibots.cli import capacity, compare, layout, lorr, paper, render, run, sweep, view
from multibots.cli._common import EXIT_CODES_HELP, run_app

__all__ = ["app", "main"]

app = typer.Typer(
    name="multibots",
    help="Simulate warehouse robot fleets with the MultiBots paper's model.",
    epilog=EXIT_CODES_HELP,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


def _version(value: bool) -> None:
    if value:
        import multibots

        print(f"multibots {multibots.__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(
        False, "--version", help="Print the version and exit.", is_eager=True, callback=_version
    ),
) -> None:
    """Simulate warehouse robot fleets with the MultiBots paper's model."""


app.command("run", epilog=EXIT_CODES_HELP)(run.run)
app.command("paper")(paper.paper)
app.command("compare")(compare.compare)
app.command("sweep")(sweep.sweep)
app.command("capacity")(capacity.capacity)
app.add_typer(layout.app, name="layout")
app.command("lorr")(lorr.lorr)
app.command("view")(view.view)
app.command("render")(render.render)


def main(argv: Optional[list[str]] = None) -> None:
    """Entry point: runs the app and turns errors into one line and an exit code."""
    run_app(app, argv)
