"""Intervals and strict verdicts over two crossed random factors: training seeds x evaluation units.

Why: a learned method's table cell averages over the maps it is evaluated on *and* the seeds it was trained
with, and both vary from one reproduction to the next. A bootstrap over maps alone treats the seeds as fixed
and is too narrow; one over (seed, map) pairs as if independent counts each map once per seed and is too
narrow too. Every seed is scored on the same maps, so the two factors are crossed, and the interval here
resamples them independently, seeds with replacement and maps with replacement, the mean taken over the
resampled grid (the "pigeonhole" bootstrap for crossed random effects, Owen, Ann. Appl. Stat. 2007; McCullagh,
Bernoulli 2000 shows it is conservative for the variance of a crossed mean, never anti-conservative).

Values are arrays (seeds, units); a single-seed method (a baseline, an oracle) is one row, broadcast against
the seeds it is compared with. The verdict rules are ``navlab.metrics.claims``' (a tie or an interval covering
zero is inconclusive; "on par" holds only inside the margin), on this interval.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from navlab.metrics.claims import ALPHA, MIN_UNITS, Direction, Test, Verdict
from navlab.metrics.intervals import RESAMPLES


def as_grid(values) -> np.ndarray:
    """``values`` as (seeds, units): a 1-D sample is one seed."""
    grid = np.asarray(values, dtype=np.float64)
    grid = grid[None] if grid.ndim == 1 else grid
    if grid.ndim != 2 or grid.size == 0 or not np.isfinite(grid).all():
        raise ValueError(f"a crossed sample is a non-empty (seeds, units) array of finite values (got shape "
                         f"{np.shape(values)})")
    return grid


def _paired(a, b) -> np.ndarray:
    """a - b on the same units, a single-seed side broadcast over the other's seeds; the same seed count
    on both sides pairs them by seed (the phases of one seed's training chain)."""
    a, b = as_grid(a), as_grid(b)
    if a.shape[1] != b.shape[1] or (a.shape[0] != b.shape[0] and 1 not in (a.shape[0], b.shape[0])):
        raise ValueError(f"crossed paired test: shapes {a.shape} and {b.shape} share neither units nor seeds")
    return a - b


def resampled_means(grid: np.ndarray, gen: np.random.Generator, resamples: int = RESAMPLES,
                    seeds: np.ndarray | None = None) -> np.ndarray:
    """``resamples`` grand means of ``grid`` (seeds, units), seeds and units drawn independently with
    replacement; ``seeds`` (resamples, seeds) fixes the seed draws (two groups sharing their seeds)."""
    rows, cols = _draws(grid.shape, gen, resamples, seeds)
    per_seed = grid[:, cols].mean(axis=2)  # (seeds, resamples): each seed's mean over the drawn units
    return np.take_along_axis(per_seed.T, rows, axis=1).mean(axis=1)


def _draws(shape: tuple[int, int], gen: np.random.Generator, resamples: int = RESAMPLES,
           seeds: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """One crossed resampling of a (seeds, units) grid: (resamples, seeds) seed indices (``seeds`` if given),
    then (resamples, units) unit indices, each drawn with replacement and apart from the other."""
    s, n = shape
    rows = gen.integers(0, s, size=(resamples, s)) if seeds is None else seeds
    return rows, gen.integers(0, n, size=(resamples, n))


def _percentile_interval(resampled: np.ndarray) -> tuple[float, float]:
    lo, hi = np.percentile(resampled, [100 * ALPHA / 2, 100 * (1 - ALPHA / 2)])
    return float(lo), float(hi)


def interval(values, gen: np.random.Generator) -> tuple[float, float]:
    """95% crossed-bootstrap interval of the grand mean of ``values`` (seeds, units)."""
    return _percentile_interval(resampled_means(as_grid(values), gen))


def ratio_interval(numerators, denominators, gen: np.random.Generator) -> tuple[float, float]:
    """95% crossed-bootstrap interval of sum(numerators) / sum(denominators) per seed, averaged over seeds
    (the share of a gap closed: numerators (seeds, units), denominators one row or one per seed)."""
    num, den = as_grid(numerators), as_grid(denominators)
    den = np.broadcast_to(den, num.shape)
    rows, cols = _draws(num.shape, gen)
    ratios = num[:, cols].sum(axis=2) / np.maximum(den[:, cols].sum(axis=2), 1e-12)  # (s, B)
    return _percentile_interval(np.take_along_axis(ratios.T, rows, axis=1).mean(axis=1))


def _side(lo: float, hi: float, sign: float) -> Verdict:
    lo, hi = sorted((sign * lo, sign * hi))
    return "holds" if lo > 0 else "does not hold" if hi < 0 else "inconclusive"


def _shape(grid: np.ndarray, unit: str) -> str:
    seeds = grid.shape[0]
    return f"{grid.shape[1]} {unit}" if seeds == 1 else f"{seeds} seeds x {grid.shape[1]} {unit}, crossed bootstrap"


def _sign(direction: Direction) -> float:
    if direction not in ("higher", "lower"):
        raise ValueError(f"direction {direction!r}: use 'higher' or 'lower'")
    return 1.0 if direction == "higher" else -1.0


def paired_difference(a, b, direction: Direction, gen: np.random.Generator, unit: str = "units",
                      names: tuple[str, str] = ("A", "B")) -> Test:
    """Is ``a`` ``direction`` than ``b`` on the same units, over the seeds? The crossed 95% interval of
    mean(a - b)."""
    sign, d = _sign(direction), _paired(a, b)
    head = f"{names[0]} - {names[1]} = {d.mean():+.4g}"
    if d.shape[1] < MIN_UNITS:
        return Test("inconclusive", f"{head}; {d.shape[1]} {unit}: too few for a verdict (at least {MIN_UNITS})")
    lo, hi = interval(d, gen)
    return Test(_side(lo, hi, sign), f"{head}, 95% CI [{lo:+.4g}, {hi:+.4g}], paired over {_shape(d, unit)}")


def on_par(a, b, margin: float, gen: np.random.Generator, unit: str = "units",
           names: tuple[str, str] = ("A", "B")) -> Test:
    """Equivalence within ``margin``: holds if the whole crossed 95% interval of mean(a - b) lies inside
    (-margin, margin), does not hold if it lies wholly outside."""
    if not margin > 0:
        raise ValueError(f"on_par: margin {margin} must be positive")
    d = _paired(a, b)
    head = f"{names[0]} - {names[1]} = {d.mean():+.4g}"
    if d.shape[1] < MIN_UNITS:
        return Test("inconclusive", f"{head}; {d.shape[1]} {unit}: too few for a verdict (at least {MIN_UNITS})")
    lo, hi = interval(d, gen)
    verdict: Verdict = ("holds" if -margin < lo and hi < margin else
                        "does not hold" if lo >= margin or hi <= -margin else "inconclusive")
    return Test(verdict, f"{head}, 95% CI [{lo:+.4g}, {hi:+.4g}] over {_shape(d, unit)}; on par means inside "
                         f"±{margin:g}")


def best_of(values: Mapping[str, object], claimed: str, direction: Direction, gen: np.random.Generator,
            unit: str = "units") -> Test:
    """``claimed`` beats each other method (paired, crossed); does not hold if any other beats it."""
    if claimed not in values or len(values) < 2:
        raise ValueError(f"best_of: {claimed!r} and at least one other method are needed (got {list(values)})")
    tests = {m: paired_difference(values[claimed], v, direction, gen, unit, (claimed, m))
             for m, v in values.items() if m != claimed}
    verdicts = {t.verdict for t in tests.values()}
    verdict: Verdict = ("does not hold" if "does not hold" in verdicts else
                        "holds" if verdicts == {"holds"} else "inconclusive")
    return Test(verdict, " | ".join(f"vs {m}: {t.verdict} ({t.evidence})" for m, t in tests.items()))


def two_sample_difference(a, b, direction: Direction, gen: np.random.Generator, unit: str = "maps",
                          names: tuple[str, str] = ("A", "B")) -> Test:
    """Is mean(``a``) ``direction`` than mean(``b``) where no unit pairs the two (seen and unseen maps) but
    the seeds do (one seed's model on both)? Seeds are drawn once for both sides, each side's units apart."""
    sign = _sign(direction)
    a, b = as_grid(a), as_grid(b)
    if a.shape[0] != b.shape[0]:
        raise ValueError(f"two_sample_difference: {a.shape[0]} and {b.shape[0]} seeds; both sides need the same")
    head = f"{names[0]} - {names[1]} = {a.mean() - b.mean():+.4g}"
    if min(a.shape[1], b.shape[1]) < MIN_UNITS:
        return Test("inconclusive", f"{head}; {a.shape[1]} and {b.shape[1]} {unit}: too few for a verdict (at "
                                    f"least {MIN_UNITS} each)")
    seeds = gen.integers(0, a.shape[0], size=(RESAMPLES, a.shape[0]))
    diff = resampled_means(a, gen, seeds=seeds) - resampled_means(b, gen, seeds=seeds)
    lo, hi = _percentile_interval(diff)
    return Test(_side(lo, hi, sign), f"{head}, 95% CI [{lo:+.4g}, {hi:+.4g}], unpaired: {a.shape[1]} and "
                                     f"{b.shape[1]} {unit} resampled apart, {a.shape[0]} seed(s) shared")
