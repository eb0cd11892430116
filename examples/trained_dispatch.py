"""The policy that examples/train_dispatch.py trained, as a strategy for ``simulate`` and ``compare``.

    multibots compare --strategies in-turn,nearest,hungarian,examples/trained_dispatch.py:TrainedDispatch
"""

from __future__ import annotations

from pathlib import Path

from multibots.envs import LinearPolicy, PolicyAllocator

WEIGHTS = Path(__file__).with_name("dispatch_policy.npz")


class TrainedDispatch(PolicyAllocator):
    """A linear policy trained on ``multibots/Dispatch-v0`` by the cross-entropy method."""

    name = "trained-dispatch"

    def __init__(self) -> None:
        super().__init__(LinearPolicy.load(WEIGHTS), max_queue=10)
