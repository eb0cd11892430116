"""Strategies named by text: ``package.module:Class``, ``module:Class`` for a module in the
current folder, or ``path/to/file.py:Class``.

:func:`load_strategy` is the one place a name becomes Python code: the command line, scenario
files (``allocator = "..."``) and ``simulate(allocator="...")`` all come here, through the
engine's binding. :func:`strategy_source` says which source a name runs, so that a cached
result can be told from a stale one (``multibots compare``).
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.machinery
import importlib.util
import os
import sys
import threading
from pathlib import Path
from types import ModuleType
from typing import Any, Optional

from multibots import _core
from multibots.exceptions import ScenarioError

__all__ = ["is_python_allocator", "load_strategy", "strategy_source"]

_FORMS = '"package.module:Class" or "path/to/file.py:Class"'
# Strategy files loaded so far: absolute path -> (mtime_ns, size, module). A file edited since
# is loaded again.
_FILES: dict[str, tuple[int, int, ModuleType]] = {}
_LOCK = threading.Lock()


def is_python_allocator(name: str) -> bool:
    """Whether a strategy name refers to Python code (``module:Class`` or ``file.py:Class``)."""
    return ":" in name


def _is_path(module: str) -> bool:
    return module.endswith(".py") or "/" in module or os.sep in module


def _split(name: str) -> tuple[str, str]:
    module, _, attr = name.rpartition(":")
    if not module or not attr or not is_python_allocator(name):
        raise ScenarioError(f'allocator = "{name}": expected {_FORMS}')
    return module, attr


def _one_line(e: BaseException) -> str:
    text = " ".join(str(e).split())
    return f"{type(e).__name__}: {text}" if text else type(e).__name__


def _load_file(name: str, module: str) -> ModuleType:
    path = Path(module).expanduser()
    try:
        resolved = path.resolve(strict=True)
        st = resolved.stat()
    except FileNotFoundError:
        raise ScenarioError(f'allocator = "{name}": no such file {module}') from None
    except OSError as e:
        raise ScenarioError(f'allocator = "{name}": cannot read {module} ({e.strerror})') from None
    if not resolved.is_file():
        raise ScenarioError(f'allocator = "{name}": {module} is not a file')
    key = str(resolved)
    with _LOCK:
        known = _FILES.get(key)
        if known is not None and known[:2] == (st.st_mtime_ns, st.st_size):
            return known[2]
        # A name of its own per file, so that two strategy files called mine.py do not clash,
        # registered so that pickling and dataclasses find the module.
        digest = hashlib.sha256(key.encode()).hexdigest()[:12]
        mod_name = f"multibots_strategy_{resolved.stem.replace('-', '_')}_{digest}"
        spec = importlib.util.spec_from_file_location(mod_name, resolved)
        if spec is None or spec.loader is None:
            raise ScenarioError(f'allocator = "{name}": {module} is not a Python file')
        mod = importlib.util.module_from_spec(spec)
        sys.modules[mod_name] = mod
        try:
            spec.loader.exec_module(mod)
        except BaseException as e:
            sys.modules.pop(mod_name, None)
            if isinstance(e, KeyboardInterrupt):
                raise
            # SystemExit too: a module that exits while being imported is a broken strategy,
            # not the user's wish to leave with its code.
            raise ScenarioError(f'allocator = "{name}": cannot import {module}: {_one_line(e)}') from None
        _FILES[key] = (st.st_mtime_ns, st.st_size, mod)
        return mod


def _from_current_folder(module: str) -> Optional[ModuleType]:
    """Imports ``module`` from the current folder (where ``python -m`` would find it, and the
    ``multibots`` script would not): its top-level package or module, then the rest."""
    top = module.split(".")[0]
    spec = importlib.machinery.PathFinder.find_spec(top, [os.getcwd()])
    if spec is None or spec.loader is None:
        return None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[top] = mod
    try:
        spec.loader.exec_module(mod)
    except BaseException:
        sys.modules.pop(top, None)
        raise
    return importlib.import_module(module)


def _load_module(name: str, module: str) -> ModuleType:
    try:
        try:
            return importlib.import_module(module)
        except ModuleNotFoundError as e:
            # Only when the named module itself is missing (not a module it imports).
            if e.name is None or module.split(".")[0] != e.name.split(".")[0]:
                raise
            found = _from_current_folder(module)
            if found is None:
                raise
            return found
    except KeyboardInterrupt:
        raise
    except BaseException as e:  # SystemExit too, as in _load_file
        raise ScenarioError(f'allocator = "{name}": cannot import {module}: {_one_line(e)}') from None


def load_strategy(name: str) -> Any:
    """The class (or function) a strategy name refers to, imported.

    Args:
        name: ``package.module:Class`` (importable, or a module or package in the current
            folder) or ``path/to/file.py:Class`` (absolute, or relative to the current
            folder). ``Class`` may be dotted (``Outer.Inner``).

    Raises:
        ScenarioError: a malformed name, a missing file or module, a file that does not
            import (a syntax error, say), a missing attribute, or one that cannot be called;
            one line, starting ``allocator = "<name>": ``.
    """
    module, attr = _split(name)
    mod = _load_file(name, module) if _is_path(module) else _load_module(name, module)
    obj: Any = mod
    for part in attr.split("."):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            raise ScenarioError(f'allocator = "{name}": module {module} has no attribute {attr}') from None
    if not callable(obj):
        raise ScenarioError(f'allocator = "{name}": {attr} is not a class or function')
    return obj


def strategy_labels(names: list[str]) -> dict[str, str]:
    """What tables and figures call each strategy: a built-in by its name, a Python strategy
    by its ``name`` (``Allocator.name``), or by ``module:Class`` where it has none or where
    two strategies (or a built-in) would share one."""
    labels = {n: n for n in names}
    for n in names:
        if is_python_allocator(n):
            own = getattr(load_strategy(n), "name", None)
            if isinstance(own, str) and own.strip():
                labels[n] = own.strip()
    taken = [labels[n] for n in names]
    built_in = set(_core.BUILT_INS)

    def clear(n: str, label: str) -> bool:
        return label == n or (taken.count(label) == 1 and label not in names and label not in built_in)

    return {n: (label if clear(n, label) else n) for n, label in labels.items()}


def strategy_source(name: str) -> bytes:
    """The source a Python strategy name runs: the bytes of the file its module was loaded
    from (the file that defines the class or function).

    Raises:
        ScenarioError: as :func:`load_strategy`, or the module has no source file.
    """
    obj = load_strategy(name)
    mod = sys.modules.get(getattr(obj, "__module__", "") or "")
    path = getattr(mod, "__file__", None)
    if not path:
        raise ScenarioError(f'allocator = "{name}": its module has no source file to fingerprint')
    try:
        return Path(path).read_bytes()
    except OSError as e:
        raise ScenarioError(f'allocator = "{name}": cannot read {path} ({e.strerror})') from None
