"""SuReNav's relax-plan step (Algorithm 1, Sec. V): graph A* under Psi picks R_rlx, then the low-level plan."""

import numpy as np
import pytest
import torch

from navlab.core.io import DataError
from navlab.core.labels import HARD_IDS, SOFT_IDS, label_id
from navlab.core.params import load_params
from navlab.graphs.region_graph import build_region_graph
from navlab.surenav.artifacts import model_path
from navlab.surenav.model.estimator import architecture, build_estimator
from navlab.surenav.policy import MODES, SuReNavPolicy, estimator_cost, learned_policy, scored_cost
from synthetic_city import ZEBRAS, zebra_band

CROSSWALK, GRASS = label_id("crosswalk"), label_id("grass")


def label_cost(table: dict[int, float]):
    """A hand-set Psi by label (0 where the table has nothing)."""
    return lambda graph, nodes, *_: np.array([table.get(int(lab), 0.0) for lab in graph.node_label[nodes]])


@pytest.fixture(scope="module")
def town():
    smap, sp = zebra_band()
    return smap, build_region_graph(sp, smap.labels, smap.frame, tau=1.0)


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("cols", [(0, 0), (5, 6), (11, 4)])
def test_plan_relaxes_only_what_the_graph_plan_chose(town, mode, cols):
    smap, graph = town
    policy = SuReNavPolicy(label_cost({CROSSWALK: 0.0, GRASS: 200.0}), mode, window_margin_m=100.0)
    start, goal = (1, 3 * cols[0] + 1), (22, 3 * cols[1] + 1)
    cells = policy.plan(smap, graph, start, goal)
    assert tuple(cells[0]) == start and tuple(cells[-1]) == goal
    assert np.abs(np.diff(cells, axis=0)).max() <= 1  # 8-connected steps
    lab = smap.labels[cells[:, 0], cells[:, 1]]
    assert not np.isin(lab, HARD_IDS).any()
    assert not (lab == GRASS).any()  # grass costs 200 m per region: a crosswalk detour is cheaper
    relaxed = np.isin(graph.superpixels[cells[:, 0], cells[:, 1]], policy.last_relaxed)
    assert relaxed[np.isin(lab, SOFT_IDS)].all()  # every soft cell walked lies in R_rlx
    assert set(np.unique(graph.node_label[np.searchsorted(graph.region_ids, policy.last_relaxed)])) == {CROSSWALK}
    crossing_cols = np.unique(cells[np.isin(lab, SOFT_IDS), 1] // 3)
    assert set(crossing_cols) <= set(ZEBRAS)


def test_cheap_grass_is_crossed_straight(town):
    smap, graph = town
    policy = SuReNavPolicy(label_cost({CROSSWALK: 0.0, GRASS: 0.0}), "free_union", window_margin_m=100.0)
    cells = policy.plan(smap, graph, (1, 16), (22, 16))
    assert (smap.labels[cells[:, 0], cells[:, 1]] == GRASS).any()
    assert len(cells) == 22  # the straight line, one row per step


def test_within_mode_stays_in_the_graph_plan(town):
    smap, graph = town
    policy = SuReNavPolicy(label_cost({GRASS: 200.0}), "within", window_margin_m=100.0)
    cells = policy.plan(smap, graph, (1, 1), (22, 34))
    route = policy.graph_plan(graph, smap.frame.cell_to_world(np.array([1, 1])),
                              smap.frame.cell_to_world(np.array([22, 34])))
    assert np.isin(graph.node_raster[cells[:, 0], cells[:, 1]], route).all()


def test_learned_cost_is_zero_on_free_nodes_and_the_policy_plans(town):
    smap, graph = town
    params = load_params("smoke").surenav.model
    torch.manual_seed(0)
    cost = estimator_cost(build_estimator(params))
    g = graph.with_endpoints(np.array([1.5, 1.5]), np.array([34.5, 22.5]))
    nodes = np.arange(g.num_nodes)
    psi = cost(g, nodes, None, None)
    soft = np.isin(g.node_label, SOFT_IDS)
    assert psi.shape == (g.num_nodes,) and np.all(psi[~soft] == 0) and np.all(psi[soft] > 0)
    cells = SuReNavPolicy(cost, "free_union", params.window_margin_m).plan(smap, graph, (1, 1), (22, 34))
    assert cells is not None and tuple(cells[-1]) == (22, 34)


def test_scored_cost_is_zero_on_free_nodes_and_scaled_on_soft_ones(town):
    _, graph = town
    nodes = np.arange(graph.num_nodes)
    psi = scored_cost(lambda g, n, p, q: np.full(len(n), 0.25), 8.0)(graph, nodes, None, None)
    soft = np.isin(graph.node_label, SOFT_IDS)
    assert np.all(psi[~soft] == 0) and np.allclose(psi[soft], 2.0)


def test_unknown_mode_is_one_clear_error():
    with pytest.raises(ValueError, match="surenav.planner.mode"):
        SuReNavPolicy(label_cost({}), "centroids")


def test_learned_policy_loads_the_trained_estimator(town, tmp_path):
    smap, graph = town
    params = load_params("smoke").surenav
    torch.manual_seed(0)
    model = build_estimator(params.model)
    path = model_path(tmp_path, "gps", params.train.seeds[0])
    path.parent.mkdir(parents=True)
    torch.save({**architecture(model), "weights": model.state_dict()}, path)
    policy = learned_policy(tmp_path, params)()
    cells = policy.plan(smap, graph, (1, 1), (22, 34))
    assert cells is not None and tuple(cells[-1]) == (22, 34)
    with pytest.raises(DataError, match="surenav_estimator"):
        learned_policy(tmp_path, params, "mpnn")


def test_benchmark_makes_surenav_runs_and_stops_on_a_missing_estimator(town, tmp_path):
    """The benchmark's SuReNav runs: a seed of the GPS estimator, RCR's scoring in its place, the MPNN
    ablation; ``benchmark_runs`` loads every estimator first, so a missing one stops before any episode."""
    from navlab.surenav.benchmark import (
        SURENAV,
        SURENAV_MPNN,
        SURENAV_RCR,
        Learned,
        benchmark_runs,
        seed_run,
        surenav_policy,
    )

    smap, graph = town
    p = load_params("smoke")
    learned = Learned(np.ones(1), np.zeros(0, dtype=int), str(tmp_path), p.surenav)
    with pytest.raises(DataError, match="surenav_estimator"):
        benchmark_runs(learned)
    torch.manual_seed(0)
    for variant, attention in (("gps", True), ("mpnn", False)):
        model = build_estimator(p.surenav.model, attention)
        path = model_path(tmp_path, variant, p.surenav.train.seeds[0])
        path.parent.mkdir(parents=True)
        torch.save({**architecture(model), "weights": model.state_dict()}, path)
    runs, methods = benchmark_runs(learned)
    assert seed_run(SURENAV, p.surenav.train.seeds[0]) in runs and SURENAV_RCR in runs
    assert {SURENAV, SURENAV_RCR, SURENAV_MPNN} <= set(methods)
    for run in (seed_run(SURENAV, 0), SURENAV_RCR, seed_run(SURENAV_MPNN, 0)):
        policy = surenav_policy(run, learned, p.surenav.benchmark)
        cells = policy.plan(smap, graph, (1, 1), (22, 34))
        assert cells is not None and tuple(cells[-1]) == (22, 34), run
    rcr = surenav_policy(SURENAV_RCR, learned, p.surenav.benchmark)
    rcr.plan(smap, graph, (1, 1), (22, 34))
    assert len(rcr.last_relaxed) > 0  # the band must be crossed: RCR's scores decided where
