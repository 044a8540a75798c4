"""COA* returns the lexicographically best (class counts, most critical first, then length) path:
checked against brute force over every simple path of small random coloured graphs."""

import math
from itertools import pairwise

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from navlab.search.coa_star import coa_star, coa_star_grid
from navlab.search.grid_astar import plan
from navlab.search.grid_graph import grid_csr


def _random_coloured_graph(rng, n, p, n_classes):
    graph = nx.gnp_random_graph(n, p, seed=int(rng.integers(1 << 31)))
    for u, v in graph.edges:
        graph.edges[u, v]["weight"] = float(rng.uniform(0.5, 3.0))
    node_class = rng.integers(0, n_classes, n)
    return graph, node_class


def _brute_force(graph, node_class, order, source, target, blocked):
    """min over simple paths of (per-class edge counts in ``order``, length), lexicographically."""
    rank = {c: r for r, c in enumerate(order)}
    best = None
    allowed = graph.subgraph([v for v in graph if not blocked[v]])
    if source not in allowed or target not in allowed or not nx.has_path(allowed, source, target):
        return None
    for path in nx.all_simple_paths(allowed, source, target) if source != target else [[source]]:
        counts = [0] * len(order)
        for u, v in pairwise(path):
            r = min(rank.get(node_class[u], len(order)), rank.get(node_class[v], len(order)))
            if r < len(order):
                counts[r] += 1
        length = sum(graph.edges[u, v]["weight"] for u, v in pairwise(path))
        if best is None or (counts, length) < best:
            best = (counts, length)
    return best


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 100_000), n=st.integers(2, 9), p=st.floats(0.2, 0.7), n_classes=st.integers(1, 4),
       with_heuristic=st.booleans())
def test_lexicographic_optimum_equals_brute_force(seed, n, p, n_classes, with_heuristic):
    rng = np.random.default_rng(seed)
    graph, node_class = _random_coloured_graph(rng, n, p, n_classes)
    order = [int(c) for c in rng.permutation(n_classes)[: int(rng.integers(0, n_classes + 1))]]
    blocked = rng.random(n) < 0.15
    source, target = 0, n - 1
    blocked[[source, target]] = False
    csr = nx.to_scipy_sparse_array(graph, nodelist=range(n), weight="weight", format="csr")
    heuristic = None
    if with_heuristic:  # a consistent length heuristic: half the true distance to the target
        heuristic = 0.5 * np.nan_to_num(dijkstra(csr_matrix(csr), indices=target), posinf=0.0)
    ours = coa_star(csr.indptr, csr.indices, csr.data, node_class, order, source, target,
                    heuristic=heuristic, blocked=blocked)
    best = _brute_force(graph, node_class, order, source, target, blocked)
    if best is None:
        assert ours.path is None and math.isinf(ours.cost)
        return
    assert ours.counts.tolist() == best[0]
    assert ours.cost == pytest.approx(best[1], rel=1e-12)
    path = ours.path.tolist()
    assert path[0] == source and path[-1] == target and not blocked[path].any()
    assert all(graph.has_edge(u, v) for u, v in pairwise(path))
    assert sum(graph.edges[u, v]["weight"] for u, v in pairwise(path)) == pytest.approx(ours.cost, rel=1e-12)


def test_one_fewer_critical_crossing_beats_any_detour():
    """Road (class 2) ranked above grass (class 1): the path detours to the far end of the road to cross
    its one grass cell rather than cross a single road cell, however long the detour."""
    labels = np.zeros((7, 30), np.int64)
    labels[3, :] = 2  # a road across the map, except at the far end
    labels[3, 29] = 1  # where it is grass
    cost = np.ones(labels.shape)
    found = coa_star_grid(labels, cost, [2, 1], (0, 0), (6, 0))
    assert found.counts.tolist() == [0, 2]  # entering and leaving the grass cell
    assert found.cost > 50  # the detour, not the 6-step straight line
    assert not (labels[found.path[:, 0], found.path[:, 1]] == 2).any()
    straight = coa_star_grid(labels, cost, [1, 2], (0, 0), (6, 0))  # grass now the critical one
    assert straight.counts.tolist() == [0, 2] and straight.cost == pytest.approx(6.0)


def test_without_ranked_classes_it_is_grid_astar():
    rng = np.random.default_rng(3)
    cost = rng.uniform(1.0, 3.0, (15, 15))
    cost[rng.random(cost.shape) < 0.2] = np.inf
    cost[0, 0] = cost[14, 14] = 1.0
    labels = rng.integers(0, 3, cost.shape)
    found = coa_star_grid(labels, cost, [], (0, 0), (14, 14), resolution=0.5)
    reference = plan(cost, (0, 0), (14, 14), resolution=0.5)
    if reference.cells is None:
        assert found.path is None
    else:
        assert found.cost == pytest.approx(reference.cost, rel=1e-12)


def test_grid_graph_matches_grid_astar_costs():
    rng = np.random.default_rng(5)
    cost = rng.uniform(1.0, 3.0, (9, 11))
    dist = dijkstra(grid_csr(cost, resolution=2.0), indices=0)
    assert dist[-1] == pytest.approx(plan(cost, (0, 0), (8, 10), resolution=2.0).cost, rel=1e-12)


@pytest.mark.parametrize("kwargs,msg", [
    ({"indptr": [0]}, "empty"),
    ({"weights": [1.0, np.nan]}, "finite and >= 0"),
    ({"weights": [1.0, -1.0]}, "finite and >= 0"),
    ({"indices": [1, 5]}, "node ids"),
    ({"node_class": [0, 0, 0]}, "node_class"),
    ({"class_order": [1, 1]}, "twice"),
    ({"start": 7}, "start node 7 is not in the graph"),
    ({"blocked": [False, True]}, "goal node 1 is blocked"),
])
def test_bad_input_names_the_problem(kwargs, msg):
    args = {"indptr": [0, 1, 2], "indices": [1, 0], "weights": [1.0, 1.0], "node_class": [0, 1],
            "class_order": [1], "start": 0, "goal": 1} | kwargs
    blocked = args.pop("blocked", None)
    with pytest.raises(ValueError, match=msg):
        coa_star(*args.values(), blocked=blocked)


def test_grid_endpoints_in_blocked_cells_are_errors():
    cost = np.ones((4, 4))
    cost[3, 3] = np.inf
    with pytest.raises(ValueError, match="goal .* blocked"):
        coa_star_grid(np.zeros((4, 4), int), cost, [0], (0, 0), (3, 3))
    with pytest.raises(ValueError, match="same shape"):
        coa_star_grid(np.zeros((3, 4), int), np.ones((4, 4)), [0], (0, 0), (3, 3))
