"""Running a sweep, under any rules: the local backend or Ray, with results stored batch by
batch (store.py). ``sweep``, ``capacity`` and ``compare`` all run here.

Every point is a job (:func:`job_of`): a scenario with its strategy, or a League of Robot
Runners problem with its run's options. Scenarios with built-in strategies run in batches on
the engine's threads (one world per layout); every other job (a Python strategy, a LoRR run)
runs one at a time by :func:`run_job`, in a worker process locally or in a Ray task."""

from __future__ import annotations

import os
import queue
import threading
import time
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED
from concurrent.futures import wait as wait_futures
from typing import Any, Optional

from multibots import _core
from multibots.exceptions import InputError, MissingExtraError
from multibots.result import people_costs
from multibots.runs import engine_id, process_pool, run_key, strategy_id
from multibots.scenario import Scenario
from multibots.strategies import is_python_allocator
from multibots.sweeps import lorr as lorr_sweep
from multibots.sweeps.spec import Point
from multibots.sweeps.store import Store

__all__ = ["FIGURES", "PEOPLE_COSTS", "Job", "backlog_growth", "batched", "estimate_cost", "figures_of", "job_of",
           "keys_of", "run_job", "run_points"]

#: The figures stored for each run (docs/sweeps.md).
FIGURES = ("T", "S", "C", "outcome", "steps", "delivered", "goods_total", "cost", "distance", "throughput",
           "sustained_throughput", "wait_share", "utilisation", "contacts", "closest", "window")
#: A finished run waits at most about this many seconds to be written to a Parquet store (at
#: most that much work is repeated after a kill; fewer, larger part files), and Ray tasks hold
#: at least this many robot-steps.
FLUSH_SECONDS = 1.0
RAY_BATCH_COST = 2_000_000
#: Seconds of runs in one call of the engine's pool (local backend).
CALL_SECONDS = 0.25


_SCALARS = tuple(k for k in FIGURES if k != "distance")
_LIFELONG = ("latency_p50", "latency_p95", "energy_per_delivery", "ordered")
_PEOPLE = ("protective_stops", "min_gap", "warning_steps", "person_wait_steps", "tours", "picks", "walk_steps",
           "blocked_steps")
#: What robots cost people (``result.people_costs``), stored as ``people_<name>``.
PEOPLE_COSTS = ("picks_per_hour", "tours_per_hour", "walk_share", "blocked_share", "alone_picks_per_hour",
                "alone_tours_per_hour", "alone_walk_share", "alone_blocked_share")


def figures_of(raw: dict[str, Any]) -> dict[str, Any]:
    """A run's engine result reduced to the stored scalars (JSON- and Parquet-ready)."""
    get = raw.get
    out = {k: get(k) for k in _SCALARS}
    distance = get("distance")
    out["distance"] = float(distance.sum()) if hasattr(distance, "sum") else distance
    lifelong = get("lifelong") or {}
    for k in _LIFELONG:
        out[k] = lifelong.get(k)
    out["backlog_growth"] = backlog_growth(out["ordered"], get("steps"), get("sustained_throughput"))
    # Deliveries per window (docs/metrics.md), as text: a CSV cell, and a flat Parquet column.
    out["windows"] = ";".join(map(str, get("windows") or ()))
    people = get("people") or {}
    for k in _PEOPLE:
        out[f"people_{k}"] = people.get(k)
    costs = people_costs(people) if people else {}
    for k in PEOPLE_COSTS:
        out[f"people_{k}"] = costs.get(k)
    return out


def backlog_growth(ordered: Optional[int], steps: Optional[int], sustained: Optional[float]) -> Optional[float]:
    """Orders per 1,000 steps a lifelong run leaves unserved once settled: the demand it saw
    (orders over its steps) less its sustained throughput. About 0 when the fleet keeps up
    (either sign, by chance); the unserved demand when it does not. None for finite runs."""
    if ordered is None or not steps or sustained is None:
        return None
    return 1000.0 * ordered / steps - sustained


def estimate_cost(s: Scenario) -> float:
    """Robot-steps a run is expected to take, for batching: the fleet times the horizon of a
    lifelong run, or times a few hundred steps per goods and robot."""
    d = s.to_dict()
    robots = int(d.get("robots", 1))
    if d.get("orders"):
        steps = int(d["orders"].get("horizon", 10_000))
    else:
        tasks = d.get("tasks")
        goods = tasks.get("random", 10) if isinstance(tasks, dict) else len(tasks or [])
        steps = 500 + 300 * goods / max(1, robots)
    return robots * min(steps, int(d.get("step_limit", 100_000)))


#: A job: what a worker process or a Ray task needs to make one run, picklable. ``("scenario",
#: (scenario JSON, strategy))`` or ``("lorr", LorrBase)``.
Job = tuple[str, Any]


def job_of(point: Any) -> Job:
    """The job of a sweep's point."""
    if isinstance(point, lorr_sweep.LorrPoint):
        return ("lorr", point.run)
    return ("scenario", (point.scenario._core.to_json(), point.allocator))


