"""95% confidence intervals for figures computed from a sample (docs/design.md, "The report contract").

A table cell that averages over environments carries a percentile-bootstrap interval over those
environments (Efron and Tibshirani, "An Introduction to the Bootstrap", 1993, ch. 13): resample the
environments with replacement, recompute the mean, take the 2.5th and 97.5th percentiles. A paired
difference (method A minus method B on the same environments) is bootstrapped the same way, which is
what says whether A beats B rather than whether their two intervals happen to overlap. A success rate
gets the Wilson score interval, which stays inside [0, 1] and is sensible at 100% success (where a
bootstrap collapses to a point).
"""

from __future__ import annotations

import numpy as np
from scipy.stats import norm

LEVEL = 0.95
RESAMPLES = 2000


def bootstrap_mean_ci(values: np.ndarray, rng: np.random.Generator, resamples: int = RESAMPLES,
                      level: float = LEVEL) -> tuple[float, float]:
    """(lo, hi) percentile-bootstrap interval of the mean of ``values`` (one number per environment)."""
    values = np.asarray(values, dtype=np.float64).ravel()
    if len(values) == 0:
        raise ValueError("bootstrap_mean_ci needs at least one value (one per environment)")
    if not np.isfinite(values).all():
        raise ValueError("bootstrap_mean_ci: values hold NaN or inf; drop or report missing environments first")
    if not 0.0 < level < 1.0:
        raise ValueError(f"level {level}: a confidence level lies strictly between 0 and 1")
    means = values[rng.integers(0, len(values), size=(resamples, len(values)))].mean(axis=1)
    tail = 100.0 * (1.0 - level) / 2.0
    lo, hi = np.percentile(means, [tail, 100.0 - tail])
    return float(lo), float(hi)


def bootstrap_ratio_ci(numerators: np.ndarray, denominators: np.ndarray, rng: np.random.Generator,
                       resamples: int = RESAMPLES, level: float = LEVEL) -> tuple[float, float]:
    """(lo, hi) percentile-bootstrap interval of sum(numerators) / sum(denominators), resampling the
    units (e.g. images, each contributing several correlated pair comparisons) with replacement."""
    num = np.asarray(numerators, dtype=np.float64).ravel()
    den = np.asarray(denominators, dtype=np.float64).ravel()
    if len(num) != len(den) or len(num) == 0 or den.sum() <= 0:
        raise ValueError("bootstrap_ratio_ci needs equally many numerators and denominators, with a positive total")
    draws = rng.integers(0, len(num), size=(resamples, len(num)))
    ratios = num[draws].sum(axis=1) / np.maximum(den[draws].sum(axis=1), 1e-12)
    tail = 100.0 * (1.0 - level) / 2.0
    lo, hi = np.percentile(ratios, [tail, 100.0 - tail])
    return float(lo), float(hi)


def wilson_ci(successes: int, trials: int, level: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a success rate."""
    if trials <= 0 or not 0 <= successes <= trials:
        raise ValueError(f"wilson_ci: need 0 <= successes ({successes}) <= trials ({trials}) and trials > 0")
    z = float(norm.ppf(0.5 + level / 2))
    p = successes / trials
    centre = (p + z * z / (2 * trials)) / (1 + z * z / trials)
    half = z * np.sqrt(p * (1 - p) / trials + z * z / (4 * trials * trials)) / (1 + z * z / trials)
    return float(max(0.0, centre - half)), float(min(1.0, centre + half))
