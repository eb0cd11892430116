"""What every test may use: the ``cli`` fixture, the one way tests run the ``multibots`` command,
and two recorded replays (``paper_run``, ``small_run``).

``tests/`` is on ``sys.path`` (``pythonpath`` in pyproject.toml), so tests import the oracles
(``oracle.reference_model``, ``oracle.geometry``) and the example strategies
(``strategies_example``) by name.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any, Optional

import pytest

import multibots

#: The repository root (scenarios/, docs/, README.md).
ROOT = Path(__file__).resolve().parent.parent


class Cli:
    """The ``multibots`` command, run in a fresh interpreter (``python -m multibots``).

    Call it with the command's arguments to run it to its end; :meth:`popen` starts it and
    returns at once (for servers and Ctrl-C tests).
    """

    argv = [sys.executable, "-m", "multibots"]

    def __call__(
        self, *args: Any, cwd: Optional[Path] = None, env: Optional[dict[str, str]] = None, timeout: float = 300
    ) -> subprocess.CompletedProcess[str]:
        """Runs ``multibots ARGS...`` (each argument passed through ``str``) and returns the
        finished process, with its stdout and stderr as text."""
        return subprocess.run(
            [*self.argv, *map(str, args)], capture_output=True, text=True, cwd=cwd, env=env, timeout=timeout
        )

    def popen(self, *args: Any, **kwargs: Any) -> subprocess.Popen[str]:
        """Starts ``multibots ARGS...`` with stdout and stderr piped, as text."""
        return subprocess.Popen(
            [*self.argv, *map(str, args)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, **kwargs
        )

    @staticmethod
    def assert_one_line_error(p: subprocess.CompletedProcess[str], *fragments: str, code: int = 2) -> None:
        """The command failed with ``code`` and one line on stderr, holding every fragment."""
        assert p.returncode == code, (p.returncode, p.stdout, p.stderr)
        err = p.stderr.strip()
        assert err and len(err.splitlines()) == 1, err
        assert "Traceback" not in p.stderr
        for frag in fragments:
            assert frag in err, (frag, err)


@pytest.fixture(scope="session")
def cli() -> Cli:
    """The ``multibots`` command line (see :class:`Cli`)."""
    return Cli()


@pytest.fixture(scope="session")
def paper_run(tmp_path_factory):
    """The paper's group 1 with 3 robots, recorded: (path, Result)."""
    path = tmp_path_factory.mktemp("replays") / "group1-3.mbr"
    result = multibots.simulate(multibots.Scenario.paper(robots=3), record=str(path))
    assert path.is_file()
    return path, result


@pytest.fixture(scope="session")
def small_run(tmp_path_factory):
    """Two robots, three goods: a short replay for export tests."""
    path = tmp_path_factory.mktemp("replays") / "small.mbr"
    result = multibots.simulate(multibots.Scenario.paper(robots=2, goods=[11, 8, 39]), record=str(path))
    return path, result


@pytest.fixture(scope="session", autouse=True)
def nothing_left_in_the_repository():
    """No test leaves a file in the repository's top folder (a hostile argument that is a valid
    relative path once wrote its result there, and the file was committed): what tests write
    goes to their temporary folders. `out/` and `results/` are the commands' own defaults."""
    root = Path(__file__).resolve().parent.parent
    before = {p.name for p in root.iterdir()}
    yield
    left = sorted({p.name for p in root.iterdir()} - before - {"out", "results", ".pytest_cache", ".hypothesis"})
    assert not left, f"tests left files in {root}: {left}"
