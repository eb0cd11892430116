"""What the studies share to run many scenarios: the run journal's keys and its file
(:mod:`.journal`), and the worker processes Python strategies run in (:mod:`.processes`).

``multibots compare`` (:mod:`multibots.experiments.compare`) and ``multibots sweep``
(:mod:`multibots.sweeps`) both run through the sweep's runner, which keys every run here and
starts its processes here: this package imports neither, so neither imports the other back.
"""

from multibots.runs.journal import Journal, engine_id, run_key, strategy_id
from multibots.runs.processes import process_pool

__all__ = ["Journal", "engine_id", "process_pool", "run_key", "strategy_id"]
