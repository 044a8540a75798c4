"""What the relaxation-cost estimator reads: a region graph as a torch_geometric ``Data`` (Sec. IV-B, Eq. 7).

Node features are f_SR = [one-hot label, start indicator, goal indicator] (Eq. 7) concatenated with a
random-walk structural encoding (the return probabilities of 1..k-step random walks, GraphGPS's RWSE):
unlike Laplacian eigenvectors it has no sign or basis ambiguity, so the estimator stays exactly
equivariant to node order. Edges carry the centroid distance d(r_i, r_j) in both directions.

The estimator and the planner work on the *window* of the graph around a query: the nodes whose
centroid lies in the start-goal bounding box grown by a margin — the same box the synthetic expert
plans in (experts.pedestrian), so no demonstrated choice lies outside it, and the global attention
costs O(window^2) rather than O(map^2).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import torch
from torch_geometric.data import Data

from navlab.core.labels import SOFT_IDS
from navlab.graphs.region_graph import RegionGraph


def window_nodes(graph: RegionGraph, start_xy, goal_xy, margin_m: float) -> np.ndarray:
    """Sorted node indices whose centroid lies in the start-goal box grown by ``margin_m``; the start
    and goal nodes are always included."""
    corners = np.stack([np.asarray(start_xy, float), np.asarray(goal_xy, float)])
    lo, hi = corners.min(axis=0) - margin_m, corners.max(axis=0) + margin_m
    inside = np.all((graph.centroid >= lo) & (graph.centroid <= hi), axis=1)
    for node in (graph.start_node, graph.goal_node):
        if node >= 0:
            inside[node] = True
    return np.nonzero(inside)[0]


def induced_edges(graph: RegionGraph, nodes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(E', 2) edges among ``nodes`` renumbered 0..len(nodes)-1, and their centroid distances."""
    local = np.full(graph.num_nodes, -1, dtype=np.int64)
    local[nodes] = np.arange(len(nodes))
    e = local[graph.edges]
    keep = (e >= 0).all(axis=1)
    return e[keep], graph.edge_length[keep]


def random_walk_encoding(edges: np.ndarray, num_nodes: int, steps: int) -> np.ndarray:
    """(N, steps) float32: diag(P^k) for k = 1..steps, P the random-walk matrix D^-1 A (RWSE)."""
    if steps == 0:
        return np.zeros((num_nodes, 0), dtype=np.float32)
    both = np.concatenate([edges, edges[:, ::-1]]) if len(edges) else np.zeros((0, 2), np.int64)
    adj = sp.csr_matrix((np.ones(len(both)), (both[:, 0], both[:, 1])), shape=(num_nodes, num_nodes))
    deg = np.asarray(adj.sum(axis=1)).ravel()
    walk = sp.diags(1.0 / np.maximum(deg, 1.0)) @ adj
    out, power = [], sp.identity(num_nodes, format="csr")
    for _ in range(steps):
        power = power @ walk
        out.append(power.diagonal())
    return np.stack(out, axis=1).astype(np.float32)


def estimator_input(graph: RegionGraph, nodes: np.ndarray | None = None, walk_steps: int = 8) -> Data:
    """The estimator's input for ``graph`` (restricted to ``nodes`` when given; start/goal set on the graph).

    Fields: ``x`` (n, NUM_LABELS + 2 + walk_steps), ``edge_index`` (2, 2E'), ``edge_attr`` (2E', 1) metres,
    ``soft`` (n,) bool — the nodes in R_soft, the only ones with a nonzero cost —, ``nodes`` (n,) the
    indices in ``graph``.
    """
    nodes = np.arange(graph.num_nodes) if nodes is None else np.asarray(nodes, dtype=np.int64)
    edges, length = induced_edges(graph, nodes)
    features = graph.features[nodes]
    pe = random_walk_encoding(edges, len(nodes), walk_steps)
    both = np.concatenate([edges, edges[:, ::-1]]).T if len(edges) else np.zeros((2, 0), np.int64)
    return Data(x=torch.from_numpy(np.concatenate([features, pe], axis=1)),
                edge_index=torch.from_numpy(np.ascontiguousarray(both, dtype=np.int64)),
                edge_attr=torch.from_numpy(np.concatenate([length, length]).astype(np.float32)[:, None]),
                soft=torch.from_numpy(np.isin(graph.node_label[nodes], SOFT_IDS)),
                nodes=torch.from_numpy(nodes), num_nodes=len(nodes))
