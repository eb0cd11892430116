"""What the commands share: parsing of the quick-run flags, the exit codes, and turning an
exception into one line on stderr and its exit code."""

from __future__ import annotations

import math
import os
import sys
from pathlib import Path
from typing import Any, Callable, NoReturn, Optional

import typer

from multibots import _core
from multibots._io import load_toml, read_input
from multibots._text import inert, shown
from multibots.exceptions import EngineError, InputError, MissingExtraError, MultibotsError, RenderError
from multibots.scenario import Scenario

__all__ = [
    "ALLOW_CODE",
    "EXIT_INCOMPLETE",
    "RULES",
    "TRAFFIC",
    "EXIT_INPUT",
    "EXIT_INTERNAL",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_CODES_HELP",
    "FlagError",
    "MAX_WORKERS",
    "check_code",
    "finite_flag",
    "named_allocator",
    "parse_cells",
    "parse_names",
    "parse_number",
    "quick_scenario",
    "run_app",
    "whole_flag",
]

#: The run (or the command) did what it was asked.
EXIT_OK = 0
#: An internal error: a bug, or an environment the command cannot run in (no browser).
EXIT_INTERNAL = 1
#: Bad input: a scenario, layout, option or file the command cannot use.
EXIT_INPUT = 2
#: ``multibots run``: the run did not complete (the step limit came first, or the fleet
#: gridlocked, stranded or stalled).
EXIT_INCOMPLETE = 3
#: Interrupted by Ctrl-C (SIGINT).
EXIT_INTERRUPTED = 130

EXIT_CODES_HELP = (
    "Exit codes: 0 done; 1 internal error; 2 bad input (one line on stderr naming the field and the value); "
    "3 the run did not complete (run); 130 interrupted (Ctrl-C)."
)

PROG = "multibots"


def parse_cells(value: str, flag: str = "--goods") -> list[int]:
    """Parses ``11,8,39`` into cell ids."""
    try:
        cells = [int(v) for v in value.split(",") if v.strip() != ""]
    except ValueError:
        raise InputError(f"{flag} = {value!r}: not a comma-separated list of cell ids") from None
    if not cells:
        raise InputError(f"{flag} = {value!r}: the task list is empty")
    return cells


def parse_names(value: str, flag: str = "--starts") -> list[str]:
    """Parses ``A,B,C`` into node names."""
    names = [v.strip() for v in value.split(",")]
    if not value.strip() or any(not n for n in names):
        raise InputError(f"{flag} = {value!r}: not a comma-separated list of node names")
    return names


#: The engine's limits (crates/multibots-core/src/input/limits.rs, docs/limits.md) for flags that
#: would otherwise reach it as out-of-range integers.
MAX_ROBOTS: int = _core.LIMITS["robots"]
MAX_STEPS: int = _core.LIMITS["steps"]


def parse_number(value: Optional[str], flag: str, kind: type, most: Optional[float] = None) -> Any:
    """A numeric flag that arrived as text (so that a bad one is reported with its value);
    ``most``: the largest value allowed (docs/limits.md)."""
    if value is None:
        return None
    what = "an integer" if kind is int else "a number"
    try:
        number = kind(value)
    except ValueError:
        raise InputError(f"{flag} = {shown(value)!r}: not {what}") from None
    if kind is float and not math.isfinite(number):
        raise InputError(f"{flag} = {shown(value)}: must be a finite number")
    if most is not None and number > most:
        raise InputError(f"{flag} = {shown(value)}: at most {most:,} (docs/limits.md)")
    return number


class FlagError(MultibotsError):
    """A flag's value refused where the flag is read (exit code 2). Not a ValueError: the
    command-line parser would wrap one in its own words."""


def finite_flag(flag: str) -> Callable[[Any], float]:
    """The parser of a float flag: a finite number, or a one-line error naming the flag and
    the value (NaN and infinity never reach a command)."""

    def parse(value: Any) -> float:
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise FlagError(f"{flag} = {shown(value)!r}: not a number") from None
        if not math.isfinite(number):
            raise FlagError(f"{flag} = {shown(value)}: must be a finite number")
        return number

    return parse


