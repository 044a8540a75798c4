"""Differentiable graph A*: its forward is the exact A*, its trace backward equals the autograd loop's."""

import numpy as np
import pytest
import torch
from scipy.spatial import Delaunay

from navlab.graphs.region_graph import build_region_graph
from navlab.graphs.superpixels import label_consistent_slic
from navlab.search.diff_astar import batch_graphs, diff_astar
from navlab.search.diff_astar_reference import diff_astar_reference
from navlab.search.graph_astar import csr_graph, graph_astar
from synthetic_city import city


def planar_graph(rng, n):
    """Delaunay triangulation of random points: planar, degree ~6, like a superpixel adjacency graph."""
    centroid = rng.uniform(0.0, 100.0, (n, 2))
    tri = Delaunay(centroid).simplices
    return csr_graph(centroid, np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [0, 2]]]))


def random_batch(seed, sizes=(40, 90, 150), blocked_fraction=0.15, dtype=torch.float64):
    rng = np.random.default_rng(seed)
    graphs, starts, goals, blocked = [], [], [], []
    for n in sizes:
        graphs.append(planar_graph(rng, n))
        s, g = rng.choice(n, 2, replace=False)
        mask = rng.random(n) < blocked_fraction
        mask[[s, g]] = False
        starts.append(int(s))
        goals.append(int(g))
        blocked.append(mask)
    batch = batch_graphs(graphs, starts=starts, goals=goals, blocked=blocked, dtype=dtype)
    psi = torch.tensor(rng.uniform(0.0, 20.0, batch.shape) * (rng.random(batch.shape) < 0.5), dtype=dtype)
    return batch, psi, rng


def loss_gradient(search, batch, psi, w_closed, w_path, temperature, **kwargs):
    psi = psi.clone().requires_grad_(True)
    result = search(batch, psi, temperature=temperature, **kwargs)
    loss = (result.closed * w_closed).sum() + (result.path * w_path).sum() + result.cost[result.solved].sum()
    (grad,) = torch.autograd.grad(loss, psi)
    return result, grad


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("temperature", [1e-3, 2.0, 50.0])
def test_forward_is_exact_astar_and_backward_equals_autograd_loop(seed, temperature):
    batch, psi, rng = random_batch(seed)
    w_closed, w_path = (torch.tensor(rng.normal(size=batch.shape)) for _ in range(2))
    ours, grad = loss_gradient(diff_astar, batch, psi, w_closed, w_path, temperature)
    ref, grad_ref = loss_gradient(diff_astar_reference, batch, psi, w_closed, w_path, temperature)
    for i, sg in enumerate(batch.graphs):
        exact = graph_astar(sg, batch.starts[i], batch.goals[i], entry_cost=psi[i, :sg.num_nodes].numpy(),
                            blocked=~batch.enterable_np[i])
        for result in (ours, ref):
            assert np.array_equal(np.flatnonzero(result.closed[i].detach().numpy()), np.sort(exact.closed))
            assert set(np.unique(result.closed[i].detach().numpy())) <= {0.0, 1.0}
            if exact.nodes is None:
                assert result.paths[i] is None and not result.solved[i] and result.path[i].sum() == 0
            else:
                assert np.array_equal(result.paths[i], exact.nodes)
                assert np.array_equal(np.flatnonzero(result.path[i].detach().numpy()), np.sort(exact.nodes))
                assert float(result.cost[i].detach()) == pytest.approx(exact.cost, rel=1e-12)
    assert torch.isfinite(grad).all() and grad.abs().max() > 0
    torch.testing.assert_close(grad, grad_ref, rtol=1e-9, atol=1e-12)
    assert (grad[~batch.node_mask] == 0).all()