def batched(job: Job) -> bool:
    """Whether a job runs in the engine's batches: a scenario with a built-in strategy."""
    return job[0] == "scenario" and not is_python_allocator(job[1][1])


def cost_of(point: Any) -> float:
    """Robot-steps a point's run is expected to take."""
    if isinstance(point, lorr_sweep.LorrPoint):
        return float(point.run.steps * (point.run.robots or 1000))
    return estimate_cost(point.scenario)


def run_job(job: Job) -> dict[str, Any]:
    """One run of any rules, its stored figures: what a worker process or a Ray task does."""
    kind, payload = job
    if kind == "lorr":
        return lorr_sweep.run_one(payload)
    return figures_of(_core.simulate(_core.Scenario.from_json(payload[0])))


def run_points(points: Sequence[Point], store: Store, workers: int = 0, backend: str = "local",
               ray_address: Optional[str] = None, progress: Optional[Callable[[int], None]] = None,
               reused: Optional[Callable[[int, int], None]] = None) -> list[str]:
    """Runs every point whose key is not in the store yet, writing batches as they finish;
    returns the points' keys."""
    workers = workers or os.cpu_count() or 1
    keys = keys_of(points)
    done = store.keys()
    todo = [k for k, key in enumerate(keys) if key not in done]
    if reused is not None:
        reused(len(points) - len(todo), len(points))
    tick = progress or (lambda k: None)
    if len(todo) < len(points):
        tick(len(points) - len(todo))
    if backend == "ray":
        _run_ray(points, keys, todo, store, workers, ray_address, tick)
    elif backend == "local":
        _run_local(points, keys, todo, store, workers, tick)
    else:
        raise InputError(f"--backend = {backend!r}: expected local or ray")
    return keys


def keys_of(points: Sequence[Point]) -> list[str]:
    """Each point's run key: its scenario, its strategy's code and the engine build."""
    engine = engine_id()
    if points and isinstance(points[0], lorr_sweep.LorrPoint):
        return lorr_sweep.keys_of(points, engine)  # type: ignore[arg-type]
    code = {name: strategy_id(name) for name in {p.allocator for p in points}}
    return [run_key(p.scenario, code[p.allocator], engine) for p in points]


class _Writer:
    """The thread that writes finished runs to the store, so the engine's threads never wait
    for a write. A finished run waits at most ``flush`` seconds (and the time of a write), also
    while the next call of the engine or a slow run is still going: the thread wakes when the
    oldest unwritten run falls due. It is not a daemon thread: after a second Ctrl-C the
    interpreter still waits for it to write what it was handed."""

    def __init__(self, store: Store, points: Sequence[Point], keys: Sequence[str], flush: float) -> None:
        self.store, self.points, self.keys, self.flush = store, points, keys, flush
        self.inbox: queue.SimpleQueue[Optional[tuple[Sequence[int], list[Any], bool]]] = queue.SimpleQueue()
        self.error: Optional[BaseException] = None
        self.thread = threading.Thread(target=self._loop, name="multibots-sweep-store")
        self.thread.start()

    def put(self, ks: Sequence[int], results: list[Any], raw: bool) -> None:
        """Hands over finished runs: engine results (``raw``) or their figures already."""
        if self.error is not None:
            raise self.error  # a failed write stops the sweep here
        self.inbox.put((ks, results, raw))

    def close(self, quiet: bool = False) -> None:
        """Writes what is left and waits for the thread; raises its error unless ``quiet``."""
        self.inbox.put(None)
        while self.thread.is_alive():
            self.thread.join(POLL)
        if self.error is not None and not quiet:
            raise self.error

    def _loop(self) -> None:
        runs: list[tuple[int, dict[str, Any]]] = []
        since = 0.0  # when the oldest unwritten run finished
        try:
            while True:
                wait_s = max(0.0, since + self.flush - time.monotonic()) if runs else None
                try:
                    item = self.inbox.get(timeout=wait_s)
                except queue.Empty:
                    pass  # the oldest unwritten run is due
                else:
                    if item is None:
                        self._write(runs)
                        return
                    ks, results, raw = item
                    if not runs:
                        since = time.monotonic()
                    runs.extend((k, figures_of(r) if raw else r) for k, r in zip(ks, results))
                if runs and time.monotonic() - since >= self.flush:
                    self._write(runs)
                    runs = []
        except BaseException as e:  # handed to the main thread, which raises it
            self.error = e

    def _write(self, runs: list[tuple[int, dict[str, Any]]]) -> None:
        if runs:
            ks = [k for k, _ in runs]
            self.store.write([self.points[k] for k in ks], [self.keys[k] for k in ks], [r for _, r in runs])


#: How often a thread waiting for runs looks up for Ctrl-C, seconds. A process-directed signal
#: may land on any thread (the store's writer, the pool's manager): only the main thread
#: raises KeyboardInterrupt, and only once its wait returns, so no wait is longer than this.
POLL = 0.1


def finished(futures: Any) -> Any:
    """The futures as they finish, like ``as_completed``, waiting at most :data:`POLL` at a time
    so that Ctrl-C is seen at once."""
    pending = set(futures)
    while pending:
        done, pending = wait_futures(pending, timeout=POLL, return_when=FIRST_COMPLETED)
        yield from done


