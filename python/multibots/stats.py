"""The statistics ``multibots compare`` reports, in plain Python (no SciPy needed).

- :func:`t_ppf`, :func:`t_sf`: Student's t distribution, through the regularised incomplete
  beta function (:func:`betainc`, a continued fraction evaluated with Lentz's method);
- :func:`mean_ci`: the mean with its t-based confidence interval, optionally clipped to the
  range the quantity can take (a count is never below 0);
- :func:`paired_t_test`: the two-sided p-value of the paired t test;
- :func:`wilcoxon`: the two-sided p-value of the Wilcoxon signed-rank test.

Each gives the value SciPy gives (``scipy.stats.t``, ``ttest_rel``, ``wilcoxon`` with its
defaults) to about 12 significant digits; ``tests/test_stats.py`` checks them against SciPy.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from typing import Optional

__all__ = ["betainc", "mean_ci", "paired_t_test", "t_cdf", "t_ppf", "t_sf", "wilcoxon"]

_EPS = 1e-16
_TINY = 1e-300


def _beta_cf(a: float, b: float, x: float) -> float:
    """The continued fraction of the incomplete beta function (modified Lentz)."""
    qab, qap, qam = a + b, a + 1.0, a - 1.0
    c, d = 1.0, 1.0 - qab * x / qap
    d = 1.0 / (d if abs(d) > _TINY else _TINY)
    h = d
    for m in range(1, 1000):
        m2 = 2 * m
        aa = m * (b - m) * x / ((qam + m2) * (a + m2))
        d = 1.0 + aa * d
        d = 1.0 / (d if abs(d) > _TINY else _TINY)
        c = 1.0 + aa / c
        c = c if abs(c) > _TINY else _TINY
        h *= d * c
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2))
        d = 1.0 + aa * d
        d = 1.0 / (d if abs(d) > _TINY else _TINY)
        c = 1.0 + aa / c
        c = c if abs(c) > _TINY else _TINY
        step = d * c
        h *= step
        if abs(step - 1.0) < _EPS:
            break
    return h


def betainc(a: float, b: float, x: float) -> float:
    """The regularised incomplete beta function I_x(a, b), for a, b > 0 and 0 <= x <= 1."""
    if not (a > 0 and b > 0):
        raise ValueError(f"betainc: a = {a}, b = {b}: must be greater than 0")
    if not 0.0 <= x <= 1.0:
        raise ValueError(f"betainc: x = {x}: must be from 0 to 1")
    if x == 0.0 or x == 1.0:
        return x
    log_front = a * math.log(x) + b * math.log1p(-x) - (math.lgamma(a) + math.lgamma(b) - math.lgamma(a + b))
    # The fraction converges fast for x below (a + 1) / (a + b + 2); above, use the symmetry.
    if x < (a + 1.0) / (a + b + 2.0):
        return math.exp(log_front) * _beta_cf(a, b, x) / a
    return 1.0 - math.exp(log_front) * _beta_cf(b, a, 1.0 - x) / b


def _t_centre(t: float, df: float) -> float:
    """P(0 < T < t) for t >= 0: accurate near the centre, where 1 - P(T > t) loses digits."""
    t2 = t * t
    return 0.5 * betainc(0.5, df / 2.0, t2 / (df + t2))


def _t_upper(t: float, df: float) -> float:
    """P(T > t) for t >= 0: accurate in the tail."""
    return 0.5 * betainc(df / 2.0, 0.5, df / (df + t * t))


def t_sf(t: float, df: float) -> float:
    """P(T > t) for Student's t with ``df`` degrees of freedom."""
    if math.isinf(t):
        return 0.0 if t > 0 else 1.0
    a = abs(t)
    # Near the centre 0.5 - P(0 < T < t) keeps every digit; in the tail it would lose them all.
    centre = _t_centre(a, df)
    tail = 0.5 - centre if centre < 0.25 else _t_upper(a, df)
    return tail if t >= 0 else 1.0 - tail


def t_cdf(t: float, df: float) -> float:
    """P(T <= t) for Student's t with ``df`` degrees of freedom."""
    return t_sf(-t, df)


def _t_pdf(t: float, df: float) -> float:
    log = (math.lgamma((df + 1) / 2) - math.lgamma(df / 2) - 0.5 * math.log(df * math.pi)
           - (df + 1) / 2 * math.log1p(t * t / df))
    return math.exp(log)


def t_ppf(q: float, df: float) -> float:
    """The ``q`` quantile of Student's t with ``df`` degrees of freedom (inverse of t_cdf)."""
    if not 0.0 < q < 1.0:
        raise ValueError(f"t_ppf: q = {q}: must be strictly between 0 and 1")
    if q < 0.5:
        return -t_ppf(1.0 - q, df)
    if q == 0.5:
        return 0.0
    # Solve P(0 < T < x) = q - 0.5 near the centre and P(T > x) = 1 - q in the tail, so that
    # neither side loses digits to a subtraction.
    if q < 0.75:
        target, gap, sign = q - 0.5, lambda x: _t_centre(x, df), -1.0
    else:
        target, gap, sign = 1.0 - q, lambda x: _t_upper(x, df), 1.0
    # Bracket the root, then Newton steps that fall back to bisection outside the bracket.
    lo, hi = 0.0, 1.0
    while sign * (gap(hi) - target) > 0:
        lo, hi = hi, hi * 2.0
    x = (lo + hi) / 2.0
    for _ in range(200):
        f = sign * (gap(x) - target)
        if f > 0:
            lo = x
        else:
            hi = x
        nxt = x + f / _t_pdf(x, df)
        if not lo < nxt < hi:
            nxt = (lo + hi) / 2.0
        if abs(nxt - x) <= 1e-15 * max(1e-300, abs(x)):
            return nxt
        x = nxt
    return x


