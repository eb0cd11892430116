"""multibots.stats against SciPy (the `test` extra installs it) and against closed forms."""

from __future__ import annotations

import math
import random

import pytest
from scipy import stats as scipy_stats

from multibots import stats

DFS = [1, 2, 3, 4, 5, 9, 29, 179, 1000, 0.5, 2.5]


@pytest.mark.parametrize("df", DFS)
def test_t_quantiles_and_tails_equal_scipys(df):
    for q in [0.6, 0.75, 0.9, 0.95, 0.975, 0.995, 0.9999999]:
        assert stats.t_ppf(q, df) == pytest.approx(scipy_stats.t.ppf(q, df), rel=1e-11)
        assert stats.t_ppf(1 - q, df) == pytest.approx(scipy_stats.t.ppf(1 - q, df), rel=1e-11)
    for t in [0.01, 0.5, 1.0, 2.5, 10.0, 100.0, 1e4]:
        for x in (t, -t):
            assert stats.t_sf(x, df) == pytest.approx(scipy_stats.t.sf(x, df), rel=1e-11)
            assert stats.t_cdf(x, df) == pytest.approx(scipy_stats.t.cdf(x, df), rel=1e-11)


def test_t_near_the_centre_against_closed_forms():
    # df = 1 is the Cauchy distribution, df = 2 has a closed-form quantile; both near q = 0.5
    # too, where 1 - q would lose every digit.
    for q in [0.5000001, 0.51, 0.6, 0.99, 0.999999]:
        # 1 - q is exact in floating point; 1 / tan(pi (1 - q)) keeps its digits near the pole.
        assert stats.t_ppf(q, 1) == pytest.approx(1 / math.tan(math.pi * (1 - q)), rel=1e-11)
        assert stats.t_ppf(q, 2) == pytest.approx((2 * q - 1) / math.sqrt(2 * q * (1 - q)), rel=1e-12)
    assert stats.t_sf(1e-8, 1) == pytest.approx(0.5 - math.atan(1e-8) / math.pi, rel=1e-15)
    assert stats.t_ppf(0.5, 7) == 0.0
    assert stats.t_ppf(0.975, 3) == pytest.approx(3.182446305284263, rel=1e-12)


def test_betainc_equals_scipys():
    from scipy.special import betainc

    rng = random.Random(3)
    for _ in range(300):
        a, b, x = rng.uniform(0.05, 60), rng.uniform(0.05, 60), rng.random()
        assert stats.betainc(a, b, x) == pytest.approx(float(betainc(a, b, x)), rel=1e-10, abs=1e-300)
    assert stats.betainc(2, 3, 0.0) == 0.0 and stats.betainc(2, 3, 1.0) == 1.0
    with pytest.raises(ValueError):
        stats.betainc(0, 1, 0.5)


def _samples():
    """Differences like a study's: small and large, with ties, with zeros, continuous."""
    rng = random.Random(11)
    for n in [1, 2, 3, 4, 5, 8, 12, 13, 14, 20, 30, 50, 51, 80, 180]:
        yield [rng.gauss(0.3, 1) for _ in range(n)]
        yield [rng.choice([-1, 1]) * rng.choice([0, 1, 2, 3, 5]) for _ in range(n)]
        yield [rng.choice([-3, -1, 0, 2, 4, 7, 150]) for _ in range(n)]


@pytest.mark.parametrize("correction", [False, True])
def test_wilcoxon_equals_scipys(correction):
    checked = 0
    for diffs in _samples():
        nonzero = [d for d in diffs if d != 0]
        if not nonzero:
            with pytest.raises(ValueError):
                stats.wilcoxon(diffs)
            continue
        want = float(scipy_stats.wilcoxon(nonzero, correction=correction).pvalue)
        assert stats.wilcoxon(diffs, correction=correction) == pytest.approx(want, rel=1e-10), diffs
        checked += 1
    assert checked > 35


def test_wilcoxon_exact_small_samples():
    # Four negative differences: the most extreme of 2^4 sign patterns, two-sided.
    assert stats.wilcoxon([-2, -2, -2, -2]) == pytest.approx(0.125)
    assert stats.wilcoxon([1, 2, 3, 4, 5]) == pytest.approx(2 / 32)
    assert stats.wilcoxon([3]) == 1.0


def test_paired_t_test_equals_scipys():
    rng = random.Random(5)
    for n in [2, 3, 5, 30, 180]:
        xs = [rng.gauss(100, 10) for _ in range(n)]
        ys = [x + rng.gauss(-2, 5) for x in xs]
        want = float(scipy_stats.ttest_rel(ys, xs).pvalue)
        assert stats.paired_t_test(xs, ys) == pytest.approx(want, rel=1e-10)
    with pytest.raises(ValueError):
        stats.paired_t_test([1, 2], [2, 3])  # no spread
    with pytest.raises(ValueError):
        stats.paired_t_test([1], [2])


def test_mean_ci_is_the_t_interval_clipped_to_the_range():
    values = [0, 0, 0, 1]
    mean, sd, lo, hi = stats.mean_ci(values)
    half = scipy_stats.t.ppf(0.975, 3) * sd / 2
    assert mean == 0.25 and lo < 0
    assert lo == pytest.approx(0.25 - half) and hi == pytest.approx(0.25 + half)
    _, _, lo, hi2 = stats.mean_ci(values, low=0.0)
    assert lo == 0.0 and hi2 == hi
    assert stats.mean_ci([5.0, 5.0], low=0.0, high=5.0)[2:] == (5.0, 5.0)
    assert stats.mean_ci([]) == (None, None, None, None)
    assert stats.mean_ci([3.0]) == (3.0, None, None, None)
