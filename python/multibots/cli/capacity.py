"""``multibots capacity``: the highest order rate a warehouse and its fleet sustain, or the
smallest fleet for a rate (docs/capacity.md)."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Optional

import typer

from multibots._io import check_folder, check_outputs
from multibots.cli._common import ALLOW_CODE, MAX_ROBOTS, MAX_STEPS, check_code, parse_number
from multibots.exceptions import InputError
from multibots.sweeps.capacity import MAX_SEEDS

__all__ = ["capacity"]


def capacity(
    scenario: Path = typer.Argument(..., help="A scenario with lifelong orders ([orders]): warehouse, fleet, "
                                    "strategy, traffic policy."),
    seeds: str = typer.Option("3", "--seeds", metavar="INT", help="Runs per level, with seeds 1..N."),
    robots: Optional[str] = typer.Option(None, "--robots", help="The fleet size (default: the scenario's robots).",
                                         show_default=False, metavar="N"),
    horizon: Optional[str] = typer.Option(None, "--horizon", metavar="STEPS",
                                          help="Steps per run (default: the scenario's "
                                          "orders.horizon, else 10000).", show_default=False),
    robots_for: Optional[str] = typer.Option(
        None, "--robots-for", help="RATE: the smallest fleet that sustains RATE orders per step, instead of the "
        "highest rate for the scenario's fleet.", show_default=False, metavar="RATE",
    ),
    start: Optional[str] = typer.Option(None, "--start", metavar="RATE",
                                        help="The first rate tried (default: robots / 1000).",
                                        show_default=False),
    served: str = typer.Option("0.95", "--served", metavar="SHARE",
                               help="The share of the demand a settled fleet must deliver "
                               "for a rate to count as sustained."),
    out: Path = typer.Option(Path("out/capacity"), "--out", help="Folder for the run store (runs/, reused by "
                             "the next search) and capacity.png."),
    workers: str = typer.Option("0", "--workers", metavar="INT",
                                help="Threads (0: one per core); Ray: CPUs of a local cluster."),
    backend: str = typer.Option("local", "--backend", metavar="NAME", help="local (this machine's cores) or ray."),
    ray_address: Optional[str] = typer.Option(None, "--ray-address", metavar="ADDRESS", help="A Ray cluster to join.",
                                              show_default=False),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object (sustainable_rate, robots, curve) "
                                 "instead of the table."),
    quiet: bool = typer.Option(False, "--quiet", help="No progress bar."),
    allocators: Optional[str] = typer.Option(
        None, "--allocators", metavar="NAMES",
        help="Strategies to compare, such as nearest,hungarian: one search per strategy and "
        "traffic policy (default: the scenario's).", show_default=False,
    ),
    traffic: Optional[str] = typer.Option(
        None, "--traffic", metavar="NAMES",
        help="Traffic policies to compare, such as wait,reserve (default: the scenario's).",
        show_default=False,
    ),
    allow_code: bool = ALLOW_CODE,
) -> None:
    """How much demand can this warehouse and fleet carry? Searches the order rate (seeds per
    rate) for the highest one whose backlog stops growing, and prints the throughput against
    demand, the knee, and latency per rate."""
    from multibots.experiments.summary import progress_bar
    from multibots.scenario import Scenario
    from multibots.sweeps import capacity as cap
    from multibots.sweeps.store import polars

    polars()  # the extra, before any work
    n_seeds = parse_number(seeds, "--seeds", int, MAX_SEEDS)
    if n_seeds < 1:
        raise InputError(f"--seeds = {n_seeds}: must be at least 1")
    steps = parse_number(horizon, "--horizon", int, MAX_STEPS)
    rate = parse_number(robots_for, "--robots-for", float)
    if rate is not None and rate <= 0:
        raise InputError(f"--robots-for = {robots_for}: must be a rate above 0 (orders per step)")
    first = parse_number(start, "--start", float)
    if first is not None and first <= 0:
        raise InputError(f"--start = {start}: must be a rate above 0 (orders per step)")
    share = parse_number(served, "--served", float)
    if not 0 < share <= 1:
        raise InputError(f"--served = {served}: must be above 0 and at most 1")
    threads = parse_number(workers, "--workers", int, 4096)
    if threads < 0:
        raise InputError(f"--workers = {threads}: must be 0 or more")
    if backend not in ("local", "ray"):
        raise InputError(f"--backend = {backend!r}: expected local or ray")
    if steps is not None and steps < 2000:
        raise InputError(f"--horizon = {steps}: at least 2000 steps, so that a settled fleet can be measured")
    from multibots.strategies import BUILT_INS

    allocs = None if allocators is None else cap.parse_names(allocators, "--allocators", BUILT_INS, allow_code)
    policies = None if traffic is None else cap.parse_names(traffic, "--traffic", cap.TRAFFIC)
    check_folder(out)
    check_code(scenario, allow_code, overridden=allocs is not None)
    base = Scenario.from_toml(scenario)
    check_outputs([], base.files(), folders=[("--out", out, ("runs/*", "capacity.png"))])
    fleet = parse_number(robots, "--robots", int, MAX_ROBOTS)
    if fleet is not None:
        if fleet < 1:
            raise InputError(f"--robots = {fleet}: must be at least 1")
        base = base.replace(robots=fleet)
    cap.check(base, steps, n_seeds, share)  # before the progress bar: a bad scenario is one line
    if allocs is not None or policies is not None:
        _combinations(base, allocs, policies, scenario, rate, first, as_json, quiet, out,
                      dict(seeds=n_seeds, horizon=steps, served=share, out=out, workers=threads, backend=backend,
                           ray_address=ray_address))
        return
    begin = time.perf_counter()
    # The number of runs is not known ahead (the search decides): the bar counts them.
    with progress_bar(None, enabled=not quiet and not as_json) as bar:
        common = dict(seeds=n_seeds, horizon=steps, served=share, out=out, workers=threads, backend=backend,
                      ray_address=ray_address, progress=bar.advance)
        if rate is None:
            answer = cap.capacity(base, start=first, **common)
        else:
            answer = cap.fleet_for(base, rate, **common)
    seconds = time.perf_counter() - begin
    if as_json:
        print(json.dumps(answer.to_dict()))
        return
    _print(answer, scenario, seconds)
    from multibots.plots.capacity import draw_capacity

    png = draw_capacity(answer, out / "capacity.png")
    print(f"wrote {png}")


def _combinations(base: object, allocs: Optional[list[str]], policies: Optional[list[str]], scenario: Path,
                  rate: Optional[float], first: Optional[float], as_json: bool, quiet: bool, out: Path,
                  common: dict[str, object]) -> None:
    """One search per strategy and traffic policy: a line each, one figure, or one JSON object
    with an entry each."""
    from multibots.experiments.summary import progress_bar
    from multibots.plots.capacity import draw_capacities
    from multibots.sweeps import capacity as cap

    begin = time.perf_counter()
    with progress_bar(None, enabled=not quiet and not as_json) as bar:
        extra = {"start": first} if rate is None else {}
        combos = cap.capacities(base, allocs, policies, robots_for=rate, progress=bar.advance,  # type: ignore[arg-type]
                                **extra, **common)
    seconds = time.perf_counter() - begin
    if as_json:
        print(json.dumps({"combinations": [c.to_dict() for c in combos]}))
        return
    runs = sum(c.answer.runs for c in combos)
    horizon = combos[0].answer.horizon
    plural = "s" if len(combos) != 1 else ""
    print(f"{scenario}: {len(combos)} combination{plural}, {runs} runs of {horizon} steps in {seconds:.1f} s; "
          "per 1,000 steps after the warm-up, at the knee")
    w = max(11, *(len(c.label) for c in combos))
    what = "sustainable" if rate is None else "robots"
    print(f"{'strategy/traffic':<{w}} {what:>11} {'delivered':>9} {'latency p50':>11} {'p95':>6} {'waiting':>7}"
          f" {'runs':>5}  bottleneck past the knee")
    for c in combos:
        a = c.answer
        knee = a.knee.to_dict() if a.knee is not None else None
        if rate is None:
            value = f"{a.sustainable_rate:.4g}" if a.sustainable_rate is not None else "none"
        else:
            value = str(a.robots) if a.robots is not None else "none"
        p50 = f"{knee['latency_p50']:.0f}" if knee and knee["latency_p50"] is not None else "-"
        p95 = f"{knee['latency_p95']:.0f}" if knee and knee["latency_p95"] is not None else "-"
        delivered = f"{knee['throughput_per_1000']:.1f}" if knee else "-"
        waiting = f"{knee['wait_share']:.0%}" if knee else "-"
        b = a.bottleneck
        neck = f"{b['kind']} {b['node']} (busy {b['busy']:.0%})" if b else ("none saturated" if a.knee else "-")
        print(f"{c.label:<{w}} {value:>11} {delivered:>9} {p50:>11} {p95:>6} {waiting:>7} {a.runs:>5}  {neck}")
    ok = [c for c in combos if (c.answer.sustainable_rate if rate is None else c.answer.robots) is not None]
    if ok and len(combos) > 1:
        key = (lambda c: c.answer.sustainable_rate or 0.0) if rate is None else (lambda c: -(c.answer.robots or 0))
        top = max(key(c) for c in ok)
        best = [c for c in ok if key(c) == top]
        said = (f"{best[0].answer.sustainable_rate:.4g} orders per step" if rate is None
                else f"{best[0].answer.robots} robots for {rate:.4g} orders per step")
        # Equal answers are a tie, not a winner picked by the order of the flags.
        print(f"{'best' if len(best) == 1 else 'tie'}: {', '.join(c.label for c in best)} with {said}")
    png = draw_capacities(combos, out / "capacity.png")
    print(f"wrote {png}")


def _print(answer: object, scenario: Path, seconds: float) -> None:
    from multibots.sweeps.capacity import Capacity

    assert isinstance(answer, Capacity)
    by_rate = answer.question == "rate"
    head = f"{'rate':>9} {'robots':>7} {'demand':>8} {'delivered':>9} {'served':>7} {'backlog+':>9} " \
           f"{'latency p50':>11} {'p95':>6} {'waiting':>7}  outcome"
    print(f"{scenario}: {answer.runs} runs of {answer.horizon} steps (warm-up {answer.warmup}) in {seconds:.1f} s; "
          "per 1,000 steps after the warm-up")
    print(head)
    for lv in answer.curve:
        d = lv.to_dict()
        mark = "*" if lv is answer.knee else " "
        p50 = f"{d['latency_p50']:.0f}" if d["latency_p50"] is not None else "-"
        p95 = f"{d['latency_p95']:.0f}" if d["latency_p95"] is not None else "-"
        print(f"{d['rate']:>9.4g} {d['robots']:>7} {d['demand_per_1000']:>8.1f} {d['throughput_per_1000']:>9.1f} "
              f"{d['served']:>6.0%}{mark} {d['backlog_growth_per_1000']:>9.1f} {p50:>11} {p95:>6} "
              f"{d['wait_share']:>7.0%}  {', '.join(d['outcomes'])}")
    b = answer.bottleneck
    if b is None and answer.knee is not None:
        print("past the knee no resource is saturated (none busy half the steps with a queue that stays: "
              "docs/metrics.md); the fleet's size and the orders set the pace")
    if b is not None:
        print(f"past the knee the bottleneck is {b['kind']} {b['node']}: busy {b['busy']:.0%} of steps, queue "
              f"{b['mean_queue']:.1f} on average ({b['longest_queue']} at most); relieve it with {b['relieve']}")
    if by_rate:
        if answer.sustainable_rate is None:
            print("no rate tried was sustained: the fleet does not keep up even with the lowest demand tried; "
                  "try a lower --start, or ask how many robots a rate needs with --robots-for RATE")
        else:
            print(f"sustainable rate: {answer.sustainable_rate:.4g} orders per step "
                  f"({1000 * answer.sustainable_rate:.1f} per 1,000 steps, {answer.robots} robots); "
                  f"* marks the knee")
    elif answer.robots is None:
        print(f"no fleet tried sustains {answer.rate:.4g} orders per step")
    else:
        print(f"smallest fleet that sustains {answer.rate:.4g} orders per step: {answer.robots} robots")
