"""The exception tree: every MultiBots error is a :class:`MultibotsError`.

The engine raises these from Rust; they are defined once, in the binding, and re-exported here.
"""

from multibots._core import (
    AllocatorError,
    EngineError,
    LayoutError,
    MultibotsError,
    ScenarioError,
)

__all__ = ["AllocatorError", "EngineError", "LayoutError", "MultibotsError", "ScenarioError"]
