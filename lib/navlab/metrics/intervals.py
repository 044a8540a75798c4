"""95% intervals for the benchmark's numbers: the paper reports single numbers, ours say how sure they are.

Means over environments get a percentile bootstrap (Efron & Tibshirani 1993), resampling environments
with replacement, vectorised as one (B, n) index draw; success rates get the Wilson score interval,
which stays inside [0, 1] and is sensible at 100% success (where a bootstrap collapses to a point).
"""

from __future__ import annotations

import numpy as np
from scipy.stats import norm


def bootstrap_mean_ci(values, rng: np.random.Generator, samples: int, level: float = 0.95) -> tuple[float, float]:
    """Percentile bootstrap interval of the mean of ``values`` (one per environment); NaN entries are
    an error (a metric that does not exist for an environment must be left out by the caller)."""
    values = np.asarray(values, dtype=float).ravel()
    if values.size == 0:
        raise ValueError("bootstrap_mean_ci: no values (no environments were measured)")
    if not np.isfinite(values).all():
        raise ValueError("bootstrap_mean_ci: values hold NaN or inf; drop undefined environments first")
    if samples < 1 or not 0 < level < 1:
        raise ValueError(f"bootstrap_mean_ci: samples {samples} must be >= 1 and level {level} in (0, 1)")
    means = values[rng.integers(values.size, size=(samples, values.size))].mean(axis=1)
    tail = (1 - level) / 2
    lo, hi = np.quantile(means, [tail, 1 - tail])
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
