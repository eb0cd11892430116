"""The package's parts import each other in one direction only.

Each subpackage of ``multibots`` (``cli``, ``experiments``, ``sweeps``, ...) and each of its
top-level modules is a part; a part may import another only if that one never imports it
back, directly or through other parts. Imports are read from the source with :mod:`ast`,
lazy ones inside functions included (they are the ones that hide a circle), so the test
imports nothing it checks. ``import multibots`` (the package's own facade) is no edge: every
submodule import runs it.
"""

from __future__ import annotations

import ast
import graphlib
import sys
from collections.abc import Iterator
from pathlib import Path

#: The package's source (the test reads it, it imports nothing).
PACKAGE = Path(__file__).resolve().parent.parent / "python" / "multibots"


def _parts() -> set[str]:
    """Subpackages and top-level modules of multibots, by name."""
    out = {p.name for p in PACKAGE.iterdir() if (p / "__init__.py").is_file()}
    out |= {p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__"}
    out |= {p.name.split(".")[0] for p in PACKAGE.glob("*.pyi")}
    return out


def _module_of(path: Path) -> list[str]:
    """``multibots.sweeps.runner`` as ``["multibots", "sweeps", "runner"]``; a package's
    ``__init__.py`` as the package."""
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    names = list(rel.parts)
    return names[:-1] if names[-1] == "__init__" else names


def _imported(path: Path) -> Iterator[tuple[str, int]]:
    """The dotted names a file imports (a ``from`` import's names too: they may be
    modules), with the line, relative imports resolved."""
    module = _module_of(path)
    package = module if path.name == "__init__.py" else module[:-1]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package[: len(package) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            for alias in node.names:
                yield f"{base}.{alias.name}", node.lineno


def _edges() -> dict[tuple[str, str], str]:
    """(part, part it imports) -> where, as ``file:line`` of the first such import."""
    parts = _parts()
    edges: dict[tuple[str, str], str] = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        own = _module_of(path)
        if len(own) < 2:
            continue  # the facade, multibots/__init__.py, imports from every part by design
        for name, line in _imported(path):
            dotted = name.split(".")
            if dotted[0] != "multibots" or len(dotted) < 2 or dotted[1] not in parts or dotted[1] == own[1]:
                continue
            edges.setdefault((own[1], dotted[1]), f"{path.relative_to(PACKAGE).as_posix()}:{line}")
    return edges


def _circle(edges: dict[tuple[str, str], str]) -> list[str]:
    """A circle of imports, ``[a, b, a]`` when a imports b and b imports a (longer ones
    likewise), or ``[]`` when there is none."""
    graph: dict[str, list[str]] = {}
    for a, b in sorted(edges):
        graph.setdefault(a, []).append(b)
    try:
        # Each part's imports are its predecessors: they must come first.
        graphlib.TopologicalSorter(graph).prepare()
    except graphlib.CycleError as e:
        return list(reversed(e.args[1]))  # the error lists predecessors first
    return []


def test_the_parts_of_multibots_import_each_other_in_one_direction_only():
    edges = _edges()
    assert ("cli", "sweeps") in edges and ("sweeps", "strategies") in edges, "the scan sees the imports"
    circle = _circle(edges)
    where = "".join(f"\n    {a} imports {b}: {edges[a, b]}" for a, b in zip(circle, circle[1:]))
    assert not circle, "parts of multibots import each other: " + " -> ".join(circle) + where


def test_the_scan_finds_a_circle_hidden_in_lazy_and_relative_imports(tmp_path, monkeypatch):
    # The shape of the circle this test was written for: one side imports the other inside
    # a function, the other side relatively.
    files = {
        "__init__.py": "from multibots.sweeps import run\n",
        "sweeps/__init__.py": "",
        "sweeps/runner.py": "def run():\n    from ..experiments.journal import Journal\n",
        "experiments/__init__.py": "",
        "experiments/journal.py": "",
        "experiments/compare.py": "import os\n\n\ndef study():\n    import multibots.sweeps.runner\n",
    }
    for name, text in files.items():
        (tmp_path / "multibots" / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / "multibots" / name).write_text(text, encoding="utf-8")
    monkeypatch.setattr(sys.modules[__name__], "PACKAGE", tmp_path / "multibots")
    edges = _edges()
    assert edges == {
        ("sweeps", "experiments"): "sweeps/runner.py:2",
        ("experiments", "sweeps"): "experiments/compare.py:5",
    }
    circle = _circle(edges)
    assert len(circle) == 3 and circle[0] == circle[2] and set(circle) == {"experiments", "sweeps"}
