"""How much demand a warehouse and its fleet can carry (docs/capacity.md).

A rate of orders is *sustained* when, once the fleet has settled, it delivers what arrives:
over the last half of the windows after the warm-up, deliveries per step are at least
``served`` (0.95) of the order rate, on average over the seeds, and no run ends in a jam
(gridlock, livelock, stalled or stranded). Below that rate the backlog stays bounded; above
it the backlog grows by the demand the fleet leaves unserved, every step.

The search brackets the highest sustained rate by doubling (or halving) from a first guess,
then narrows the bracket by bisection on a log scale until its ends are within
``precision`` of each other. Every run goes through the sweep runner: stored run by run in
``out/runs``, so a killed search loses no finished run and a new one reuses them, on this
machine's cores or a Ray cluster. The same search over the fleet size answers "how many
robots for this demand". :func:`capacities` runs either search once per allocation strategy
and traffic policy, so that one command says which combination carries the most.
"""

from __future__ import annotations

import difflib
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Optional, Union

from multibots import _args, _core
from multibots.exceptions import ArgumentError, InputError, ScenarioError
from multibots.scenario import Scenario

#: Most runs per rate (the command line's --seeds takes as many).
MAX_SEEDS = 1000

__all__ = ["Capacity", "Combination", "Level", "capacities", "capacity", "check", "fleet_for", "parse_names"]

#: Outcomes in which a fleet stopped working: the rate it was given is not sustained,
#: whatever it delivered before.
JAMMED = frozenset({"gridlock", "livelock", "stalled", "stranded", "collapse"})
#: Doublings or halvings before the search gives up bracketing.
MAX_BRACKET = 16


@dataclass
class Level:
    """One demand level (an order rate, or a fleet size) and what its runs did, one entry a
    seed."""

    rate: float
    robots: int
    #: Deliveries per 1,000 steps over the last half of the windows after the warm-up.
    throughput: list[float] = field(default_factory=list)
    #: Orders still open when the run ended (ordered less delivered).
    backlog: list[int] = field(default_factory=list)
    latency_p50: list[Optional[float]] = field(default_factory=list)
    latency_p95: list[Optional[float]] = field(default_factory=list)
    wait_share: list[float] = field(default_factory=list)
    outcomes: list[str] = field(default_factory=list)

    @property
    def demand(self) -> float:
        """Orders per 1,000 steps."""
        return 1000.0 * self.rate

    @property
    def served(self) -> float:
        """Mean sustained throughput over the demand (1: every order served as it comes)."""
        return _mean(self.throughput) / self.demand if self.demand > 0 else 1.0

    @property
    def backlog_growth(self) -> float:
        """Orders per 1,000 steps that the fleet leaves unserved once settled (0 when it
        keeps up)."""
        return max(0.0, self.demand - _mean(self.throughput))

    def sustained(self, served: float) -> bool:
        return self.served >= served and not any(o in JAMMED for o in self.outcomes)

    def to_dict(self) -> dict[str, Any]:
        return {
            "rate": self.rate,
            "robots": self.robots,
            "demand_per_1000": self.demand,
            "throughput_per_1000": _mean(self.throughput),
            "served": self.served,
            "backlog_growth_per_1000": self.backlog_growth,
            "backlog": _mean(self.backlog),
            "latency_p50": _mean_or_none(self.latency_p50),
            "latency_p95": _mean_or_none(self.latency_p95),
            "wait_share": _mean(self.wait_share),
            "outcomes": sorted(set(self.outcomes)),
            "seeds": len(self.throughput),
        }


@dataclass
class Capacity:
    """The answer: the highest sustained order rate (or, for :func:`fleet_for`, the smallest
    fleet that sustains a rate), and every level tried, lowest first."""

    question: str
    sustainable_rate: Optional[float]
    robots: Optional[int]
    curve: list[Level]
    served: float
    horizon: int
    warmup: int
    runs: int
    #: The rate asked about (:func:`fleet_for`); None for :func:`capacity`.
    rate: Optional[float] = None
    #: What limits the warehouse just past the knee (``Result.bottleneck`` of a run at the
    #: first level not sustained, seed 1: kind, node, busy share, queues, what would relieve
    #: it), or None when no resource saturates.
    bottleneck: Optional[dict[str, Any]] = None

    @property
    def knee(self) -> Optional[Level]:
        """The level the answer stands on: the highest rate sustained, or (a fleet-size
        question) the smallest fleet that sustains the rate, the one ``robots`` names."""
        ok = [lv for lv in self.curve if lv.sustained(self.served)]
        if not ok:
            return None
        if self.question == "robots":
            return next((lv for lv in ok if lv.robots == self.robots), ok[0])
        return ok[-1]

    def to_dict(self) -> dict[str, Any]:
        return {
            "question": self.question,
            "sustainable_rate": self.sustainable_rate,
            "robots": self.robots,
            "served": self.served,
            "horizon": self.horizon,
            "warmup": self.warmup,
            "runs": self.runs,
            "rate": self.rate,
            "bottleneck": self.bottleneck,
            "curve": [lv.to_dict() | {"sustained": lv.sustained(self.served)} for lv in self.curve],
        }


