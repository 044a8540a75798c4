"""navlab.metrics.crossed: the crossed seeds x units bootstrap and the strict verdicts on it. One seed is the
units' own bootstrap exactly; the seeds' spread widens the interval to what drawing seeds again would give;
a difference a lucky seed carries is inconclusive where a bootstrap over maps alone would call it."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.seeding import rng
from navlab.metrics import claims as engine
from navlab.metrics import crossed
from navlab.metrics.intervals import RESAMPLES


def test_one_seed_is_the_units_own_bootstrap():
    values = rng(0, "units").uniform(0, 1, 17)
    gen = np.random.default_rng(5)
    means = crossed.resampled_means(values[None], gen)
    again = np.random.default_rng(5)
    again.integers(0, 1, size=(RESAMPLES, 1))  # the seed draws come first (all seed 0)
    cols = again.integers(0, 17, size=(RESAMPLES, 17))
    np.testing.assert_allclose(means, values[cols].mean(axis=1))


def test_the_seeds_spread_widens_the_interval_to_the_seeds_own_distribution():
    # maps identical, seeds 0 / 1 / 2 apart: a bootstrap over maps has no width, the crossed one is the mean of
    # three seeds drawn with replacement, whose 2.5% and 97.5% points are 0 and 2 (P(all 0) = 1/27 > 2.5%)
    grid = np.repeat(np.array([[0.0], [1.0], [2.0]]), 20, axis=1)
    lo, hi = crossed.interval(grid, rng(0, "t"))
    assert (lo, hi) == (0.0, 2.0)
    assert crossed.interval(grid.mean(axis=0), rng(0, "t")) == (1.0, 1.0)


def test_a_difference_one_seed_reverses_is_inconclusive():
    # every map agrees, but the seeds disagree: +0.20, +0.25 and -0.15; the seed mean +0.10 looks certain to a
    # bootstrap over maps, the crossed test sees a seed draw of three -0.15s in 1 of 27
    maps = 24
    b = rng(1, "maps").uniform(0.3, 0.7, maps)
    a = b + np.array([[0.20], [0.25], [-0.15]]) + 0.01 * rng(2, "noise").standard_normal((3, maps))
    assert engine.paired_difference(a.mean(axis=0), b, "higher", rng(0, "t")).verdict == "holds"
    test = crossed.paired_difference(a, b, "higher", rng(0, "t"), "maps")
    assert test.verdict == "inconclusive" and "3 seeds x 24 maps" in test.evidence


@pytest.mark.parametrize(("shift", "direction", "verdict"), [
    (0.0, "higher", "inconclusive"),  # a tie
    (0.2, "higher", "holds"),
    (0.2, "lower", "does not hold"),
])
def test_paired_difference_is_strict(shift, direction, verdict):
    b = rng(1, "maps").uniform(0.3, 0.7, 12)
    a = b + shift + 0.01 * rng(3, "noise").standard_normal((3, 12))
    assert crossed.paired_difference(a, b, direction, rng(0, "t")).verdict == verdict
    assert "too few" in crossed.paired_difference(a[:, :5], b[:5], direction, rng(0, "t")).evidence


def test_on_par_best_of_and_the_two_sample_rule():
    b = rng(1, "maps").uniform(0.3, 0.7, 12)
    near = b + 0.01 * rng(3, "noise").standard_normal((3, 12))
    assert crossed.on_par(near, b, 0.1, rng(0, "t")).verdict == "holds"
    assert crossed.on_par(near + 0.5, b, 0.1, rng(0, "t")).verdict == "does not hold"
    assert crossed.best_of({"a": near + 0.2, "b": b, "c": near}, "a", "higher", rng(0, "t")).verdict == "holds"
    assert crossed.best_of({"a": near, "b": b + 0.2}, "a", "higher", rng(0, "t")).verdict == "does not hold"
    seen, unseen = near, near[:, :9] - 0.2
    assert crossed.two_sample_difference(seen, unseen, "higher", rng(0, "t")).verdict == "holds"
    assert crossed.two_sample_difference(seen, seen, "higher", rng(0, "t")).verdict == "inconclusive"
    with pytest.raises(ValueError, match="same"):
        crossed.two_sample_difference(seen, unseen[:2], "higher", rng(0, "t"))


def test_ratio_interval_of_a_constant_share_is_that_share():
    room = rng(1, "room").uniform(0.1, 0.5, 15)
    lo, hi = crossed.ratio_interval(np.stack([0.4 * room] * 3), room, rng(0, "t"))
    assert lo == pytest.approx(0.4) and hi == pytest.approx(0.4)


def test_bad_samples_are_refused():
    with pytest.raises(ValueError, match="finite"):
        crossed.interval(np.array([[0.1, np.nan]]), rng(0, "t"))
    with pytest.raises(ValueError, match="share neither"):
        crossed.paired_difference(np.zeros((3, 6)), np.zeros((2, 6)), "higher", rng(0, "t"))
