"""The exception tree: every error a MultiBots user can meet is a :class:`MultibotsError`.

The engine's errors are defined once, in the binding (``multibots._core``), and re-exported
here; the errors that only the Python side raises are defined below, under the same base::

    MultibotsError
    ├── ScenarioError       a scenario field or file the model cannot run with (engine)
    ├── LayoutError         a layout robots cannot use (engine)
    ├── AllocatorError      a strategy's answer the engine cannot carry out (engine)
    ├── DecisionError       decisions from outside (a learning environment's action) that the
    │                       engine cannot carry out; the run is unchanged (engine)
    ├── EngineError         an internal error of the engine: a bug (engine)
    ├── InputError          a command-line option or study parameter out of range
    │   └── ArgumentError   an argument of the Python API of the wrong kind or out of range
    ├── ReplayError         a replay file that cannot be read
    ├── OutputError         an output path that cannot be written (or must not be replaced)
    ├── RenderError         a video export that cannot run (no browser, no encoder)
    └── MissingExtraError   a feature whose optional dependencies are not installed

The command line turns each into one line on stderr and an exit code (``multibots.cli``).
"""

from __future__ import annotations

from multibots._core import (
    AllocatorError,
    DecisionError,
    EngineError,
    LayoutError,
    MultibotsError,
    ScenarioError,
)

__all__ = [
    "AllocatorError",
    "ArgumentError",
    "DecisionError",
    "EngineError",
    "InputError",
    "LayoutError",
    "MissingExtraError",
    "MultibotsError",
    "OutputError",
    "RenderError",
    "ReplayError",
    "ScenarioError",
]


class InputError(MultibotsError, ValueError):
    """A command-line option or study parameter with a value that cannot be used.

    The message names the option and the value, such as ``--robots = '3..1': the range 3..1
    is empty``.
    """


class ArgumentError(InputError, TypeError):
    """An argument of the Python API of the wrong kind or out of range: the message names the
    parameter and the value, such as ``steps = 1.5: expected a whole number from 0 to
    4,294,967,295``. It is also a ``ValueError`` and a ``TypeError``, the errors a Python caller
    would expect for a bad argument.
    """


class ReplayError(MultibotsError, ValueError):
    """A replay file that cannot be read: the message names the file and the problem."""


class OutputError(MultibotsError, OSError):
    """An output path that cannot be written, or that is not a file we may replace."""


class RenderError(MultibotsError, RuntimeError):
    """A video export that cannot run: no browser, no encoder, a page that failed."""


class MissingExtraError(MultibotsError, ImportError):
    """A feature whose optional dependencies (a ``pip install 'multibots[extra]'``) are missing.

    Attributes:
        extra: the name of the extra that provides them.
    """

    def __init__(self, feature: str, extra: str) -> None:
        super().__init__(f"{feature} needs the '{extra}' extra: pip install 'multibots[{extra}]'")
        self.extra = extra