def capacity(scenario: Union[Scenario, str, os.PathLike[str]], *, seeds: int = 3, horizon: Optional[int] = None,
             served: float = 0.95, precision: float = 0.05, start: Optional[float] = None,
             out: Union[str, os.PathLike[str]] = "out/capacity", workers: int = 0, backend: str = "local",
             ray_address: Optional[str] = None, progress: Optional[Callable[[int], None]] = None) -> Capacity:
    """The highest order rate (orders per step) that ``scenario``'s warehouse and fleet
    sustain, with the throughput-against-demand curve. ``seeds`` runs per rate, each
    ``horizon`` steps (the scenario's ``orders.horizon``, else 10,000); ``start``: the first
    rate tried (else one order per 1,000 steps per robot)."""
    start = _args.number("start", start, above=0.0, optional=True)
    _search_args(out, workers, backend, ray_address, progress)
    base, horizon, warmup = _prepared(scenario, horizon, seeds, served, precision)
    robots = int(base.to_dict()["robots"])
    first = start if start is not None else robots / 1000.0
    if not (math.isfinite(first) and first > 0):
        raise InputError(f"start = {first}: must be a rate above 0")
    search = _Search(base, seeds, served, out, workers, backend, ray_address, progress)
    best = search.bracket(first, precision, lambda r: {"orders.rate": r})
    curve = sorted(search.levels.values(), key=lambda lv: lv.rate)
    answer = Capacity("rate", best, robots, curve, served, horizon, warmup, search.runs)
    if best is not None:
        # Where the limit binds: the first rate past the knee (the knee itself, when nothing
        # above it was tried), whose queues show what saturates first.
        past = [lv.rate for lv in curve if lv.rate > best]
        answer.bottleneck = _bottleneck(base.replace(orders={"rate": past[0] if past else best, "seed": 1}))
    return answer


def fleet_for(scenario: Union[Scenario, str, os.PathLike[str]], rate: float, *, seeds: int = 3,
              horizon: Optional[int] = None, served: float = 0.95, most: int = 100_000,
              out: Union[str, os.PathLike[str]] = "out/capacity", workers: int = 0, backend: str = "local",
              ray_address: Optional[str] = None, progress: Optional[Callable[[int], None]] = None) -> Capacity:
    """The smallest fleet (at most ``most`` robots) that sustains ``rate`` orders per step in
    ``scenario``'s warehouse; ``robots`` of the answer is None when even ``most`` does not."""
    rate = _args.number("rate", rate, above=0.0)  # type: ignore[assignment]
    most = _args.whole("most", most, 1, _core.LIMITS["robots"])  # type: ignore[assignment]
    _search_args(out, workers, backend, ray_address, progress)
    base, horizon, warmup = _prepared(scenario, horizon, seeds, served, 0.05)
    base = base.replace(orders={"rate": rate})
    search = _Search(base, seeds, served, out, workers, backend, ray_address, progress)
    robots = int(base.to_dict()["robots"])
    # Fewer robots never serve more: the smallest sustaining fleet is found by bisection,
    # once a fleet that sustains the rate and one that does not bracket it.
    lo, hi = 0, None
    n = robots
    for _ in range(MAX_BRACKET + 1):
        try:
            level = search.level({"robots": n}, rate, n)
        except ScenarioError as e:
            if n == robots:
                raise
            raise InputError(f"robots = {n}: {lo} robots do not sustain {rate:.4g} orders per step, and a larger "
                             f"fleet cannot be placed ({e})") from None
        if level.sustained(served):
            hi = n
            break
        lo = n
        if n >= most:
            break
        n = min(most, n * 2)
    if hi is not None:
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if search.level({"robots": mid}, rate, mid).sustained(served):
                hi = mid
            else:
                lo = mid
    curve = sorted(search.levels.values(), key=lambda lv: lv.robots)
    answer = Capacity("robots", rate if hi is not None else None, hi, curve, served, horizon, warmup, search.runs, rate)
    if hi is not None:
        answer.bottleneck = _bottleneck(base.replace(robots=hi, orders={"seed": 1}))
    return answer


