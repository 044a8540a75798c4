"""Exact A* over a region-adjacency graph with per-node entry costs (SuReNav Eq. 6 and 9-11).

Hart, Nilsson and Raphael, "A Formal Basis for the Heuristic Determination of Minimum Cost Paths",
IEEE Trans. SSC, 1968; the objective is SuReNav's Eq. (6) (Koh et al., ICRA 2026).

A path r_1 .. r_L costs sum_t d(r_t, r_t+1) + sum_t Psi(r_t): the centroid distance of every edge plus
the entry cost Psi of every node on it, the start included (Eq. 6 sums over t = 1 .. |X_G|; the start's
Psi is the same for every path, so it shifts the cost but never the choice). In the search's own terms
(Eq. 9 and 11) a node j reached from i has g_j = g_ext_i + d(i, j), and g_ext_j = g_j + Psi_j is what
its successors build on; A* pops the open node of least f = g_ext + h. The heuristic h is the
Euclidean distance of a node's centroid to the goal's: every edge is at least that long (triangle
inequality) and Psi >= 0, so h is consistent and the first time the goal is popped its cost is optimal.

Ties in f are broken by the lower node index; the differentiable search (``diff_astar``) breaks them
the same way, so both expand the same nodes in the same order. The loop is compiled with numba (the
SuReNav planner calls it for every re-plan of every episode); ``graph_astar_reference`` is the same
search as a plain heapq loop, which the tests hold the compiled one to.
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass

import numpy as np
from numba import njit

from navlab.graphs.region_graph import RegionGraph


@dataclass(frozen=True)
class SearchGraph:
    """A region graph as the searches here read it: CSR adjacency (both directions of every edge),
    the centroid distance of each arc (Eq. 6's d) and the centroids (for the heuristic). Build it once
    per graph (``search_graph``) and search it many times."""

    indptr: np.ndarray  # (N + 1,) int64: node i's arcs are indptr[i]:indptr[i + 1]
    indices: np.ndarray  # (2E,) int64 head of each arc
    length: np.ndarray  # (2E,) float64 centroid distance of each arc, metres
    centroid: np.ndarray  # (N, 2) float64 world (x, y), metres

    @property
    def num_nodes(self) -> int:
        return len(self.centroid)

    @property
    def degree(self) -> np.ndarray:
        return np.diff(self.indptr)


@dataclass(frozen=True)
class GraphPath:
    nodes: np.ndarray | None  # (L,) int64 node indices from start to goal; None when the goal is unreachable
    cost: float  # Eq. (6) objective of the path; inf when unreachable
    closed: np.ndarray  # (M,) int64 nodes in the order A* expanded them (the goal last when reached)


def search_graph(graph: RegionGraph | SearchGraph) -> SearchGraph:
    """The CSR form of a ``RegionGraph`` (a ``SearchGraph`` is returned as it is)."""
    if isinstance(graph, SearchGraph):
        return graph
    if not isinstance(graph, RegionGraph):
        raise TypeError(f"expected a RegionGraph or SearchGraph, got {type(graph).__name__}")
    return csr_graph(graph.centroid, graph.edges)


def csr_graph(centroid: np.ndarray, edges: np.ndarray) -> SearchGraph:
    """A ``SearchGraph`` from node centroids (N, 2) and undirected edges (E, 2); lengths are centroid
    distances, as in ``RegionGraph``."""
    centroid = np.asarray(centroid, dtype=np.float64)
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    if centroid.ndim != 2 or centroid.shape[1] != 2:
        raise ValueError(f"centroid must have shape (N, 2), got {centroid.shape}")
    n = len(centroid)
    if n == 0:
        raise ValueError("the graph has no nodes; build it from a map with free or soft regions")
    if not np.isfinite(centroid).all():
        raise ValueError("centroid holds NaN or inf; every node needs a finite (x, y)")
    if len(edges) and (edges.min() < 0 or edges.max() >= n):
        raise ValueError(f"edges name nodes outside 0..{n - 1}")
    if np.any(edges[:, 0] == edges[:, 1]):
        raise ValueError("edges hold self-loops (i, i); a region is not adjacent to itself")
    arcs = np.unique(np.concatenate([edges, edges[:, ::-1]]), axis=0)  # sorted by (tail, head), no duplicates
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(arcs[:, 0], minlength=n), out=indptr[1:])
    length = np.linalg.norm(centroid[arcs[:, 0]] - centroid[arcs[:, 1]], axis=1)
    return SearchGraph(indptr=indptr, indices=np.ascontiguousarray(arcs[:, 1]), length=length, centroid=centroid)


def euclidean_heuristic(graph: SearchGraph, goal: int) -> np.ndarray:
    """(N,) float64 straight-line distance of each centroid to the goal's: consistent for Eq. (6)."""
    return np.sqrt(((graph.centroid - graph.centroid[goal]) ** 2).sum(axis=1))


def check_query(graph: SearchGraph, start, goal, entry_cost, blocked) -> tuple[int, int, np.ndarray, np.ndarray]:
    """Validated (start, goal, entry cost (N,) float64, enterable (N,) bool); one clear error per problem."""
    n = graph.num_nodes
    if entry_cost is None:
        entry = np.zeros(n)
    else:
        entry = np.asarray(entry_cost, dtype=np.float64)
        if entry.shape != (n,):
            raise ValueError(f"entry_cost must have shape ({n},) (one Psi per node), got {entry.shape}")
        if not np.isfinite(entry).all() or (entry < 0).any():
            raise ValueError("entry_cost holds NaN, inf or negative values; Psi must be finite and >= 0 "
                             "(mark nodes that may not be entered with `blocked`)")
    if blocked is None:
        enterable = np.ones(n, dtype=bool)
    else:
        blocked = np.asarray(blocked)
        if blocked.shape != (n,) or blocked.dtype != bool:
            raise ValueError(f"blocked must be a bool array of shape ({n},), got {blocked.dtype} {blocked.shape}")
        enterable = ~blocked
    ends = []
    for name, node in (("start", start), ("goal", goal)):
        if not (0 <= int(node) < n):
            raise ValueError(f"{name} node {int(node)} is out of range for a graph of {n} nodes")
        if not enterable[int(node)]:
            raise ValueError(f"{name} node {int(node)} is blocked; pick a {name} in an enterable region")
        ends.append(int(node))
    return ends[0], ends[1], entry, enterable


@njit(cache=True)
def _grow(a, size):
    if size < len(a):
        return a
    out = np.empty(2 * len(a), dtype=a.dtype)
    out[:len(a)] = a
    return out


@njit(cache=True)
def astar_kernel(indptr, indices, length, entry, h, enterable, start, goal, record):
    """The A* loop. Returns (g, parent, closed order, n_closed) and, when ``record``, the trace the
    differentiable search's backward needs: for every expansion t, the open set O_t just before the
    pop (``trace_node``, with each node's g at that moment in ``trace_g``; step t's entries are
    ``trace_ptr[t]:trace_ptr[t + 1]``) and the popped node ``trace_sel[t]``."""
    n = len(h)
    g = np.full(n, np.inf)  # cost of reaching a node, before its own entry cost (Eq. 11's g)
    parent = np.full(n, -1, dtype=np.int64)
    state = np.zeros(n, dtype=np.int8)  # 0 unseen, 1 open, 2 closed
    open_nodes = np.empty(n, dtype=np.int64)  # the open set as a list (O(1) removal through open_at)
    open_at = np.full(n, -1, dtype=np.int64)
    order = np.empty(n, dtype=np.int64)
    trace_node = np.empty(1024 if record else 1, dtype=np.int64)
    trace_g = np.empty(1024 if record else 1)
    trace_ptr = np.zeros(n + 1, dtype=np.int64)
    n_trace = 0
    g[start] = 0.0
    state[start] = 1
    open_nodes[0] = start
    open_at[start] = 0
    n_open = 1
    n_closed = 0
    heap = [((0.0 + entry[start]) + h[start], start)]
    while len(heap) > 0:
        _, i = heapq.heappop(heap)
        if state[i] != 1:  # a stale entry: the node was closed through a cheaper one
            continue
        if record:
            while n_trace + n_open > len(trace_node):
                trace_node = _grow(trace_node, n_trace + n_open)
                trace_g = _grow(trace_g, n_trace + n_open)
            for k in range(n_open):
                trace_node[n_trace + k] = open_nodes[k]
                trace_g[n_trace + k] = g[open_nodes[k]]
            n_trace += n_open
            trace_ptr[n_closed + 1] = n_trace
        last = open_nodes[n_open - 1]  # remove i from the open list: move the last entry into its slot
        open_nodes[open_at[i]] = last
        open_at[last] = open_at[i]
        n_open -= 1
        state[i] = 2
        order[n_closed] = i
        n_closed += 1
        if i == goal:
            break
        g_ext = g[i] + entry[i]  # Eq. (9): the selected node's cost including its entry penalty
        for a in range(indptr[i], indptr[i + 1]):
            j = indices[a]
            if state[j] == 2 or not enterable[j]:
                continue
            g_j = g_ext + length[a]  # Eq. (11)
            if state[j] == 0 or g_j < g[j]:
                g[j] = g_j
                parent[j] = i
                if state[j] == 0:
                    state[j] = 1
                    open_nodes[n_open] = j
                    open_at[j] = n_open
                    n_open += 1
                heapq.heappush(heap, ((g_j + entry[j]) + h[j], j))
    return g, parent, order, n_closed, trace_node[:n_trace], trace_g[:n_trace], trace_ptr[:n_closed + 1]


def backtrack(parent, start: int, goal: int) -> np.ndarray:
    """Node path start -> goal from the parent pointers of a search that closed the goal."""
    chain = [goal]
    while chain[-1] != start:
        chain.append(int(parent[chain[-1]]))
    return np.array(chain[::-1], dtype=np.int64)


def graph_astar(graph: RegionGraph | SearchGraph, start: int, goal: int, *, entry_cost=None,
                blocked=None) -> GraphPath:
    """Least-cost node path from ``start`` to ``goal`` under Eq. (6).

    ``entry_cost``: (N,) Psi >= 0 paid on entering each node (default 0: shortest centroid path);
    ``blocked``: (N,) bool, nodes that may not be entered (hard, or soft and not relaxed). For many
    queries on one graph, pass ``search_graph(region_graph)`` to build the CSR form once.
    """
    sg = search_graph(graph)
    start, goal, entry, enterable = check_query(sg, start, goal, entry_cost, blocked)
    h = euclidean_heuristic(sg, goal)
    g, parent, order, n_closed, *_ = astar_kernel(sg.indptr, sg.indices, sg.length, entry, h, enterable,
                                                  start, goal, False)
    closed = order[:n_closed].copy()
    if n_closed == 0 or closed[-1] != goal:
        return GraphPath(None, float("inf"), closed)
    return GraphPath(backtrack(parent, start, goal), float(g[goal] + entry[goal]), closed)


def graph_astar_reference(graph: RegionGraph | SearchGraph, start: int, goal: int, *, entry_cost=None,
                          blocked=None) -> GraphPath:
    """``graph_astar`` as a plain heapq loop (the reference the compiled kernel is tested against)."""
    sg = search_graph(graph)
    start, goal, entry, enterable = check_query(sg, start, goal, entry_cost, blocked)
    h = euclidean_heuristic(sg, goal)
    g = {start: 0.0}
    parent = {start: -1}
    closed: list[int] = []
    done = set()
    heap = [((0.0 + entry[start]) + h[start], start)]
    while heap:
        _, i = heapq.heappop(heap)
        if i in done:
            continue
        done.add(i)
        closed.append(i)
        if i == goal:
            break
        g_ext = g[i] + entry[i]
        for a in range(sg.indptr[i], sg.indptr[i + 1]):
            j = int(sg.indices[a])
            if j in done or not enterable[j]:
                continue
            g_j = g_ext + sg.length[a]
            if j not in g or g_j < g[j]:
                g[j], parent[j] = g_j, i
                heapq.heappush(heap, ((g_j + entry[j]) + h[j], j))
    closed = np.array(closed, dtype=np.int64)
    if closed[-1] != goal:
        return GraphPath(None, float("inf"), closed)
    return GraphPath(backtrack(parent, start, goal), float(g[goal] + entry[goal]), closed)
