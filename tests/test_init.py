"""The package itself: every module imports on its own (no import circle), ``import multibots``
stays light and reaches every submodule, and the version."""

from __future__ import annotations

import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

import multibots

PACKAGE = Path(multibots.__file__).resolve().parent


def _module_names():
    names = []
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__main__":
            continue
        if parts[-1] == "__init__":
            parts.pop()
        names.append(".".join(parts))
    return names


def test_every_module_imports_alone_in_a_fresh_interpreter():
    """A module that needs another to be imported first, or an import circle that only works in
    one order, fails here."""
    names = _module_names()
    assert {"multibots.cli", "multibots.cli._common", "multibots.cli.run", "multibots.stats"} <= set(names)

    def alone(name):
        p = subprocess.run([sys.executable, "-c", f"import {name}"], capture_output=True, text=True, timeout=120)
        return name, p.returncode, p.stderr.strip().splitlines()[-1:] if p.returncode else ""

    with ThreadPoolExecutor(max_workers=2) as pool:
        failed = [r for r in pool.map(alone, names) if r[1] != 0]
    assert not failed, failed


def test_import_multibots_is_light_and_reaches_every_submodule():
    code = (
        "import sys, multibots\n"
        "heavy = [m for m in ('matplotlib', 'typer', 'rich', 'scipy', 'playwright', 'multibots.plots',"
        " 'multibots.render', 'multibots.cli') if m in sys.modules]\n"
        "print(heavy)\n"
        "for name in multibots.SUBMODULES:\n"
        "    assert getattr(multibots, name).__name__ == 'multibots.' + name, name\n"
        "print('ok')\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.split() == ["[]", "ok"]


def test_submodules_are_attributes():
    import multibots.plots as plots

    assert multibots.plots is plots
    assert multibots.render.render.__module__ == "multibots.render"
    assert multibots.replay.Replay is multibots.Replay
    assert {"plots", "render", "replay", "stats", "viewer"} <= set(dir(multibots))
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        multibots.nope  # noqa: B018


def test_the_version_is_the_installed_distribution_s():
    from importlib.metadata import version

    assert version("multibots") == multibots.__version__
