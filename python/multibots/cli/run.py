"""``multibots run``: one scenario, from a file or the quick-run flags, as a table or one JSON
object. A run that does not complete exits with code 3."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any, Optional

import typer

from multibots._text import sparkline
from multibots.cli._common import (
    ALLOW_CODE,
    EXIT_INCOMPLETE,
    GOODS,
    MARGIN,
    MAX_STEPS,
    ROBOTS,
    RULES,
    STARTS,
    STEP_LIMIT,
    TRAFFIC,
    UNLOAD,
    check_code,
    quick_scenario,
    whole_flag,
)
from multibots.exceptions import ScenarioError

__all__ = ["flow_lines", "lifelong_lines", "people_cost_lines", "people_lines", "result_lines", "run", "sparkline"]


def run(
    scenario: Optional[Path] = typer.Argument(None, help="A scenario file (TOML).", show_default=False),
    robots: Optional[str] = ROBOTS,
    goods: Optional[str] = GOODS,
    starts: Optional[str] = STARTS,
    unload: Optional[str] = UNLOAD,
    margin: Optional[str] = MARGIN,
    step_limit: Optional[str] = STEP_LIMIT,
    rules: Optional[str] = RULES,
    traffic: Optional[str] = TRAFFIC,
    as_json: bool = typer.Option(
        False, "--json", help="Print one JSON object on stdout (the same keys for every run; floats rounded)."
    ),
    record: Optional[Path] = typer.Option(
        None, "--record", help="Write a replay of every step to this file.", show_default=False
    ),
    allocator: Optional[str] = typer.Option(
        None, "--allocator", metavar="NAME", show_default=False,
        help="Task-allocation strategy: a built-in (in-turn, nearest, hungarian, auction, energy-aware, min-cost), "
        "package.module:Class, module:Class for a module in the current folder, or path/to/file.py:Class.",
    ),
    horizon: Optional[int] = typer.Option(
        None, "--horizon", help="Lifelong scenarios: steps to run (overrides orders.horizon).", show_default=False,
        parser=whole_flag("--horizon", 1, MAX_STEPS), metavar="INT",
    ),
    allow_code: bool = ALLOW_CODE,
) -> None:
    """Run one scenario, from a file or from the quick-run flags on the paper layout.

    Exits with code 3 when the run does not complete (the step limit came first, or the fleet
    gridlocked, stranded or stalled; a lifelong run that reaches its horizon completes).
    """
    from multibots.result import Result
    from multibots.simulation import check_record, simulate

    check_code(scenario, allow_code, overridden=allocator is not None)
    s = quick_scenario(scenario, robots, goods, starts, unload, margin, step_limit, rules, traffic)
    if allocator is not None:
        s = s.replace(allocator=allocator)
    lifelong = s.to_dict().get("orders") is not None
    if horizon is not None:
        if not lifelong:
            raise ScenarioError(f"--horizon = {horizon}: only for lifelong scenarios (with [orders])")
        s = s.replace(orders={"horizon": horizon})
    check_record(s, record, "--record")
    for line in s.warnings():
        print(f"multibots: warning: {line}", file=sys.stderr)
    result: Result = simulate(s, record=record)
    if as_json:
        print(json.dumps(result.to_dict(rounded=True), separators=(",", ":")))
    else:
        print("\n".join(lifelong_lines(result) if lifelong else result_lines(result)))
        if lifelong:
            print("\n".join(overload_lines(result, scenario)))
        if result.people is not None:
            # The cost of people: the same run with nobody on the floor.
            print("\n".join(people_lines(result, simulate(s.replace(humans={"count": 0})))))
        if record is not None:
            print(f"\nreplay written to {record}")
    if result.outcome not in ("complete", "horizon"):
        print(
            f"multibots: the run ended {result.outcome}: {result.delivered} of {result.goods_total} goods delivered "
            f"in {result.steps} steps (exit code {EXIT_INCOMPLETE})",
            file=sys.stderr,
        )
        raise typer.Exit(EXIT_INCOMPLETE)


def overload_lines(result: Any, scenario: Optional[Path]) -> list[str]:
    """For a lifelong run whose backlog grows by more than a tenth of the demand: that the
    demand is more than the fleet carries, and the command that finds the rate it does."""
    from multibots.sweeps.runner import backlog_growth

    ll = result.lifelong
    if result.outcome not in (None, "horizon", "complete"):
        # A fleet that jammed or stranded carries nothing: its backlog says nothing about how
        # much demand it could carry (the outcome line says what happened).
        return []
    growth = backlog_growth(ll["ordered"], result.steps, result.sustained_throughput)
    demand = 1000.0 * ll["ordered"] / result.steps if result.steps else 0.0
    if growth is None or growth <= 0.1 * demand:
        return []
    file = str(scenario) if scenario is not None else "SCENARIO.toml"
    return [f"backlog      grows by {growth:.1f} orders per 1,000 steps of {demand:.1f} ordered: more demand than "
            f"this fleet carries; `multibots capacity {file}` finds the rate it sustains"]


def flow_lines(result: Any) -> list[str]:
    """How the fleet flowed: throughput by window, waiting, working, contacts, gridlock."""
    from multibots.result import bottleneck_line

    def opt(v: Any, fmt: str) -> str:
        return "-" if v is None else fmt.format(v)

    windows = list(result.windows)
    lines = [
        f"throughput   {opt(result.throughput, '{:.2f}')} deliveries per 1,000 steps"
        f" (sustained {opt(result.sustained_throughput, '{:.2f}')} over the last half)",
    ]
    if windows:
        lines.append(f"per {result.window:,} steps {sparkline(windows)}  {min(windows)}..{max(windows)}")
    lines += [
        f"waiting      {result.wait_share:.1%} of robot-steps",
        f"utilisation  {result.utilisation:.1%} of robot-steps working on orders (not waiting)",
        f"contacts     {result.contacts} (pairs of robots closer than r_i + r_j, summed over steps);"
        f" closest {opt(result.closest, '{:.1f} px')}",
    ]
    g = result.gridlock
    if g is not None:
        where = ", ".join(f"{name} ({k})" for name, k in g["crossings"][:5])
        lines.append(f"gridlock     at step {g['step']}: {len(g['waiting'])} robots waiting, at {where}")
    if getattr(result, "resources", None):
        # Rules that measure their resources (the paper's): a verdict either way.
        lines.append(f"bottleneck   {bottleneck_line(getattr(result, 'bottleneck', None), result.outcome)}")
    c = getattr(result, "collapse", None)
    if c is not None:
        where = ", ".join(f"{name} ({k})" for name, k in c["crossings"][:5]) or "-"
        if c["collapsed"]:
            stranded = f", {c['stranded']} robots stranded from step {c['first_stranded']:,}" if c["stranded"] else ""
            lines.append(
                f"collapse     from step {c['step']:,}: windows fell from {c['best']} to {c['last']}{stranded};"
                f" robots stand still at {where}"
            )
        else:
            windows = f", windows best {c['best']}, last {c['last']}" if c["best"] else ""
            lines.append(
                f"stranded     from step {c['step']:,}: {c['stranded']} robots out of energy{windows};"
                f" they stand at {where}"
            )
    return lines


def result_lines(result: Any) -> list[str]:
    """The indicators of a run with a task list, and a line per robot."""
    t = "-" if result.T is None else str(result.T)
    lines = [
        f"outcome    {result.outcome}",
        f"T (steps)  {t}",
        f"S          {result.S}",
        f"C          {result.C}",
        f"delivered  {result.delivered}/{result.goods_total} in {result.steps} steps",
    ]
    if result.stranded:
        lines.append(f"stranded   robots {', '.join(map(str, result.stranded))}")
    if result.cost is not None:
        lines.append(f"Cost_total {result.cost:.1f}")
    lines += ["", *flow_lines(result)]
    lines += ["", "robot  delivered  distance  waits  S  C  energy used"]
    for i in range(len(result.distance)):
        lines.append(
            f"{i:>5}  {result.robot_delivered[i]:>9}  {result.distance[i]:>8.0f}  {result.wait_steps[i]:>5}"
            f"  {result.collisions[i]}  {result.charges[i]}  {result.energy_used[i]:>11.3f}"
        )
    return lines


def people_lines(result: Any, without: Any) -> list[str]:
    """The safety figures of a run with people, and what people cost against ``without``
    (the same run with nobody on the floor)."""
    p = result.people
    m = p["px_per_m"]

    def gap(v: Any) -> str:
        return "-" if v is None else f"{v / m:.2f} m ({v:.1f} px)"

    share = p["person_wait_steps"] / p["person_steps"] if p["person_steps"] else 0.0
    if result.lifelong is not None or without.T is None or result.T is None:
        a, b = result.throughput, without.throughput
        cost = f"throughput {a or 0:.1f} against {b or 0:.1f} deliveries per 1,000 steps without people"
        if a is not None and b:
            cost += f" ({(a - b) / b:+.1%})"
    else:
        cost = f"T {result.T} against {without.T} steps without people ({(result.T - without.T) / without.T:+.1%})"
    return [
        f"people       {p['count']} on the floor: {p['tours']} tours, {p['picks']} picks; "
        f"stopped hard by robots {share:.1%} of person-steps",
        *people_cost_lines(p),
        f"gap          smallest {gap(p['min_gap'])}, 1st percentile {gap(p['gap_p1'])}; contacts {p['contacts']}",
        f"robots       {p['protective_stops']} protective stops ({p['stopped_steps']} robot-steps stopped), "
        f"{p['warning_steps']} robot-steps with a person in the warning zone",
        f"cost         {cost}",
    ]


def people_cost_lines(p: dict[str, Any]) -> list[str]:
    """What robots cost people: picks and tours per worker-hour, and the shares of their time
    walking and blocked, against the same people with the fleet removed (same seed)."""
    from multibots.result import people_costs

    c = people_costs(p)

    def pair(key: str, fmt: str) -> str:
        a, b = c[key], c[f"alone_{key}"]
        return f"{'-' if a is None else format(a, fmt)} ({'-' if b is None else format(b, fmt)})"

    hours = p["person_steps"] * p["step_seconds"] / 3600.0
    return [
        f"per worker   {pair('picks_per_hour', '.1f')} picks and {pair('tours_per_hour', '.2f')} tours an hour; "
        f"in brackets the same people without robots",
        f"their time   walking {pair('walk_share', '.1%')}, of which held up {pair('blocked_share', '.1%')} "
        f"({hours:.2f} worker-hours at {p['step_seconds']} s a step)",
    ]


def lifelong_lines(result: Any) -> list[str]:
    """The figures of a lifelong run, as aligned lines."""
    ll = result.lifelong

    def opt(v: Any, fmt: str = "{}") -> str:
        return "-" if v is None else fmt.format(v)

    return [
        f"outcome      {result.outcome} after {result.steps} steps, {len(result.distance)} robots",
        *flow_lines(result),
        f"orders       {ll['ordered']} = {result.delivered} delivered + {ll['in_flight']} in flight"
        f" + {ll['queued']} queued + {ll['waiting']} waiting for stock",
        f"latency      p50 {opt(ll['latency_p50'])}, p95 {opt(ll['latency_p95'])}, p99 {opt(ll['latency_p99'])} steps",
        f"energy       {opt(ll['energy_per_delivery'], '{:.3f}')} per delivery",
        f"S, C         {result.S}, {result.C}",
    ]