@dataclass
class Combination:
    """The answer of one allocation strategy under one traffic policy (:func:`capacities`)."""

    allocator: str
    traffic: str
    answer: Capacity
    #: What tables call the strategy: its ``name`` for a Python strategy
    #: (:func:`multibots.strategies.strategy_labels`).
    strategy: str = ""

    @property
    def label(self) -> str:
        return f"{self.strategy or self.allocator}/{self.traffic}"

    def to_dict(self) -> dict[str, Any]:
        return {"allocator": self.allocator, "traffic": self.traffic, **self.answer.to_dict()}


#: The traffic policies (docs/traffic.md).
TRAFFIC = ("auto", "wait", "gate", "reserve")


def parse_names(text: str, flag: str, known: Sequence[str], python_ok: bool = False) -> list[str]:
    """Comma-separated names in order (``nearest,hungarian``), each one of ``known`` (or, with
    ``python_ok``, a Python strategy ``module:Class``); a bad one is one line that lists the
    known names."""
    from multibots._text import shown
    from multibots.strategies import is_python_allocator

    names = [n.strip() for n in text.split(",")]
    if not text.strip() or any(not n for n in names):
        raise InputError(f"{flag} = {shown(text)!r}: expected comma-separated names, such as {','.join(known[:2])}")
    for n in names:
        if n not in known and not (python_ok and is_python_allocator(n)):
            near = difflib.get_close_matches(n, known, n=1, cutoff=0.75)
            hint = f" (did you mean {near[0]}?)" if near else ""
            raise InputError(f"{flag} = {shown(n)!r}: unknown; expected one of {', '.join(known)}{hint}")
    dup = [n for n in names if names.count(n) > 1]
    if dup:
        raise InputError(f"{flag} = {shown(dup[0])!r}: named twice")
    return names


def capacities(scenario: Union[Scenario, str, os.PathLike[str]], allocators: Optional[Sequence[str]] = None,
               traffic: Optional[Sequence[str]] = None, *, robots_for: Optional[float] = None,
               **kwargs: Any) -> list[Combination]:
    """:func:`capacity` (or, given ``robots_for``, :func:`fleet_for`) once per allocation
    strategy and traffic policy, every strategy under every policy, strategies first. A list
    left out (None) keeps the scenario's own choice. Every combination's runs share the store
    ``out``; the other keyword arguments go to each search."""
    s = scenario if isinstance(scenario, Scenario) else Scenario.from_toml(scenario)
    d = s.to_dict()
    allocs = list(allocators) if allocators is not None else [str(d.get("allocator") or "in-turn")]
    policies = list(traffic) if traffic is not None else [str(d.get("traffic") or "auto")]
    for name, values in (("allocators", allocs), ("traffic", policies)):
        if not values:
            raise InputError(f"{name}: give at least one")
        if len(set(values)) < len(values):
            raise InputError(f"{name} = {values}: a name given twice")
    combos = [(a, t) for a in allocs for t in policies]
    # Every combination is checked before the first run: a bad name costs no search.
    variants = [s.replace(allocator=a, traffic=t) for a, t in combos]
    for v in variants:
        check(v, kwargs.get("horizon"), kwargs.get("seeds", 3), kwargs.get("served", 0.95))
    from multibots.strategies import strategy_labels

    labels = strategy_labels(allocs)
    out = []
    for (a, t), v in zip(combos, variants):
        if robots_for is None:
            answer = capacity(v, **kwargs)
        else:
            kwargs.pop("start", None)
            answer = fleet_for(v, robots_for, **kwargs)
        out.append(Combination(a, t, answer, labels[a]))
    return out


def _bottleneck(scenario: Scenario) -> Optional[dict[str, Any]]:
    """The bottleneck of one run at the knee (the busiest saturated resource, docs/metrics.md)."""
    from multibots.simulation import simulate

    b = simulate(scenario).bottleneck
    return dict(b) if b is not None else None


def _search_args(out: Any, workers: Any, backend: Any, ray_address: Any, progress: Any) -> None:
    """The arguments of a search's runs, checked (:mod:`multibots._args`)."""
    from multibots.sweeps import _checked

    _checked(out, workers, backend, ray_address, progress, None)


def check(scenario: Union[Scenario, str, os.PathLike[str]], horizon: Optional[int] = None, seeds: int = 3,
          served: float = 0.95) -> None:
    """Raises what :func:`capacity` would raise about its arguments, before any run."""
    _prepared(scenario, horizon, seeds, served, 0.05)


