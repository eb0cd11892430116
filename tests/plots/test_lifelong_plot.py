"""Throughput over time: windows read as rates, bands across runs, no figure without data."""

from __future__ import annotations

import pytest

from multibots.plots.lifelong import bands, draw_throughput_over_time, series_of


def test_a_run_is_read_as_deliveries_per_1000_steps_at_the_end_of_each_window() -> None:
    assert series_of({"windows": "5;10;0", "window": 500}) == [(500, 10.0), (1000, 20.0), (1500, 0.0)]
    assert series_of({"windows": "7", "window": 500}) is None  # one window: no curve
    assert series_of({"windows": "", "window": None}) is None  # a finite run


def test_bands_are_the_mean_and_interval_across_runs_over_the_shortest_run() -> None:
    steps, means, los, his = bands([[(100, 10.0), (200, 20.0)], [(100, 14.0), (200, 20.0), (300, 5.0)]])
    assert steps == [100, 200] and means == [12.0, 20.0]
    # t(0.975, 1) = 12.706...: 12 ± 12.706 · 2.828 / 1.414, clipped at 0 below.
    assert los[0] == 0.0 and his[0] == pytest.approx(12 + 12.706204736 * 2)
    assert los[1] == his[1] == 20.0


def test_a_figure_only_when_there_is_a_run(tmp_path) -> None:
    assert draw_throughput_over_time({}, tmp_path / "a.png") is None
    assert draw_throughput_over_time({"x": []}, tmp_path / "a.png") is None
    assert not (tmp_path / "a.png").exists()
    path = draw_throughput_over_time({"x": [[(100, 1.0), (200, 2.0)]]}, tmp_path / "b.png")
    assert path is not None and path.stat().st_size > 0
