"""One exception tree: every exception class the package defines is a MultibotsError."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import multibots
from multibots import _core


def _modules():
    """Every module of the package, imported (``__main__`` would run the command line)."""
    names = ["multibots"] + [
        m.name for m in pkgutil.walk_packages(multibots.__path__, "multibots.") if not m.name.endswith("__main__")
    ]
    return [importlib.import_module(n) for n in names]


def test_every_exception_class_in_the_package_is_a_multibots_error():
    modules = _modules()
    assert len(modules) > 25, [m.__name__ for m in modules]
    found = {}
    for module in modules:
        for obj in vars(module).values():
            if inspect.isclass(obj) and issubclass(obj, BaseException) and obj.__module__ == module.__name__:
                found[f"{module.__name__}.{obj.__name__}"] = obj
    # The engine's, defined in the binding.
    for name in ("MultibotsError", "ScenarioError", "LayoutError", "AllocatorError", "EngineError"):
        found[f"multibots._core.{name}"] = getattr(_core, name)
    assert len(found) >= 10, sorted(found)
    outside = sorted(name for name, cls in found.items() if not issubclass(cls, multibots.MultibotsError))
    assert not outside, f"exception classes outside the tree: {outside}"


def test_exception_tree():
    for cls in (multibots.ScenarioError, multibots.LayoutError, multibots.AllocatorError, multibots.EngineError,
                multibots.ReplayError, multibots.InputError, multibots.OutputError, multibots.RenderError,
                multibots.MissingExtraError):
        assert issubclass(cls, multibots.MultibotsError)
    # Each is also the built-in exception a Python caller would expect.
    assert issubclass(multibots.ReplayError, ValueError) and issubclass(multibots.InputError, ValueError)
    assert issubclass(multibots.OutputError, OSError) and issubclass(multibots.MissingExtraError, ImportError)
    # Defined once: the package's names are the binding's classes and the exceptions module's.
    assert multibots.ScenarioError is _core.ScenarioError
    from multibots import exceptions, render, replay

    assert replay.ReplayError is exceptions.ReplayError is multibots.ReplayError
    assert render.RenderError is exceptions.RenderError


def test_a_missing_extra_names_it():
    e = multibots.MissingExtraError("multibots render", "render")
    assert str(e) == "multibots render needs the 'render' extra: pip install 'multibots[render]'"
    assert e.extra == "render"


def test_every_exception_of_the_engine_is_exported_by_the_package():
    # Defined once, in the binding: whatever it registers, `import multibots` has, under the
    # same name, in `__all__`, and in the exceptions module.
    engine = {name: obj for name, obj in vars(_core).items() if inspect.isclass(obj) and issubclass(obj, BaseException)}
    assert {"MultibotsError", "ScenarioError", "DecisionError"} <= set(engine), sorted(engine)
    from multibots import exceptions

    for name, cls in engine.items():
        assert getattr(multibots, name) is cls, name
        assert getattr(exceptions, name) is cls, name
        assert name in multibots.__all__ and name in exceptions.__all__, name
