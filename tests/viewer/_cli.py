"""A minimal `multibots` command line with only the viewer's commands (used by the tests
when the main CLI does not register them)."""

import typer

from multibots.viewer.cli import register

app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


@app.callback()
def main() -> None:
    """MultiBots viewer commands."""


register(app)

if __name__ == "__main__":
    app()
