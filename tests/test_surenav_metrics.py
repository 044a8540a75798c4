"""SuReNav benchmark metrics against independent references and analytic values."""

from __future__ import annotations

import numpy as np
import pytest
import similaritymeasures

from navlab.core.labels import HARD_IDS
from navlab.metrics.frechet import discrete_frechet, discrete_frechet_reference, normalised_frechet
from navlab.metrics.intervals import bootstrap_mean_ci, wilson_ci
from navlab.metrics.navigation import (
    path_length,
    risk_table,
    shortest_feasible_length,
    spl,
    success,
    total_risk,
)
from navlab.metrics.relaxation import relaxed_regions, set_iou
from navlab.search.grid_astar import plan
from synthetic_city import L, city


@pytest.mark.parametrize("n, m", [(1, 1), (1, 7), (6, 1), (30, 30), (57, 23), (200, 140)])
def test_frechet_equals_similaritymeasures(n, m):
    rng = np.random.default_rng(n * 1000 + m)
    p, q = rng.normal(size=(n, 2)).cumsum(axis=0), rng.normal(size=(m, 2)).cumsum(axis=0)
    expected = similaritymeasures.frechet_dist(p, q)
    assert discrete_frechet(p, q) == pytest.approx(expected, rel=1e-12, abs=1e-12)
    assert discrete_frechet_reference(p, q) == pytest.approx(expected, rel=1e-12, abs=1e-12)
    assert discrete_frechet(q, p) == pytest.approx(expected, rel=1e-12, abs=1e-12)  # symmetric


def test_frechet_of_a_curve_with_itself_is_zero_and_normalisation_is_scale_free():
    p = np.random.default_rng(0).normal(size=(40, 2)).cumsum(axis=0)
    assert discrete_frechet(p, p) == 0.0
    q = p + np.array([0.0, 3.0])  # a parallel copy: the leash is exactly the offset
    assert discrete_frechet(p, q) == pytest.approx(3.0)
    a = normalised_frechet(p, q, p[0], p[-1])
    assert normalised_frechet(5 * p, 5 * q, 5 * p[0], 5 * p[-1]) == pytest.approx(a)
    with pytest.raises(ValueError, match="start and goal coincide"):
        normalised_frechet(p, q, p[0], p[0])
    with pytest.raises(ValueError, match=r"\(K, 2\)"):
        discrete_frechet(np.zeros((0, 2)), q)


def test_iou_of_a_set_with_itself_is_one():
    a = np.array([3, 1, 4, 1, 5])
    assert set_iou(a, a) == 1.0
    assert set_iou(a, [9, 8]) == 0.0
    assert set_iou([1, 2, 3], [2, 3, 4, 5]) == pytest.approx(2 / 5)
    assert set_iou([], []) == 1.0


def test_relaxed_regions_keep_soft_cells_only():
    labels = np.array([[L["sidewalk"], L["grass"], L["road"]]])
    superpixels = np.array([[0, 1, 2]])
    cells = np.array([[0, 0], [0, 1], [0, 2]])
    assert relaxed_regions(cells, labels, superpixels).tolist() == [1, 2]


def test_spl_is_one_for_the_shortest_path_itself_and_lower_for_a_detour():
    smap = city()
    free = np.argwhere(smap.labels == L["sidewalk"])
    start, goal = tuple(free[0]), tuple(free[-1])
    cost = np.where(np.isin(smap.labels, HARD_IDS), np.inf, 1.0)
    shortest = plan(cost, start, goal).cells
    ell_star = shortest_feasible_length(smap.labels, start, goal, 1.0)
    assert path_length(shortest, 1.0) == pytest.approx(ell_star)
    assert success(shortest, smap.labels, goal)
    assert spl(True, path_length(shortest, 1.0), ell_star) == pytest.approx(1.0)
    detour = np.concatenate([shortest, shortest[::-1][1:], shortest[1:]])  # there, back and there again
    assert spl(True, path_length(detour, 1.0), ell_star) == pytest.approx(1 / 3)
    assert spl(False, path_length(shortest, 1.0), ell_star) == 0.0
    assert not success(shortest[:-1], smap.labels, goal)


def test_success_fails_on_a_hard_cell():
    labels = np.full((1, 3), L["sidewalk"], dtype=np.uint8)
    labels[0, 1] = L["building"]
    assert not success(np.array([[0, 0], [0, 1], [0, 2]]), labels, (0, 2))


def test_total_risk_is_the_path_integral():
    table = risk_table({"sidewalk": 0.0, "crosswalk": 0.1, "road": 1.0, "living_street": 0.5, "parking": 0.4,
                        "grass": 0.3, "rough_terrain": 0.7})
    labels = np.full((3, 12), L["road"], dtype=np.uint8)
    labels[:, :2] = L["sidewalk"]
    line = np.stack([np.ones(12, int), np.arange(12)], axis=1)
    # one sidewalk step (0), one step half sidewalk half road, 9 road steps at 1.0/m; 2 m cells
    assert total_risk(line, labels, table, 2.0) == pytest.approx(2.0 * (0.5 + 9 * 1.0))
    with pytest.raises(ValueError, match="unit_risk lacks"):
        risk_table({"sidewalk": 0.0})


def test_wilson_and_bootstrap_intervals():
    lo, hi = wilson_ci(20, 20)
    z2 = 1.959963984540054 ** 2
    assert hi == 1.0 and lo == pytest.approx(20 / (20 + z2))
    lo, hi = wilson_ci(10, 20)
    assert lo < 0.5 < hi and hi - 0.5 == pytest.approx(0.5 - lo)
    values = np.random.default_rng(1).normal(2.0, 1.0, size=200)
    lo, hi = bootstrap_mean_ci(values, np.random.default_rng(2), 2000)
    assert lo < values.mean() < hi
    half = 1.96 * values.std(ddof=1) / np.sqrt(len(values))  # the normal-theory interval, for scale
    assert (hi - lo) / 2 == pytest.approx(half, rel=0.15)
    assert bootstrap_mean_ci(np.full(5, 0.7), np.random.default_rng(0), 100) == pytest.approx((0.7, 0.7))
    with pytest.raises(ValueError, match="NaN"):
        bootstrap_mean_ci([1.0, np.nan], np.random.default_rng(0), 10)