def whole_flag(flag: str, least: int, most: int, why: str = "") -> Callable[[Any], int]:
    """The parser of an integer flag from ``least`` to ``most`` (``why``: what passing the
    upper limit means, such as ``"layout too large: "``)."""

    def parse(value: Any) -> int:
        if isinstance(value, int) and not isinstance(value, bool):
            number = value
        else:
            try:
                number = int(str(value).strip())
            except ValueError:
                raise FlagError(f"{flag} = {shown(value)!r}: not an integer") from None
        if number < least:
            raise FlagError(f"{flag} = {number}: must be {least} or more")
        if number > most:
            raise FlagError(f"{flag} = {shown(number)}: {why}at most {most:,} (docs/limits.md)")
        return number

    return parse


#: Threads or processes a command may start (``--workers``).
MAX_WORKERS = 1024


def named_allocator(path: Path) -> Optional[str]:
    """The ``allocator`` a scenario file names, read as plain TOML before anything validates
    the file (validating imports the strategy, which runs its code); None if it names none or
    cannot be read (the file's own checks report that, after this one)."""
    try:
        data = load_toml(read_input(path, InputError, "scenario file"), str(path), InputError)
    except InputError:
        return None
    name = data.get("allocator")
    return name if isinstance(name, str) else None


def check_code(path: Optional[Path], allow: bool, overridden: bool = False) -> None:
    """Refuses a scenario file that names Python code unless the user allowed it; call it
    before the file is loaded.

    ``allocator = "module:Class"`` imports and runs that code (``"os:abort"`` would abort), so
    a file from elsewhere must not run code by being opened: the command line asks for
    ``--allow-code`` (or ``MULTIBOTS_ALLOW_CODE=1``). The Python API does not ask: code that
    calls it already runs with the user's trust. ``overridden``: ``--allocator`` replaces the
    file's choice.
    """
    if path is None or allow or overridden or os.environ.get("MULTIBOTS_ALLOW_CODE") == "1":
        return
    from multibots.strategies import is_python_allocator

    name = named_allocator(path)
    if name is not None and is_python_allocator(name):
        raise InputError(
            f"allocator = {shown(name)!r} in {shown(path)}: this scenario file names Python code, which "
            "would run; add --allow-code if you trust the file"
        )


def quick_scenario(
    scenario: Optional[Path],
    robots: Optional[str],
    goods: Optional[str],
    starts: Optional[str],
    unload: Optional[str],
    margin: Optional[str],
    step_limit: Optional[str],
    rules: Optional[str] = None,
    traffic: Optional[str] = None,
) -> Scenario:
    """A scenario from a file, from the quick-run flags on the paper layout, or a file with
    flags on top (``run`` and ``view --live`` share these rules)."""
    n = parse_number(robots, "--robots", int, MAX_ROBOTS)
    if n is not None and n < 1:
        raise InputError(f"--robots = {n}: must be at least 1")
    changes: dict[str, Any] = {}
    if n is not None:
        changes["robots"] = n
    if goods is not None:
        changes["tasks"] = parse_cells(goods)
    if starts is not None:
        changes["starts"] = parse_names(starts)
    if unload is not None:
        changes["unload"] = unload
    m = parse_number(margin, "--margin", float)
    if m is not None:
        changes["collision"] = {"margin": m}
    limit = parse_number(step_limit, "--step-limit", int, MAX_STEPS)
    if limit is not None:
        changes["step_limit"] = limit
    if rules is not None:
        changes["rules"] = rules
    if traffic is not None:
        changes["traffic"] = traffic
    if scenario is not None:
        base = Scenario.from_toml(scenario)
        return base.replace(**changes) if changes else base
    if "tasks" not in changes:
        raise InputError("give a SCENARIO.toml or the quick-run flags (at least --goods)")
    return Scenario.from_dict({"layout": "paper", **changes})


# The quick-run flags, shared by `run` and `view --live`. Numbers arrive as text so that a bad
# one is reported with its value.
ROBOTS = typer.Option(None, "--robots", help="Number of robots N.", show_default=False, metavar="N")
GOODS = typer.Option(None, "--goods", metavar="CELLS",
                     help="Cells to fetch, in order, such as 11,8,39.", show_default=False)
STARTS = typer.Option(None, "--starts", metavar="NODES",
                      help="Start nodes, such as A,B,C (default A, B, C, ...).", show_default=False)
UNLOAD = typer.Option(None, "--unload", metavar="NODE",
                      help="Unloading zone: a node name, such as M.", show_default=False)
