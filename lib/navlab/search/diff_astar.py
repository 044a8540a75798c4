"""Batched differentiable graph A* (Neural A* / GraphMP; SuReNav Eq. 1-3 and 9-11), sparse and exact.

Yonetani et al., "Path Planning using Neural A* Search", ICML 2021; Kang et al., GraphMP (the graph
form SuReNav Sec. III reviews); SuReNav (Koh et al., ICRA 2026) Eq. (9)-(11) add the entry cost Psi.

The search. At step t every graph selects, among its open nodes O_t, the one of least
f = g_ext + h = (g + Psi) + h (Eq. 9-10). The selection is a straight-through one-hot
(Eq. 1's I_max): its value is the hard one-hot ŷ_t of the arg-min (ties to the lower node index), its
gradient that of y_t = softmax_{O_t}(z_t) with z_t = -f_t / tau (a masked log-softmax, so nothing
underflows however large f / tau grows). The closed set is c = sum_t ŷ_t, each graph stopping when
it selects its goal (the goal is closed). As in Neural A*, g, the open set and the parents are not
differentiated through (they are the exact A*'s): the gradient reaches Psi only through the softmax.

The fast route. The forward pass is the exact search (``graph_astar.astar_kernel``, compiled), run
without autograd; it records each step's open set with the g of every open node. Its value therefore
*is* the exact A*'s closed set and path. The backward rebuilds the softmax terms from that record.
Derivation, for any loss L(c) with v = dL/dc (one graph; steps are summed):

    c = sum_t (ŷ_t + (y_t - sg(y_t)))            (straight-through, sg = stop-gradient: value ŷ_t)
    dc/dy_t = I, so dL/dy_t = v
    dL/dz_t = J_softmax(z_t)^T v = y_t ⊙ v - y_t <y_t, v> = y_t ⊙ (v - <y_t, v>)
    dz_t/dPsi = -(1/tau) I on O_t  (y_t is 0 off O_t; g_t is detached, so z_t sees Psi only in f_t)
    dL/dPsi = -(1/tau) sum_t u_t · y_t ⊙ (v - <y_t, v>)

where u_t = 1 while the graph is still searching at step t and 0 after it closed its goal (the
record simply holds no entries then). The backward evaluates this as segment operations over the
recorded (step, node, g) triples (a segment max for the log-sum-exp, then segment sums), in chunks of
whole steps to bound memory: O(sum_t |O_t|) work, never a dense N x N product.

For SuReNav training (Eq. 12-14) the result carries the closed set and the path node indicator per
graph, both as differentiable functions of Psi (B, N); the path indicator is c ⊙ p with p the hard
path mask (the path lies in the closed set, so its value is p and its gradient flows through c).
``diff_astar_reference`` is the plain step-by-step autograd loop the tests hold this to.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import torch

from navlab.graphs.region_graph import RegionGraph
from navlab.search.graph_astar import (
    SearchGraph,
    astar_kernel,
    backtrack,
    check_query,
    euclidean_heuristic,
    search_graph,
)


@dataclass(frozen=True)
class GraphBatch:
    """B graphs with their queries, padded to N nodes and K neighbours (superpixel graphs: K ~ 6-15).

    Padding nodes and blocked nodes are not ``enterable``; padding neighbour slots hold -1."""

    graphs: tuple[SearchGraph, ...]  # CPU CSR of each graph: the forward search runs on these
    starts: tuple[int, ...]
    goals: tuple[int, ...]
    enterable_np: tuple[np.ndarray, ...]  # (N_b,) bool per graph
    heuristic_np: tuple[np.ndarray, ...]  # (N_b,) float64 per graph (the forward search's exact h)
    neighbours: torch.Tensor  # (B, N, K) int64 node index, -1 padding
    edge_length: torch.Tensor  # (B, N, K) centroid distance (Eq. 6's d), 0 at padding
    heuristic: torch.Tensor  # (B, N) Euclidean distance to the goal, 0 at padding
    enterable: torch.Tensor  # (B, N) bool
    node_mask: torch.Tensor  # (B, N) bool: a real node (not padding)
    start: torch.Tensor  # (B,) int64
    goal: torch.Tensor  # (B,) int64

    @property
    def shape(self) -> tuple[int, int]:
        return tuple(self.heuristic.shape)

    @property
    def device(self) -> torch.device:
        return self.heuristic.device


@dataclass(frozen=True)
class DiffAStarResult:
    closed: torch.Tensor  # (B, N) 0/1 closed set, differentiable in Psi
    path: torch.Tensor  # (B, N) 0/1 path node indicator, differentiable in Psi
    cost: torch.Tensor  # (B,) Eq. (6) cost of the path (differentiable in Psi); inf when unsolved
    paths: tuple[np.ndarray | None, ...]  # node sequence start -> goal per graph; None when unsolved
    solved: torch.Tensor  # (B,) bool


def batch_graphs(graphs: Sequence[RegionGraph | SearchGraph], *, starts: Sequence[int] | None = None,
                 goals: Sequence[int] | None = None, blocked: Sequence[np.ndarray | None] | None = None,
                 device: str | torch.device = "cpu", dtype: torch.dtype = torch.float32) -> GraphBatch:
    """Pad B graphs into one neighbour table. ``starts``/``goals`` default to each RegionGraph's
    ``start_node``/``goal_node`` (set by ``with_endpoints``); ``blocked`` is one (N_b,) bool mask (or
    None) per graph: nodes that may not be entered."""
    if len(graphs) == 0:
        raise ValueError("batch_graphs needs at least one graph")
    b = len(graphs)
    sgs = tuple(search_graph(g) for g in graphs)
    for name, given in (("starts", starts), ("goals", goals), ("blocked", blocked)):
        if given is not None and len(given) != b:
            raise ValueError(f"{name} has {len(given)} entries for {b} graphs; give one per graph")
    ends = []
    for name, given, field in (("start", starts, "start_node"), ("goal", goals, "goal_node")):
        if given is None:
            given = [getattr(g, field, -1) for g in graphs]
            if any(v < 0 for v in given):
                raise ValueError(f"a graph has no {name} node; set it with RegionGraph.with_endpoints "
                                 f"or pass {name}s=")
        ends.append(given)
    starts_, goals_, enterable, heuristics = [], [], [], []
    for i, sg in enumerate(sgs):
        s, g, _, e = check_query(sg, ends[0][i], ends[1][i], None, None if blocked is None else blocked[i])
        starts_.append(s)
        goals_.append(g)
        enterable.append(e)
        heuristics.append(euclidean_heuristic(sg, g))
    n = max(sg.num_nodes for sg in sgs)
    k = max(1, max(int(sg.degree.max()) for sg in sgs))
    neighbours = np.full((b, n, k), -1, dtype=np.int64)
    length = np.zeros((b, n, k))
    heuristic = np.zeros((b, n))
    enter = np.zeros((b, n), dtype=bool)
    node_mask = np.zeros((b, n), dtype=bool)
    for i, sg in enumerate(sgs):
        deg = sg.degree
        tail = np.repeat(np.arange(sg.num_nodes), deg)
        slot = np.arange(len(sg.indices)) - sg.indptr[tail]
        neighbours[i, tail, slot] = sg.indices
        length[i, tail, slot] = sg.length
        heuristic[i, :sg.num_nodes] = heuristics[i]
        enter[i, :sg.num_nodes] = enterable[i]
        node_mask[i, :sg.num_nodes] = True

    def put(a):
        return torch.from_numpy(a).to(device=device, dtype=dtype if a.dtype == np.float64 else None)

    return GraphBatch(graphs=sgs, starts=tuple(starts_), goals=tuple(goals_), enterable_np=tuple(enterable),
                      heuristic_np=tuple(heuristics), neighbours=put(neighbours), edge_length=put(length), heuristic=put(heuristic),
                      enterable=put(enter), node_mask=put(node_mask),
                      start=torch.tensor(starts_, device=device), goal=torch.tensor(goals_, device=device))


def check_psi(batch: GraphBatch, psi: torch.Tensor, temperature: float) -> None:
    """One clear error for a Psi or temperature the search cannot use."""
    if not isinstance(psi, torch.Tensor) or not psi.is_floating_point():
        raise ValueError("psi must be a floating-point torch tensor of shape (B, N)")
    if tuple(psi.shape) != batch.shape:
        raise ValueError(f"psi has shape {tuple(psi.shape)} but the batch is (B, N) = {batch.shape}; "
                         "give one entry cost per (graph, padded node)")
    if psi.device != batch.device:
        raise ValueError(f"psi is on {psi.device} but the batch on {batch.device}; build the batch with "
                         f"device={psi.device}")
    real = torch.where(batch.node_mask, psi.detach(), 0.0)  # padding entries are never read
    if not bool(torch.isfinite(real).all()) or bool(real.min() < 0):
        raise ValueError("psi holds NaN, inf or negative entry costs; Psi must be finite and >= 0 "
                         "(softplus output, zero-masked on free nodes)")
    if not (np.isfinite(temperature) and temperature > 0):
        raise ValueError(f"temperature must be a positive finite number, got {temperature}")


class _ClosedSetFromTrace(torch.autograd.Function):
    """c(Psi) = sum_t ŷ_t with the straight-through gradient of the recorded softmax selections."""

    @staticmethod
    def forward(ctx, psi, closed_hard, heuristic, trace_index, trace_g, trace_step, temperature, chunks):
        ctx.save_for_backward(psi, heuristic, trace_index, trace_g, trace_step)
        ctx.temperature, ctx.chunks = temperature, chunks
        return closed_hard.clone()

    @staticmethod
    def backward(ctx, grad_closed):
        psi, heuristic, trace_index, trace_g, trace_step = ctx.saved_tensors
        v_all = grad_closed.reshape(-1).to(psi.dtype)
        psi_flat, h_flat = psi.detach().reshape(-1), heuristic.reshape(-1)
        grad = torch.zeros_like(psi_flat)
        for e0, e1, s0, s1 in ctx.chunks:  # index_select, not x[idx]: the latter is ~100x slower on CPU
            idx, step = trace_index[e0:e1], trace_step[e0:e1] - s0
            z = -((trace_g[e0:e1] + psi_flat.index_select(0, idx)) + h_flat.index_select(0, idx)) / ctx.temperature
            z_max = torch.full((s1 - s0,), -torch.inf, dtype=z.dtype, device=z.device)
            z_max = z_max.scatter_reduce(0, step, z, reduce="amax")
            ez = torch.exp(z - z_max.index_select(0, step))
            total = torch.zeros_like(z_max).index_add_(0, step, ez)
            y = ez / total.index_select(0, step)  # the softmax over each step's open set O_t
            v = v_all.index_select(0, idx)
            y_dot_v = torch.zeros_like(z_max).index_add_(0, step, y * v)
            grad.index_add_(0, idx, y * (v - y_dot_v.index_select(0, step)))
        return (grad * (-1.0 / ctx.temperature)).reshape(psi.shape), None, None, None, None, None, None, None


def _chunks(step_ptr: np.ndarray, chunk_size: int) -> list[tuple[int, int, int, int]]:
    """(entry lo, entry hi, step lo, step hi) ranges of whole steps with about ``chunk_size`` entries."""
    out, s0, n_steps = [], 0, len(step_ptr) - 1
    while s0 < n_steps:
        s1 = max(s0 + 1, int(np.searchsorted(step_ptr, step_ptr[s0] + chunk_size, side="right")) - 1)
        s1 = min(s1, n_steps)
        out.append((int(step_ptr[s0]), int(step_ptr[s1]), s0, s1))
        s0 = s1
    return out


def diff_astar(batch: GraphBatch, psi: torch.Tensor, *, temperature: float,
               chunk_size: int = 1 << 22) -> DiffAStarResult:
    """Differentiable A* on every graph of ``batch`` with entry costs ``psi`` (B, N), >= 0.

    The forward values are exactly ``graph_astar``'s (closed set, path, cost) for each graph; the
    gradients are those of Neural A*'s straight-through softmax selection at ``temperature``
    (see the module docstring). ``chunk_size`` bounds the entries the backward holds at once.
    """
    check_psi(batch, psi, temperature)
    b, n = batch.shape
    psi64 = psi.detach().to("cpu", torch.float64).numpy()
    closed_hard = np.zeros((b, n))
    path_hard = np.zeros((b, n))
    path_length = np.full(b, np.inf)
    paths, index, g_trace, ptrs = [], [], [], [np.zeros(1, dtype=np.int64)]
    for i, sg in enumerate(batch.graphs):
        start, goal, nn = batch.starts[i], batch.goals[i], sg.num_nodes
        _, parent, order, n_closed, t_node, t_g, t_ptr = astar_kernel(
            sg.indptr, sg.indices, sg.length, psi64[i, :nn], batch.heuristic_np[i], batch.enterable_np[i],
            start, goal, True)
        closed_hard[i, order[:n_closed]] = 1.0
        index.append(t_node + i * n)
        g_trace.append(t_g)
        ptrs.append(t_ptr[1:] + ptrs[-1][-1])
        if order[n_closed - 1] == goal:
            nodes = backtrack(parent, start, goal)
            path_hard[i, nodes] = 1.0
            path_length[i] = np.linalg.norm(np.diff(sg.centroid[nodes], axis=0), axis=1).sum()
            paths.append(nodes)
        else:
            paths.append(None)
    step_ptr = np.concatenate(ptrs)
    step_of_entry = np.repeat(np.arange(len(step_ptr) - 1), np.diff(step_ptr))

    def put(a, dtype=psi.dtype):
        return torch.from_numpy(a).to(device=psi.device, dtype=dtype)

    closed = _ClosedSetFromTrace.apply(psi, put(closed_hard), batch.heuristic.to(psi.dtype),
                                       put(np.concatenate(index), torch.int64), put(np.concatenate(g_trace)),
                                       put(step_of_entry, torch.int64), float(temperature),
                                       _chunks(step_ptr, chunk_size))
    path_mask = put(path_hard)
    return DiffAStarResult(closed=closed, path=closed * path_mask, cost=put(path_length) + (path_mask * psi).sum(1),
                           paths=tuple(paths), solved=torch.tensor([p is not None for p in paths], device=psi.device))