def test_gradient_is_the_closed_set_formula_and_chunking_does_not_change_it():
    batch, psi, rng = random_batch(7, sizes=(120, 120))
    w = torch.tensor(rng.normal(size=batch.shape))
    zero = torch.zeros_like(w)
    _, whole = loss_gradient(diff_astar, batch, psi, w, zero, 3.0)
    _, chunked = loss_gradient(diff_astar, batch, psi, w, zero, 3.0, chunk_size=5)
    torch.testing.assert_close(whole, chunked, rtol=1e-12, atol=1e-14)
    # raising one open node's Psi lowers its selection probability: for L = closed . e_j the gradient
    # at j is -(1/tau) sum_t y_tj (1 - y_tj) <= 0, and its neighbours in the open set gain (>= 0)
    result = diff_astar(batch, psi, temperature=3.0)
    j = int(result.paths[0][len(result.paths[0]) // 2])
    e_j = torch.zeros_like(w)
    e_j[0, j] = 1.0
    psi = psi.clone().requires_grad_(True)
    (g,) = torch.autograd.grad((diff_astar(batch, psi, temperature=3.0).closed * e_j).sum(), psi)
    assert g[0, j] < 0 and (g[0, torch.arange(batch.shape[1]) != j] >= 0).all() and (g[1] == 0).all()


def test_float32_tiny_temperature_has_no_nan_and_unreachable_goals_stop():
    # Neural A*'s exp(-f/tau) underflows to 0 (then NaN) once f/tau > ~104 in float32; log-softmax does not
    batch, psi, rng = random_batch(3, dtype=torch.float32)
    w = torch.tensor(rng.normal(size=batch.shape), dtype=torch.float32)
    _, grad = loss_gradient(diff_astar, batch, psi, w, w, 1e-4)
    _, grad_ref = loss_gradient(diff_astar_reference, batch, psi, w, w, 1e-4)
    assert torch.isfinite(grad).all() and torch.isfinite(grad_ref).all()
    # a wall of blocked nodes around the start: the search exhausts its component and reports no path
    sg = batch.graphs[0]
    start = batch.starts[0]
    wall = np.zeros(sg.num_nodes, dtype=bool)
    wall[sg.indices[sg.indptr[start]:sg.indptr[start + 1]]] = True
    goal = int(np.flatnonzero(~wall & (np.arange(sg.num_nodes) != start))[0])
    walled = batch_graphs([sg, batch.graphs[1]], starts=[start, batch.starts[1]], goals=[goal, batch.goals[1]],
                          blocked=[wall, None])
    result = diff_astar(walled, torch.zeros(walled.shape), temperature=1.0)
    assert result.solved.tolist() == [False, True] and result.paths[0] is None
    assert result.closed[0].sum() == 1 and torch.isinf(result.cost[0])


def test_region_graphs_batch_with_their_endpoints():
    m = city()
    graphs = [build_region_graph(label_consistent_slic(m.labels, n, 1.0), m.labels, m.frame, m.frame.resolution)
              .with_endpoints(np.array([5.5, 50.5]), np.array([115.5, 50.5])) for n in (80, 160)]
    batch = batch_graphs(graphs)
    assert batch.shape == (2, max(g.num_nodes for g in graphs))
    result = diff_astar(batch, torch.zeros(batch.shape), temperature=1.0)
    for i, g in enumerate(graphs):
        assert np.array_equal(result.paths[i], graph_astar(g, g.start_node, g.goal_node).nodes)


@pytest.mark.skipif(not torch.cuda.is_available(), reason="needs CUDA")
def test_cuda_matches_cpu():
    batch, psi, rng = random_batch(5)
    w = torch.tensor(rng.normal(size=batch.shape))
    _, grad = loss_gradient(diff_astar, batch, psi, w, w, 2.0)
    gpu = batch_graphs(batch.graphs, starts=batch.starts, goals=batch.goals,
                       blocked=[~e for e in batch.enterable_np], device="cuda", dtype=torch.float64)
    _, grad_gpu = loss_gradient(diff_astar, gpu, psi.cuda(), w.cuda(), w.cuda(), 2.0)
    torch.testing.assert_close(grad_gpu.cpu(), grad, rtol=1e-9, atol=1e-12)


def _bad_batch(case):
    sg = csr_graph(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), np.array([[0, 1], [1, 2]]))
    if case == "empty":
        return batch_graphs([])
    if case == "starts":
        return batch_graphs([sg, sg], starts=[0], goals=[2, 2])
    if case == "blocked start":
        return batch_graphs([sg], starts=[0], goals=[2], blocked=[np.array([True, False, False])])
    if case == "goal range":
        return batch_graphs([sg], starts=[0], goals=[5])
    if case == "no endpoints":
        m = city()
        return batch_graphs([build_region_graph(label_consistent_slic(m.labels, 40, 1.0), m.labels, m.frame, 1.0)])
    batch = batch_graphs([sg, sg], starts=[0, 0], goals=[2, 2])
    psi = {"shape": torch.zeros(2, 4), "nan": torch.tensor([[0.0, np.nan, 0.0]] * 2),
           "negative": torch.tensor([[0.0, -1.0, 0.0]] * 2), "int": torch.zeros(2, 3, dtype=torch.int64),
           "temperature": torch.zeros(2, 3)}[case]
    return diff_astar(batch, psi, temperature=0.0 if case == "temperature" else 1.0)


@pytest.mark.parametrize("case,msg", [
    ("empty", "at least one graph"), ("starts", "starts has 1 entries for 2 graphs"),
    ("blocked start", "start node 0 is blocked"), ("goal range", "goal node 5 is out of range"),
    ("no endpoints", "has no start node"), ("shape", r"psi has shape \(2, 4\) but the batch is"),
    ("nan", "NaN, inf or negative"), ("negative", "NaN, inf or negative"), ("int", "floating-point"),
    ("temperature", "temperature must be a positive"),
])
def test_bad_input_names_the_problem(case, msg):
    with pytest.raises(ValueError, match=msg):
        _bad_batch(case)