def mean_ci(
    values: Sequence[float], level: float = 0.95, low: Optional[float] = None, high: Optional[float] = None
) -> tuple[Optional[float], Optional[float], Optional[float], Optional[float]]:
    """Mean, standard deviation and the t confidence interval of the mean.

    The interval is mean ± t(1 - (1 - level) / 2, n - 1) · sd / √n, then clipped to
    [``low``, ``high``] when given: the interval of a count never reaches below 0.

    Returns:
        (mean, sd, ci_low, ci_high), None where undefined (no values; one value has no sd).
    """
    n = len(values)
    if n == 0:
        return None, None, None, None
    mean = statistics.fmean(values)
    if n == 1:
        return mean, None, None, None
    sd = statistics.stdev(values)
    half = t_ppf(1.0 - (1.0 - level) / 2.0, n - 1) * sd / math.sqrt(n)
    lo, hi = mean - half, mean + half
    if low is not None:
        lo = max(lo, low)
    if high is not None:
        hi = min(hi, high)
    return mean, sd, lo, hi


def paired_t_test(xs: Sequence[float], ys: Sequence[float]) -> float:
    """Two-sided p-value of the paired t test of ``ys`` against ``xs`` (``ttest_rel(ys, xs)``).

    Raises:
        ValueError: fewer than two pairs, or the differences have no spread (t undefined).
    """
    diffs = [y - x for x, y in zip(xs, ys)]
    n = len(diffs)
    if n < 2:
        raise ValueError("paired_t_test needs at least two pairs")
    sd = statistics.stdev(diffs)
    if sd == 0:
        raise ValueError("paired_t_test: the differences are all equal (t is undefined)")
    t = statistics.fmean(diffs) / (sd / math.sqrt(n))
    return min(1.0, 2.0 * t_sf(abs(t), n - 1))


def _ranks(values: Sequence[float]) -> tuple[list[float], list[int]]:
    """Ranks 1..n, ties given their average rank, and the size of every group of ties."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    ranks = [0.0] * len(values)
    groups = []
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            ranks[order[k]] = (i + j) / 2.0 + 1.0
        groups.append(j - i + 1)
        i = j + 1
    return ranks, groups


def _exact_signed_rank_p(ranks: Sequence[float], r_plus: float) -> float:
    """Two-sided p of R+ under its exact null distribution: each sign + or - with
    probability 1/2, over the ranks as they are (ties keep their average ranks)."""
    doubled = [round(2 * r) for r in ranks]  # average ranks are halves: whole numbers here
    total = sum(doubled)
    counts = [0] * (total + 1)
    counts[0] = 1
    for r in doubled:
        for s in range(total, r - 1, -1):
            counts[s] += counts[s - r]
    observed = round(2 * r_plus)
    below = sum(counts[: observed + 1])
    above = sum(counts[observed:])
    return min(1.0, 2.0 * min(below, above) / 2 ** len(doubled))


def wilcoxon_floor(n: int) -> float:
    """The smallest two-sided p-value the exact Wilcoxon signed-rank test can give with ``n``
    nonzero differences: every difference of one sign, 2 / 2^n. With 5 pairs that is 0.0625,
    so no data can reach p < 0.05."""
    return min(1.0, 2.0 / 2.0**n) if n > 0 else 1.0


def pairs_to_reach(alpha: float = 0.05) -> int:
    """The fewest pairs with which the exact Wilcoxon test can give p below ``alpha``."""
    n = 1
    while wilcoxon_floor(n) >= alpha:
        n += 1
    return n


def wilcoxon(diffs: Sequence[float], correction: bool = False) -> float:
    """Two-sided p-value of the Wilcoxon signed-rank test that ``diffs`` centre on 0.

    Zero differences are dropped (Wilcoxon's method); the others are ranked by size, ties
    given their average rank. As SciPy's ``wilcoxon`` with its defaults:

    - without ties and with at most 50 differences, the exact null distribution of R+ (the
      sum of the positive differences' ranks);
    - with ties and at most 13 differences, the exact distribution of R+ over the 2^n sign
      patterns of the tied ranks (SciPy's exact permutation test);
    - otherwise the normal approximation, with the variance corrected for ties, and with the
      continuity correction (SciPy's ``correction=True``) if ``correction``.

    Raises:
        ValueError: every difference is zero (nothing to test).
    """
    nonzero = [d for d in diffs if d != 0]
    n = len(nonzero)
    if n == 0:
        raise ValueError("wilcoxon: every difference is zero")
    ranks, groups = _ranks([abs(d) for d in nonzero])
    r_plus = sum(r for r, d in zip(ranks, nonzero) if d > 0)
    ties = any(g > 1 for g in groups)
    if (not ties and n <= 50) or (ties and n <= 13):
        return _exact_signed_rank_p(ranks, r_plus)
    mean = n * (n + 1) / 4.0
    se = math.sqrt((n * (n + 1) * (2 * n + 1) - sum(g**3 - g for g in groups) / 2.0) / 24.0)
    z = (r_plus - mean) / se
    if correction:
        z -= math.copysign(0.5, z) / se if z != 0 else 0.0
    return min(1.0, math.erfc(abs(z) / math.sqrt(2.0)))
