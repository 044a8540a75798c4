"""Exact graph A* returns Eq. (6)-optimal node paths: checked against scipy's Dijkstra (csgraph)."""

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from navlab.graphs.region_graph import build_region_graph
from navlab.graphs.superpixels import label_consistent_slic
from navlab.search.graph_astar import csr_graph, graph_astar, graph_astar_reference, search_graph
from synthetic_city import city


def random_graph(rng, n, extra_edges):
    """Random centroids joined by a random spanning-ish set of edges (may leave nodes unconnected)."""
    centroid = rng.uniform(0.0, 100.0, (n, 2))
    a, b = rng.integers(0, n, (2, extra_edges))
    edges = np.stack([a, b], axis=1)[a != b]
    return csr_graph(centroid, edges)


def dijkstra_eq6(sg, start, goal, psi, blocked):
    """Eq. (6) by Dijkstra: arc i -> j weighs d_ij + Psi_j, arcs into blocked nodes removed, + Psi_start."""
    tail = np.repeat(np.arange(sg.num_nodes), sg.degree)
    keep = ~blocked[sg.indices]
    w = sg.length[keep] + psi[sg.indices[keep]]
    m = csr_matrix((w, (tail[keep], sg.indices[keep])), shape=(sg.num_nodes, sg.num_nodes))
    return float(dijkstra(m, indices=start)[goal]) + psi[start]


@settings(max_examples=80, deadline=None)
@given(seed=st.integers(0, 100_000), n=st.integers(2, 60), density=st.floats(0.5, 4.0),
       psi_scale=st.sampled_from([0.0, 1.0, 30.0]), blocked_fraction=st.floats(0.0, 0.3))
def test_cost_equals_dijkstra_with_entry_costs(seed, n, density, psi_scale, blocked_fraction):
    rng = np.random.default_rng(seed)
    sg = random_graph(rng, n, int(density * n) + 1)
    psi = rng.uniform(0.0, 1.0, n) * psi_scale
    blocked = rng.random(n) < blocked_fraction
    start, goal = rng.choice(n, 2, replace=False)
    blocked[[start, goal]] = False
    ours = graph_astar(sg, start, goal, entry_cost=psi, blocked=blocked)
    reference = dijkstra_eq6(sg, start, goal, psi, blocked)
    plain = graph_astar_reference(sg, start, goal, entry_cost=psi, blocked=blocked)
    assert np.array_equal(ours.closed, plain.closed)  # compiled kernel = plain heapq loop, step by step
    if not math.isfinite(reference):
        assert ours.nodes is None and math.isinf(ours.cost) and plain.nodes is None
        return
    assert ours.cost == pytest.approx(reference, rel=1e-12, abs=1e-9)
    assert np.array_equal(ours.nodes, plain.nodes) and ours.cost == plain.cost
    nodes = ours.nodes
    assert nodes[0] == start and nodes[-1] == goal and not blocked[nodes].any()
    assert len(set(nodes.tolist())) == len(nodes)
    adjacent = {(int(i), int(j)) for i in range(n) for j in sg.indices[sg.indptr[i]:sg.indptr[i + 1]]}
    assert all((int(i), int(j)) in adjacent for i, j in itertools.pairwise(nodes))
    walked = np.linalg.norm(np.diff(sg.centroid[nodes], axis=0), axis=1).sum() + psi[nodes].sum()
    assert walked == pytest.approx(ours.cost, rel=1e-12)
    assert ours.closed[-1] == goal and set(nodes.tolist()) <= set(ours.closed.tolist())


def test_region_graph_query_and_heuristic_pruning():
    m = city()
    rg = build_region_graph(label_consistent_slic(m.labels, 200, 1.0), m.labels, m.frame, m.frame.resolution)
    rg = rg.with_endpoints(np.array([5.5, 50.5]), np.array([115.5, 50.5]))
    sg = search_graph(rg)
    assert np.allclose(np.sort(sg.length[::1])[::2], np.sort(rg.edge_length))  # Eq. 6's d, both directions
    path = graph_astar(rg, rg.start_node, rg.goal_node)
    tail = np.repeat(np.arange(sg.num_nodes), sg.degree)
    dist = dijkstra(csr_matrix((sg.length, (tail, sg.indices)), shape=(rg.num_nodes,) * 2), indices=rg.start_node)
    assert path.cost == pytest.approx(dist[rg.goal_node], rel=1e-12)
    # Dijkstra closes every node nearer than the goal; the consistent heuristic closes fewer
    assert len(path.closed) < (dist < path.cost).sum()


def test_entry_cost_detours_around_an_expensive_node():
    # a square 0-1-3, 0-2-3: both routes are equally long; Psi on node 1 sends the path through 2
    sg = csr_graph(np.array([[0.0, 0.0], [1.0, 1.0], [1.0, -1.0], [2.0, 0.0]]), np.array([[0, 1], [1, 3], [0, 2], [2, 3]]))
    assert graph_astar(sg, 0, 3).nodes.tolist() == [0, 1, 3]  # tie: lower index first
    path = graph_astar(sg, 0, 3, entry_cost=np.array([0.0, 5.0, 0.0, 0.0]))
    assert path.nodes.tolist() == [0, 2, 3] and path.cost == pytest.approx(2 * math.sqrt(2))
    assert graph_astar(sg, 0, 3, blocked=np.array([False, False, True, False])).nodes.tolist() == [0, 1, 3]


@pytest.mark.parametrize("kwargs,start,goal,msg", [
    ({"blocked": np.array([True, False, False])}, 0, 2, "start node 0 is blocked"),
    ({"blocked": np.array([False, False, True])}, 0, 2, "goal node 2 is blocked"),
    ({}, 0, 3, "goal node 3 is out of range"),
    ({}, -1, 2, "start node -1 is out of range"),
    ({"entry_cost": np.array([0.0, np.nan, 0.0])}, 0, 2, "NaN, inf or negative"),
    ({"entry_cost": np.array([0.0, -1.0, 0.0])}, 0, 2, "NaN, inf or negative"),
    ({"entry_cost": np.zeros(4)}, 0, 2, r"shape \(3,\)"),
    ({"blocked": np.zeros(3)}, 0, 2, "bool array"),
])
def test_bad_queries_name_the_problem(kwargs, start, goal, msg):
    sg = csr_graph(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), np.array([[0, 1], [1, 2]]))
    with pytest.raises(ValueError, match=msg):
        graph_astar(sg, start, goal, **kwargs)


def test_bad_graphs_name_the_problem():
    with pytest.raises(ValueError, match="no nodes"):
        csr_graph(np.zeros((0, 2)), np.zeros((0, 2)))
    with pytest.raises(ValueError, match="outside 0..1"):
        csr_graph(np.zeros((2, 2)), np.array([[0, 2]]))
    with pytest.raises(ValueError, match="NaN or inf"):
        csr_graph(np.array([[0.0, np.nan], [1.0, 1.0]]), np.array([[0, 1]]))
