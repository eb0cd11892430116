"""What every command shares (cli/_common.py): help, the version, usage errors and exit codes."""

from __future__ import annotations

import subprocess
import sys

import pytest

import multibots
from multibots.cli import _common


@pytest.mark.parametrize(
    "command", [[], ["run"], ["paper"], ["compare"], ["layout"], ["layout", "generate"], ["view"], ["render"]]
)
def test_help_everywhere(cli, command):
    p = cli(*command, "--help")
    assert p.returncode == 0 and "Usage" in p.stdout


def test_no_command_shows_the_help(cli):
    p = cli()
    assert p.returncode == 2
    assert p.stderr.startswith("Usage: multibots") and "Commands:" in p.stderr and "Exit codes:" in p.stderr


def test_usage_errors_are_one_line_exit_2(cli):
    cli.assert_one_line_error(cli("fly"), "No such command 'fly'")
    cli.assert_one_line_error(cli("paper", "--workers", "many"), "--workers")
    cli.assert_one_line_error(cli("paper", "--workers", "-1"), "--workers = -1: must be 0 or more")


def test_version(cli):
    p = cli("--version")
    assert p.returncode == 0 and p.stdout == f"multibots {multibots.__version__}\n"


def test_exit_codes():
    assert (_common.EXIT_OK, _common.EXIT_INTERNAL, _common.EXIT_INPUT, _common.EXIT_INCOMPLETE,
            _common.EXIT_INTERRUPTED) == (0, 1, 2, 3, 130)


def _main_raising(exc: str) -> subprocess.CompletedProcess[str]:
    """Runs the command line's error handling around a command that raises ``exc``."""
    code = (
        "import typer, multibots\n"
        "from multibots.cli._common import run_app\n"
        "app = typer.Typer()\n"
        "@app.command()\n"
        f"def boom() -> None:\n    raise {exc}\n"
        "run_app(app, [])\n"
    )
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize(
    ("exc", "code", "line"),
    [
        ("multibots.ScenarioError('robots = 0: no robot')", 2, "multibots: error: robots = 0: no robot"),
        ("multibots.InputError('--x = 1:\\n two lines')", 2, "multibots: error: --x = 1: two lines"),
        ("multibots.EngineError('a bug')", 1, "multibots: internal error: a bug"),
        ("multibots.RenderError('no Chromium found')", 1, "multibots: error: no Chromium found"),
        ("multibots.MissingExtraError('multibots render', 'render')", 2,
         "multibots render needs the 'render' extra: pip install 'multibots[render]'"),
        ("KeyboardInterrupt", 130, "multibots: interrupted"),
        ("ZeroDivisionError('oops')", 1,
         "multibots: internal error: ZeroDivisionError: oops (set MULTIBOTS_DEBUG=1 for the traceback)"),
    ],
)
def test_each_error_is_one_line_and_its_exit_code(exc, code, line):
    p = _main_raising(exc)
    assert p.returncode == code, (p.stdout, p.stderr)
    assert p.stderr == line + "\n"
