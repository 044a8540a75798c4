"""The SuReNav benchmark on the smoke dataset: training-only priors, episodes, the runner (its claims:
test_surenav_claims)."""

from __future__ import annotations

import shutil
from dataclasses import replace

import numpy as np
import pytest

from navlab.core.labels import FREE_IDS, HARD_IDS, NUM_LABELS, label_id
from navlab.maps.dataset import load_maps
from navlab.surenav.benchmark import (
    EXPERT,
    SURENAV,
    Learned,
    Outcome,
    fig4_rows,
    method_of,
    run_all,
    seed_run,
    surenav_runs,
    table1_rows,
)
from navlab.surenav.demo_priors import (
    LabelTraversal,
    class_order,
    dstar_label_costs,
    label_traversal,
    load_training_traversal,
)
from navlab.surenav.episodes import (
    CITIES,
    build_episodes,
    connected,
    human_likeness_environments,
    load_city_episodes,
    safety_efficiency_environments,
    window,
)
from navlab.surenav.experts.store import load_demos


@pytest.fixture(scope="module")
def episodes_dir(tmp_path_factory, smoke_params, smoke_data):
    """Only the `surenav_episodes` artefact (the others are not needed here)."""
    out = tmp_path_factory.mktemp("episodes")
    build_episodes(smoke_params, smoke_data, out)
    return out


def test_priors_never_read_test_demonstrations(smoke_data, tmp_path):
    """The traversal (and so D* Lite's costs and COA*'s order) is the same when every validation and
    test demonstration file is garbage, and label_traversal refuses them outright."""
    before = load_training_traversal(smoke_data)
    copy = tmp_path / "data"
    shutil.copytree(smoke_data, copy, symlinks=True)
    for split in ("val", "test"):
        for f in (copy / "surenav" / "demos" / split).glob("*.npz"):
            f.write_bytes(b"not an archive")
    after = load_training_traversal(copy)
    assert np.array_equal(before.traversed, after.traversed) and np.array_equal(before.total, after.total)
    with pytest.raises(ValueError, match="training demonstrations only"):
        label_traversal(load_demos(smoke_data, "test"), load_maps(smoke_data, "test"))


def test_dstar_costs_are_scaled_reciprocal_rates():
    traversed = np.array([50, 10, 5, 0, 2, 8, 1, 0, 0])
    total = np.array([100, 40, 50, 10, 20, 40, 20, 5, 5])
    t = LabelTraversal(traversed, total)
    cost = dstar_label_costs(t, 0.1)
    assert cost[0] == pytest.approx(0.1)  # the most traversed label: the floor
    assert cost[label_id("rough_terrain")] == pytest.approx(1.0)  # the least traversed: the top
    assert cost[label_id("living_street")] == 1.0  # never traversed: the top as well
    assert np.isinf(cost[HARD_IDS]).all()
    inverse = total[:7] / np.maximum(traversed[:7], 1)
    seen = traversed[:7] > 0
    expected = 0.1 + 0.9 * (inverse[seen] - inverse[seen].min()) / (inverse[seen].max() - inverse[seen].min())
    assert cost[:7][seen] == pytest.approx(expected)
    order = class_order(t)
    # soft labels only, least traversed (most critical) first; road and parking tie at 0.1 (id order)
    assert order.tolist() == [label_id(n) for n in ("living_street", "rough_terrain", "road", "parking", "grass",
                                                     "crosswalk")]
    with pytest.raises(ValueError, match="floor"):
        dstar_label_costs(t, 0.0)


def test_episodes_are_valid_and_perturbed(smoke_data, episodes_dir, smoke_params):
    cities = load_city_episodes(episodes_dir)
    assert [c.city for c in cities] == list(CITIES)
    maps = {m.name: m for m in load_maps(smoke_data, "test")}
    margin = int(np.ceil(smoke_params.surenav.benchmark.executor.window_margin_m / 2.0))
    for ce in cities:
        smap = maps[ce.map_name]
        truth = ce.truth(smap.labels)
        assert len(ce.starts) == smoke_params.surenav.benchmark.episodes.per_city
        assert len(ce.delta_cells) and (truth.ravel()[ce.delta_cells] != smap.labels.ravel()[ce.delta_cells]).all()
        for s, g in zip(ce.starts, ce.goals, strict=True):
            assert np.isin(truth[tuple(s)], FREE_IDS) and np.isin(truth[tuple(g)], FREE_IDS)
            d = np.hypot(*(s - g)) * smap.frame.resolution
            assert 30.0 <= d <= 200.0
            assert connected(truth, s, g, window(truth.shape, s, g, margin))