def _prepared(scenario: Union[Scenario, str, os.PathLike[str]], horizon: Optional[int], seeds: int, served: float,
              precision: float) -> tuple[Scenario, int, int]:
    """The scenario as a lifelong run of ``horizon`` steps, with a warm-up of a fifth of it
    and windows that leave at least four after the warm-up."""
    seeds = _args.whole("seeds", seeds, 1, MAX_SEEDS)  # type: ignore[assignment]
    served = _args.number("served", served, high=1.0, above=0.0)  # type: ignore[assignment]
    precision = _args.number("precision", precision, high=1.0, above=0.0)  # type: ignore[assignment]
    if precision >= 1:
        raise ArgumentError(f"precision = {precision}: expected a number above 0 and below 1")
    horizon = _args.whole("horizon", horizon, 0, _core.LIMITS["steps"], optional=True)
    s = scenario if isinstance(scenario, Scenario) else Scenario.from_toml(_args.path("scenario", scenario))
    d = s.to_dict()
    if d.get("tasks") and not d.get("orders"):
        raise InputError("tasks: capacity is a question about a stream of orders; the scenario has a fixed task "
                         "list (give it an [orders] table, docs/layout-format.md)")
    orders = dict(d.get("orders") or {})
    if orders.get("csv"):
        raise InputError(f"orders.csv = {orders['csv']!r}: capacity varies the rate of Poisson orders; a CSV "
                         "stream has its own rate")
    h = int(horizon if horizon is not None else orders.get("horizon") or 10_000)
    if h < 2000:
        raise InputError(f"horizon = {h}: at least 2000 steps, so that a settled fleet can be measured")
    warmup = h // 5
    window = max(1, min(1000, (h - warmup) // 8))
    orders.update({"horizon": h, "rate": orders.get("rate") or 0.001})
    metrics = {**(d.get("metrics") or {}), "warmup": warmup, "window": window}
    return s.replace(tasks=[], orders=orders, metrics=metrics), h, warmup


class _Search:
    """Runs levels through the sweep runner, each once (the store keeps them)."""

    def __init__(self, base: Scenario, seeds: int, served: float, out: Union[str, os.PathLike[str]], workers: int,
                 backend: str, ray_address: Optional[str], progress: Optional[Callable[[int], None]]) -> None:
        self.base, self.seeds, self.served = base, seeds, served
        self.out, self.workers, self.backend, self.ray_address = Path(out), workers, backend, ray_address
        self.progress = progress
        self.levels: dict[tuple[float, int], Level] = {}
        self.runs = 0

    def level(self, changes: dict[str, Any], rate: float, robots: int) -> Level:
        from multibots.sweeps import run_planned
        from multibots.sweeps.spec import Spec

        key = (rate, robots)
        if key in self.levels:
            return self.levels[key]
        spec = Spec(base=self.base, axes={k: [v] for k, v in changes.items()}, repeats=self.seeds,
                    source="capacity")
        points = spec.points(self.workers)
        df = run_planned(points, self.out, workers=self.workers, backend=self.backend,
                         ray_address=self.ray_address, progress=self.progress)
        self.runs += len(points)
        lv = Level(rate, robots)
        for row in df.to_dicts():
            lv.throughput.append(float(row["sustained_throughput"] or 0.0))
            lv.backlog.append(int(row["goods_total"]) - int(row["delivered"]))
            lv.latency_p50.append(row.get("latency_p50"))
            lv.latency_p95.append(row.get("latency_p95"))
            lv.wait_share.append(float(row["wait_share"] or 0.0))
            lv.outcomes.append(str(row["outcome"]))
        self.levels[key] = lv
        return lv

    def bracket(self, first: float, precision: float, changes: Callable[[float], dict[str, Any]]) -> Optional[float]:
        """The highest sustained rate within ``precision``, or None if none was found."""
        robots = int(self.base.to_dict()["robots"])

        def ok(r: float) -> bool:
            return self.level(changes(r), r, robots).sustained(self.served)

        r = _round(first)
        lo: Optional[float] = None
        hi: Optional[float] = None
        if ok(r):
            lo = r
            for _ in range(MAX_BRACKET):
                r = _round(r * 2)
                if not ok(r):
                    hi = r
                    break
                lo = r
        else:
            hi = r
            for _ in range(MAX_BRACKET):
                r = _round(r / 2)
                if ok(r):
                    lo = r
                    break
                hi = r
        if lo is None or hi is None:
            return lo
        while hi / lo > 1 + precision:
            mid = _round(math.sqrt(lo * hi))
            if mid in (lo, hi):
                break
            if ok(mid):
                lo = mid
            else:
                hi = mid
        return lo


def _round(r: float) -> float:
    """Rates to 4 significant digits: the same level asked twice is one set of runs, and the
    store's keys are stable across searches."""
    return float(f"{r:.4g}")


def _mean(xs: Sequence[float]) -> float:
    return sum(xs) / len(xs) if xs else 0.0


def _mean_or_none(xs: Sequence[Optional[float]]) -> Optional[float]:
    vals = [x for x in xs if x is not None]
    return sum(vals) / len(vals) if vals else None
