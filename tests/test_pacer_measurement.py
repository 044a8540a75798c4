"""PACER's measurement (Tables I-IV): per-environment tiers, reference rows, intervals, held-out agreement."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.core.seeding import rng
from navlab.metrics.cost_tiers import TIER_NAMES, cost_tier_proportions
from navlab.metrics.intervals import bootstrap_mean_ci, bootstrap_ratio_ci
from navlab.pacer.aerial import AerialMap, aerial_maps
from navlab.pacer.bev import fov_mask
from navlab.pacer.datasets import evaluation_dataset
from navlab.pacer.evaluate import oracle_window_costs, window_oracle_costmap
from navlab.pacer.experiments import (
    context_limited_oracle_method,
    map_context,
    navigation_rows,
    terrain_costmap,
    uniform_method,
    window_oracle_method,
)
from navlab.pacer.preferences import (
    IGNORE,
    environment_tiers,
    mean_consistent_ranks,
    order_terrains,
    target_costmap,
)
from navlab.pacer.terrain import load_terrain_bank
from navlab.search.grid_astar import plan
from pacer_support import with_pacer_data


@pytest.fixture(scope="module")
def bank(smoke_data, smoke_params):
    return load_terrain_bank(smoke_data, smoke_params.pacer.data)


def test_bootstrap_intervals_cover_the_mean_and_shrink_with_the_sample():
    gen = rng(0, "values")
    small, large = gen.normal(0.4, 0.1, 10), gen.normal(0.4, 0.1, 400)
    lo, hi = bootstrap_mean_ci(small, rng(0, "ci"))
    assert lo < small.mean() < hi
    lo2, hi2 = bootstrap_mean_ci(large, rng(0, "ci"))
    assert lo2 < large.mean() < hi2 and (hi2 - lo2) < 0.4 * (hi - lo)  # ~ 1/sqrt(n)
    # the standard error of a mean of 400 N(0.4, 0.1) draws is 0.005: a 95% interval is ~0.02 wide
    assert 0.012 < hi2 - lo2 < 0.03
    assert bootstrap_mean_ci(np.full(7, 0.25), rng(0, "ci")) == (0.25, 0.25)
    lo, hi = bootstrap_ratio_ci(np.array([1, 2, 0, 3]), np.array([2, 2, 1, 3]), rng(0, "ratio"))
    assert lo <= 6 / 8 <= hi and 0 <= lo and hi <= 1
    with pytest.raises(ValueError, match="at least one value"):
        bootstrap_mean_ci(np.array([]), rng(0))


@pytest.mark.parametrize("target", ["in_view", "context"])
def test_window_oracle_reproduces_the_training_target_on_a_window(bank, smoke_params, smoke_data, target):
    data = smoke_params.pacer.data
    mask = fov_mask(data.image_size, data.camera.near_width)
    params = with_pacer_data(smoke_params, train_target=target)
    ds = evaluation_dataset(params, smoke_data, "seen", "inverted", bank=bank, context="superset")
    for i in range(6):
        item = ds.item(i)
        ranked = item["ordering"][item["ordering"] != IGNORE]
        shown = np.unique(item["labels"][item["fov_mask"]])
        if target == "in_view":
            # the map's hidden ordering names more terrains than the window shows; the window's target ranks
            # only those in view, in the same order
            others = np.setdiff1d(bank.ids("seen"), ranked)[:2]
            map_ordering = order_terrains(np.concatenate([ranked, others]), "inverted", bank, rng(i))
        else:  # the target ranks every terrain the context was drawn over, shown or not
            others, map_ordering = np.setdiff1d(ranked, shown)[:1], ranked
        outside = int(others[0]) if len(others) else int(shown[0])
        labels = np.where(item["fov_mask"], item["labels"], outside)  # another terrain outside the view
        oracle = oracle_window_costs(labels, mask, map_ordering, target)
        np.testing.assert_array_equal(oracle, item["costmap"])


def test_stitched_oracle_is_exact_where_every_window_sees_the_same_terrains(bank, smoke_params):
    data = smoke_params.pacer.data
    mask = fov_mask(data.image_size, data.camera.near_width)
    a, b = bank.ids("seen")[:2]
    labels = np.full((80, 96), a)
    labels[:, ::2] = b  # stripes: every window sees both terrains, so each is costed like on the whole map
    ordering = np.array([b, a])
    stitched = window_oracle_costmap(labels, ordering, mask).numpy()
    np.testing.assert_allclose(stitched, target_costmap(labels, ordering), atol=1e-6)


def test_uniform_row_is_the_plain_shortest_path(bank, smoke_params, smoke_data):
    P = smoke_params.pacer
    maps = aerial_maps(smoke_params, smoke_data, "seen", bank)
    result = navigation_rows(maps, {"Uniform costmap": (uniform_method(), True),
                                    "Window oracle": (window_oracle_method(P.data), True)},
                             bank, P.data, "realistic", P.evaluation.cost_scale, P.seed, queries_per_map=1)
    for k, amap in enumerate(maps):
        path = plan(np.ones(amap.labels.shape), amap.start, amap.goal)
        ordering, _, _ = map_context(bank, P.data, amap, "realistic", True, P.seed, k)
        shares = cost_tier_proportions(path.cells, amap.labels, environment_tiers(ordering, len(bank)))
        np.testing.assert_allclose(result.shares["Uniform costmap"][k], [shares[t] for t in TIER_NAMES])
        np.testing.assert_array_equal(result.paths["Uniform costmap"][k], path.cells)
        dr, dc = (abs(x - y) for x, y in zip(amap.start, amap.goal))
        assert path.cost == pytest.approx(max(dr, dc) + (np.sqrt(2) - 1) * min(dr, dc))  # octile distance
    rows = {r["method"]: r for r in result.rows}
    for row in rows.values():
        assert sum(row[t] for t in TIER_NAMES) == pytest.approx(1.0)
        for t in TIER_NAMES:
            lo, hi = row[f"{t}_ci"]
            assert lo - 1e-4 <= row[t] <= hi + 1e-4
    # the oracle knows every window's target: it keeps at least as much to the low tier as chance
    assert rows["Window oracle"]["low"] >= rows["Uniform costmap"]["low"] - 1e-9


def test_evaluation_contexts_are_drawn_both_ways_on_the_same_images(bank, smoke_params, smoke_data):
    params = with_pacer_data(smoke_params, train_target="in_view")  # the same targets whichever context is drawn
    view = evaluation_dataset(params, smoke_data, "unseen", "realistic", bank=bank, context="in_view")
    superset = evaluation_dataset(params, smoke_data, "unseen", "realistic", bank=bank, context="superset")
    grew = 0
    for i in range(8):
        a, b = view.item(i), superset.item(i)
        np.testing.assert_array_equal(a["image"], b["image"])
        np.testing.assert_array_equal(a["costmap"], b["costmap"])
        in_view = set(a["ordering"][a["ordering"] != IGNORE].tolist())
        assert set(a["pairs"].ravel().tolist()) <= in_view
        assert in_view <= set(b["pairs"].ravel().tolist())  # every terrain in view is named
        grew += not set(b["pairs"].ravel().tolist()) <= in_view
    assert grew > 0  # superset contexts name terrains outside the view
    with pytest.raises(ValueError, match="in_view or superset"):
        evaluation_dataset(smoke_params, smoke_data, "seen", "realistic", bank=bank, context="all")


@settings(max_examples=60, deadline=None)
@given(count=st.integers(1, 6), data=st.data())
def test_mean_consistent_ranks_match_enumerating_every_ordering(count, data):
    """The subset DP against brute force over all permutations, for random (acyclic) pair sets."""
    terrains = np.array(data.draw(st.permutations(range(10, 10 + count))), dtype=np.int64)
    hidden = data.draw(st.permutations(terrains.tolist()))  # pairs drawn from one order never contradict
    pairs = [(hidden[i], hidden[j]) for i, j in data.draw(st.lists(
        st.tuples(st.integers(0, count - 1), st.integers(0, count - 1)).filter(lambda p: p[0] < p[1]), max_size=4))]
    pairs.append((99, terrains[0]))  # a terrain not on the map constrains nothing
    agree = [p for p in itertools.permutations(terrains.tolist())
             if all(p.index(a) < p.index(b) for a, b in pairs if a in p and b in p)]
    expected = [np.mean([p.index(t) for p in agree]) for t in terrains.tolist()]
    np.testing.assert_allclose(mean_consistent_ranks(terrains, np.array(pairs).reshape(-1, 2)), expected)


def test_context_limited_oracle_costs_follow_the_pairs_and_average_the_rest(bank):
    a, b, c = (int(t) for t in bank.ids("seen")[:3])
    labels = np.array([[a, b, c]])
    amap = AerialMap(np.zeros((3, 1, 3), np.float32), labels, np.array(sorted([a, b, c])), (0, 0), (0, 2))
    cost = context_limited_oracle_method()(amap, None, None, np.array([[a, b]]))
    # a before b, c anywhere (abc, acb, cab): mean ranks a 1/3, b 5/3, c 1 of 0..2, costs rank / 2
    np.testing.assert_allclose(cost[0], [1 / 6, 5 / 6, 1 / 2], atol=1e-6)
    with pytest.raises(ValueError, match="contradict"):
        mean_consistent_ranks(np.array([a, b]), np.array([[a, b], [b, a]]))


@given(st.lists(st.integers(0, 5), min_size=1, max_size=40), st.lists(st.floats(0, 1, width=32), min_size=6, max_size=6))
def test_terrain_costmap_prices_every_pixel_by_its_terrain(labels, costs):
    labels = np.asarray(labels, dtype=np.int64).reshape(1, -1)
    cost_of = dict(enumerate(costs))
    expected = np.array([[np.float32(cost_of[t]) for t in labels[0]]], dtype=np.float32)
    assert terrain_costmap(labels, cost_of).dtype == np.float32
    np.testing.assert_array_equal(terrain_costmap(labels, cost_of), expected)


def test_terrain_costmap_names_an_unpriced_terrain():
    with pytest.raises(ValueError, match=r"terrains \[7\]"):
        terrain_costmap(np.array([[1, 7]]), {1: 0.5})