@pytest.fixture(scope="module")
def smoke_outcomes(smoke_data, episodes_dir, smoke_params):
    settings = smoke_params.surenav.benchmark
    learned = Learned.from_training(smoke_data, settings)
    methods = ["D* Lite", "COA*", "RCR", EXPERT]
    se = safety_efficiency_environments(smoke_data, episodes_dir)[::3]
    hl = human_likeness_environments(smoke_data)[:2]
    run = {"learned": learned, "settings": settings, "graph": smoke_params.surenav.graph, "progress": False}
    return methods, run_all(se, methods, **run), run_all(hl, methods, data_dir=smoke_data, **run)


def test_runner_outcomes_are_consistent(smoke_outcomes, smoke_params):
    methods, se, hl = smoke_outcomes
    for o in se + hl:
        assert 0.0 <= o.spl <= 1.0 and o.total_risk >= 0.0
        assert o.length_m + 1e-9 >= o.shortest_m or not o.success
        assert o.success == (o.status == "reached")
    for o in hl:
        assert o.frechet is not None and o.frechet >= 0 and 0.0 <= o.relaxation_iou <= 1.0
    rows = fig4_rows(se, methods, smoke_params.surenav.benchmark)
    assert {r["method"] for r in rows} == set(methods)
    for r in rows:
        for col in ("sr", "spl", "total_risk"):  # the bounds are rounded to 4 decimals
            assert r[f"{col}_ci"][0] - 5e-5 <= r[col] <= r[f"{col}_ci"][1] + 5e-5
    t1 = table1_rows(hl, methods, smoke_params.surenav.benchmark)
    assert [r["method"] for r in t1] == methods


def test_dstar_costs_of_the_smoke_data_are_finite_on_walkable_labels(smoke_data, smoke_params):
    learned = Learned.from_training(smoke_data, smoke_params.surenav.benchmark)
    walkable = ~np.isin(np.arange(NUM_LABELS), HARD_IDS)
    assert np.isfinite(learned.dstar_costs[walkable]).all() and (learned.dstar_costs[walkable] > 0).all()
    assert learned.dstar_costs[label_id("sidewalk")] == pytest.approx(smoke_params.surenav.benchmark.dstar_cost_floor)


def test_workers_do_not_change_outcomes(smoke_data, episodes_dir, smoke_params):
    settings = smoke_params.surenav.benchmark
    learned = Learned.from_training(smoke_data, settings)
    envs = safety_efficiency_environments(smoke_data, episodes_dir)[:2]
    run = {"learned": learned, "graph": smoke_params.surenav.graph, "progress": False}
    one = run_all(envs, ["RCR", EXPERT], settings=settings, **run)
    two = run_all(envs, ["RCR", EXPERT], settings=replace(settings, workers=2), **run)
    assert [(o.method, o.environment) for o in one] == [(o.method, o.environment) for o in two]
    for a, b in zip(one, two, strict=True):
        assert np.array_equal(a.trajectory, b.trajectory) and a.total_risk == b.total_risk


def _outcome(run, env, success, spl, iou):
    return Outcome(run, env, "milan", "reached" if success else "stuck", success, 100.0, 90.0, spl, 1.0, 0.2, iou,
                   (0.01,), np.zeros((2, 2)))


def test_seed_runs_are_averaged_per_environment_with_their_spread(smoke_params):
    settings = smoke_params.surenav.benchmark
    assert method_of(seed_run(SURENAV, 2)) == SURENAV and method_of("RCR") == "RCR"
    assert [method_of(r) for r in surenav_runs([0, 1], [0])].count(SURENAV) == 2
    spl = {(0, "e0"): 0.8, (0, "e1"): 0.6, (0, "e2"): 1.0, (1, "e0"): 0.4, (1, "e1"): 0.6, (1, "e2"): 0.8}
    outcomes = [_outcome(seed_run(SURENAV, k), e, spl[k, e] > 0.5, spl[k, e], spl[k, e] / 2) for k, e in spl]
    outcomes += [_outcome("RCR", e, True, 0.5, 0.25) for e in ("e0", "e1", "e2")]
    rows = {r["method"]: r for r in fig4_rows(outcomes, [SURENAV, "RCR"], settings)}
    row = rows[SURENAV]
    assert row["episodes"] == 3 and row["seeds"] == 2
    assert row["spl"] == pytest.approx(np.mean(list(spl.values())))
    assert row["spl_seed_sd"] == pytest.approx(np.std([0.8, 0.6], ddof=1), abs=1e-4)  # seed means 0.8 and 0.6
    assert row["sr"] == pytest.approx(5 / 6) and row["sr_seed_sd"] == pytest.approx(np.std([1.0, 2 / 3], ddof=1), abs=1e-4)
    assert row["spl_ci"][0] <= row["spl"] <= row["spl_ci"][1]
    assert rows["RCR"]["seeds"] == 1 and rows["RCR"]["spl_seed_sd"] is None
    t1 = {r["method"]: r for r in table1_rows(outcomes, [SURENAV, "RCR"], settings)}
    assert t1[SURENAV]["environments"] == 3 and t1[SURENAV]["relaxation_iou"] == pytest.approx(0.35)