def _run_local(points: Sequence[Point], keys: Sequence[str], todo: Sequence[int], store: Store, workers: int,
               tick: Callable[[int], None]) -> None:
    # MULTIBOTS_SWEEP_FLUSH: seconds a finished run may wait to be written (tests write often to
    # kill in between). The journal of `compare` writes each call's runs at once (its flush is 0).
    flush = float(os.environ.get("MULTIBOTS_SWEEP_FLUSH", getattr(store, "flush_seconds", FLUSH_SECONDS)))
    writer = _Writer(store, points, keys, flush)
    jobs = {k: job_of(points[k]) for k in todo}
    engine_jobs = [k for k in todo if batched(jobs[k])]
    single_jobs = [k for k in todo if not batched(jobs[k])]
    try:
        _run_engine(points, engine_jobs, workers, writer, tick)
        if single_jobs:
            # A run each in worker processes: Ctrl-C stops them at once, and a kill of the
            # study leaves none behind.
            with process_pool(min(workers, len(single_jobs))) as pool:
                futures = {pool.submit(run_job, jobs[k]): k for k in single_jobs}
                for f in finished(futures):
                    writer.put([futures[f]], [f.result()], raw=False)
                    tick(1)
    except BaseException:
        # Whatever finished is kept, also when the study stops on an error or Ctrl-C.
        writer.close(quiet=True)
        raise
    writer.close()


def _run_engine(points: Sequence[Point], jobs: Sequence[int], workers: int, writer: _Writer,
                tick: Callable[[int], None]) -> None:
    """Built-in strategies on the engine's threads, in calls of about CALL_SECONDS each, so the
    progress bar moves and runs are written as they finish. The calls, and the progress
    callback, run on this thread, where Ctrl-C stops them at once; each call's results go to
    the writer thread before anything else, so an interrupt loses none of them."""
    size = 2 * workers  # the first call measures how long a run takes
    start = 0
    while start < len(jobs):
        ks = jobs[start:start + size]
        start += len(ks)
        t0 = time.monotonic()
        raws = _core.simulate_many([points[k].scenario._core for k in ks], workers)
        writer.put(ks, raws, raw=True)
        per_run = max(time.monotonic() - t0, 1e-6) / len(ks)
        size = max(2 * workers, min(4 * size, int(CALL_SECONDS / per_run)))
        tick(len(ks))


# ---------------------------------------------------------------- Ray


def _ray() -> Any:
    try:
        import ray
    except ImportError:
        raise MissingExtraError("multibots sweep --backend ray", "ray") from None
    return ray


def _ray_batch(jobs: list[Job]) -> list[dict[str, Any]]:
    """A Ray task: a batch of jobs of any rules on its worker."""
    marker = os.environ.get("MULTIBOTS_TEST_KILL_ONCE")
    if marker and not os.path.exists(marker):
        # Tests: the first task to get here dies as a killed worker would.
        open(marker, "w").close()
        os._exit(1)
    # Built-in strategies in one engine call (one world per layout), the others one by one.
    engine = iter(_core.simulate_many([_core.Scenario.from_json(j[1][0]) for j in jobs if batched(j)], 1))
    return [figures_of(next(engine)) if batched(j) else run_job(j) for j in jobs]


def _batches(points: Sequence[Point], todo: Sequence[int], workers: int) -> list[list[int]]:
    """Runs grouped so each task holds at least RAY_BATCH_COST robot-steps (a task is never
    tiny), yet there are a few tasks per worker to balance the load."""
    costs = [cost_of(points[k]) for k in todo]
    target = max(RAY_BATCH_COST, sum(costs) / max(1, 4 * workers))
    out: list[list[int]] = []
    cur: list[int] = []
    acc = 0.0
    for k, c in zip(todo, costs):
        cur.append(k)
        acc += c
        if acc >= target:
            out.append(cur)
            cur, acc = [], 0.0
    if cur:
        out.append(cur)
    return out


def _run_ray(points: Sequence[Point], keys: Sequence[str], todo: Sequence[int], store: Store, workers: int,
             address: Optional[str], tick: Callable[[int], None]) -> None:
    ray = _ray()
    started = False
    if not ray.is_initialized():
        env = {"env_vars": {k: v for k, v in os.environ.items() if k == "MULTIBOTS_TEST_KILL_ONCE"}}
        if address:
            ray.init(address=address, runtime_env=env, log_to_driver=False, ignore_reinit_error=True)
        else:
            ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False, runtime_env=env,
                     _node_ip_address="127.0.0.1", ignore_reinit_error=True)
        started = True
    try:
        # Retried when a worker dies (not when a run raises: that is an answer).
        task = ray.remote(max_retries=3, num_cpus=1)(_ray_batch)
        batches = _batches(points, todo, workers)
        pending = {task.remote([job_of(points[k]) for k in b]): b for b in batches}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1, timeout=POLL)
            for ref in ready:
                b = pending.pop(ref)
                raws = ray.get(ref)
                store.write([points[k] for k in b], [keys[k] for k in b], raws)
                tick(len(b))
    finally:
        if started:
            ray.shutdown()

