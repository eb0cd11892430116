"""Charging at scale (docs/charging.md): the shipped 1,000-robot scenario with a battery of
20,000 steps of driving keeps delivering over 20,000 steps, where the paper's threshold rule
at the same chargers stops the warehouse for thousands of steps."""

from __future__ import annotations

from pathlib import Path

import multibots

ROOT = Path(__file__).resolve().parents[1]
SCENARIO = ROOT / "scenarios" / "warehouse-1000-charging.toml"


def worst_share_after(windows: list[int], first: int = 3) -> float:
    """The worst window after the first ones, as a share of the best one there."""
    after = windows[first:]
    return min(after) / max(after)


def test_the_shipped_fleet_charges_without_a_wave():
    s = multibots.Scenario.from_toml(SCENARIO)
    d = s.to_dict()
    assert d["robot"]["consumption"] * 20_000 <= d["robot"]["energy_full"], "a battery of at most 20,000 steps"
    r = multibots.simulate(s)
    assert r.outcome == "horizon" and len(r.windows) == 20
    assert not r.stranded
    assert all(w > 0 for w in r.windows), r.windows
    assert r.C > 0
    assert worst_share_after(r.windows) >= 0.75, r.windows
    assert r.contacts == 0
    # The paper's rule at the same chargers: the fleet drains together and goes together.
    wave = multibots.simulate(s.replace(charging={**d["charging"], "policy": "threshold"}))
    assert not wave.stranded
    assert worst_share_after(wave.windows) < 0.5, wave.windows