MARGIN = typer.Option(None, "--margin", help="Collision margin, px (default 0).", show_default=False, metavar="PX")
TRAFFIC = typer.Option(
    None, "--traffic", metavar="NAME",
    help="Traffic policy: auto (the default: wait for the paper's fleets, reserve for "
    "fleets spread along the aisles), wait (the paper's collision waiting), gate or reserve (docs/traffic.md).",
    show_default=False,
)
RULES = typer.Option(
    None, "--rules", metavar="NAME",
    help="Rule set: paper (docs/model.md, the default) or original (the authors' code).",
    show_default=False,
)
ALLOW_CODE = typer.Option(
    False, "--allow-code", help="Let a scenario file that names a Python strategy (allocator = \"module:Class\") "
    "run it: only for files you trust (docs/strategies.md).",
)
STEP_LIMIT = typer.Option(
    None, "--step-limit", help="Steps before the run ends incomplete (default 100000).", show_default=False,
    metavar="STEPS",
)


def _fail(message: str, code: int, prefix: str = "error: ") -> NoReturn:
    line = inert(message)  # one line of printable text, whatever the message held
    print(f"{PROG}: {prefix}{line}", file=sys.stderr)
    sys.exit(code)


class _ReaderMayLeave:
    """Standard output for a reader that may stop reading (``multibots run ... | head -1``):
    once the pipe is closed, the rest goes to the null device and the command ends with its
    own exit code (3 for a run that stranded, say), not the internal error's."""

    def __init__(self, stream: Any) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        try:
            written = self._stream.write(text)
            return len(text) if written is None else int(written)
        except BrokenPipeError:
            self._drop()
            return len(text)

    def flush(self) -> None:
        try:
            self._stream.flush()
        except BrokenPipeError:
            self._drop()

    def _drop(self) -> None:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, self._stream.fileno())
        os.close(null)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def run_app(app: typer.Typer, argv: Optional[list[str]] = None) -> None:
    """Runs ``app`` and turns every error into one line on stderr and an exit code.

    MultiBots errors are the user's (exit 2), except :class:`EngineError` (a bug) and
    :class:`RenderError` (no browser or encoder), which exit 1; a missing extra is named by
    its line; anything else is an internal error, with the traceback only when
    ``MULTIBOTS_DEBUG`` is set.
    """
    out = sys.stdout
    if out is not None and not isinstance(out, _ReaderMayLeave):
        sys.stdout = _ReaderMayLeave(out)
    try:
        _run_app(app, argv)
    finally:
        if sys.stdout is not None:
            sys.stdout.flush()
        sys.stdout = out


def _run_app(app: typer.Typer, argv: Optional[list[str]]) -> None:
    try:
        rv = app(args=argv, prog_name=PROG, standalone_mode=False)
    except MissingExtraError as e:
        print(str(e), file=sys.stderr)  # the line names the extra and the command that installs it
        sys.exit(EXIT_INPUT)
    except EngineError as e:
        _fail(str(e), EXIT_INTERNAL, "internal error: ")
    except RenderError as e:
        _fail(str(e), EXIT_INTERNAL)
    except MultibotsError as e:
        _fail(str(e), EXIT_INPUT)
    except (KeyboardInterrupt, typer.Abort):
        _fail("interrupted", EXIT_INTERRUPTED, "")
    except typer.Exit as e:
        sys.exit(e.exit_code)
    except BrokenPipeError:  # a pipe other than standard output: the reader left
        sys.exit(EXIT_INTERNAL)
    except Exception as e:
        # Usage errors of the (vendored) click parser carry these two attributes.
        if hasattr(e, "format_message") and isinstance(getattr(e, "exit_code", None), int):
            if type(e).__name__ == "NoArgsIsHelpError":  # `multibots` alone: the help, as click shows it
                print(e.format_message(), file=sys.stderr)
                sys.exit(EXIT_INPUT)
            _fail(e.format_message(), EXIT_INPUT)
        if os.environ.get("MULTIBOTS_DEBUG"):
            raise
        _fail(f"{type(e).__name__}: {e} (set MULTIBOTS_DEBUG=1 for the traceback)", EXIT_INTERNAL, "internal error: ")
    except BaseException as e:  # PyO3's PanicException derives from BaseException
        if isinstance(e, (SystemExit, GeneratorExit)) or os.environ.get("MULTIBOTS_DEBUG"):
            raise
        _fail(f"{type(e).__name__}: {e}", EXIT_INTERNAL, "internal error: ")
    if rv == EXIT_INTERRUPTED:  # typer turns Ctrl-C into a silent exit code
        _fail("interrupted", EXIT_INTERRUPTED, "")
    if isinstance(rv, int) and rv != 0:
        sys.exit(rv)
