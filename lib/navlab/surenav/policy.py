"""SuReNav's relax-plan step of Algorithm 1 (Sec. V) as a policy for the benchmark's executor.

Given the believed map and its region graph: the relaxation cost Psi of every node in the query
window (the learned estimator, or any other scoring — RCR's, for the ablation), exact graph A* under
g_ext = g + Psi (Eq. 6, 9-11) gives the graph plan X_G, R_rlx = R_soft ∩ X_G, and the low-level plan
follows one of Sec. V's three modes:

- ``free_union`` (the paper's choice): grid A* in R_free ∪ R_rlx — free space anywhere, soft space only
  in the relaxed regions;
- ``within``: grid A* restricted to the regions of X_G;
- ``graph``: the graph plan itself, tracked through its portal sequence (the shared-boundary points
  between consecutive regions), with local grid motions inside X_G from portal to portal.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from pathlib import Path

import numpy as np
import torch

from navlab.core.labels import FREE_IDS, SOFT_IDS
from navlab.core.params.surenav import SuReNavParams
from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.search.graph_astar import csr_graph, graph_astar
from navlab.search.grid_astar import plan as grid_plan
from navlab.surenav.artifacts import model_path
from navlab.surenav.model.estimator import RelaxationCostEstimator
from navlab.surenav.model.inputs import estimator_input, induced_edges, window_nodes
from navlab.surenav.train import load_estimator

# (graph with start/goal set, window nodes, position xy, goal xy) -> Psi >= 0 per window node, metres
RelaxationCost = Callable[[RegionGraph, np.ndarray, np.ndarray, np.ndarray], np.ndarray]
MODES = ("free_union", "within", "graph")


def estimator_cost(model: RelaxationCostEstimator, device: str | torch.device = "cpu") -> RelaxationCost:
    """Psi from the trained estimator (eval mode, no gradient)."""
    model = model.to(device).eval()

    def cost(graph: RegionGraph, nodes: np.ndarray, position_xy=None, goal_xy=None) -> np.ndarray:
        with torch.no_grad():
            data = estimator_input(graph, nodes, model.params.walk_steps).to(device)
            return model(data).double().cpu().numpy()
    return cost


def scored_cost(score: Callable[[RegionGraph, np.ndarray, np.ndarray, np.ndarray], np.ndarray],
                scale_m: float) -> RelaxationCost:
    """Psi = ``scale_m`` x a hand-made score (lower = better to relax) on soft nodes, 0 on free ones: the
    ablation that puts a rule-based scoring (RCR's label risk + distance to goal) in place of the
    learned estimator while keeping the rest of the planner."""
    def cost(graph: RegionGraph, nodes: np.ndarray, position_xy: np.ndarray, goal_xy: np.ndarray) -> np.ndarray:
        soft = np.isin(graph.node_label[nodes], SOFT_IDS)
        return np.where(soft, scale_m * np.maximum(score(graph, nodes, position_xy, goal_xy), 0.0), 0.0)
    return cost


class SuReNavPolicy:
    """``surenav.semi_static.Policy``: relax with ``cost`` and plan in the chosen mode (one instance per episode)."""

    uses_graph = True

    def __init__(self, cost: RelaxationCost, mode: str = "free_union", window_margin_m: float = 40.0):
        if mode not in MODES:
            raise ValueError(f"surenav.planner.mode = {mode!r}: allowed modes are {', '.join(MODES)}")
        self.cost, self.mode, self.margin = cost, mode, float(window_margin_m)
        self.last_relaxed: np.ndarray = np.zeros(0, dtype=np.int64)  # raster ids of R_rlx at the last plan

    def relax(self, graph: RegionGraph, position_xy: np.ndarray, goal_xy: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """(window nodes, their Psi, X_G) — X_G the node indices of ``graph`` from the position's region
        to the goal's under Eq. (6) with entry costs Psi, None when there is no path."""
        g = graph.with_endpoints(position_xy, goal_xy)
        nodes = window_nodes(g, position_xy, goal_xy, self.margin)
        psi = np.asarray(self.cost(g, nodes, position_xy, goal_xy), dtype=np.float64)
        edges, _ = induced_edges(g, nodes)
        local = np.searchsorted(nodes, [g.start_node, g.goal_node])
        found = graph_astar(csr_graph(g.centroid[nodes], edges), int(local[0]), int(local[1]), entry_cost=psi)
        return nodes, psi, None if found.nodes is None else nodes[found.nodes]

    def graph_plan(self, graph: RegionGraph, position_xy: np.ndarray, goal_xy: np.ndarray) -> np.ndarray | None:
        """X_G alone (see ``relax``)."""
        return self.relax(graph, position_xy, goal_xy)[2]

    def cell_costs(self, believed_map: SemanticMap) -> np.ndarray | float:
        """What a metre of an admissible cell costs the grid plan: 1 (the paper's free-space plan); a subclass
        prices the ground (the stack's terrain costs, ``navlab.stack.route``)."""
        return 1.0

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position, goal) -> np.ndarray | None:
        if graph is None:
            raise ValueError("SuReNav plans on the region graph: run it with uses_graph = True")
        frame, labels = believed_map.frame, believed_map.labels
        position, goal = tuple(int(v) for v in position), tuple(int(v) for v in goal)
        xy = frame.cell_to_world(np.array([position, goal]))
        route = self.graph_plan(graph, xy[0], xy[1])
        if route is None:
            return None
        relaxed = route[np.isin(graph.node_label[route], SOFT_IDS)]
        self.last_relaxed = graph.region_ids[relaxed]
        if self.mode == "free_union":
            admissible = np.isin(labels, FREE_IDS) | np.isin(graph.node_raster, relaxed)
        else:
            admissible = np.isin(graph.node_raster, route)
        cost = np.where(admissible, self.cell_costs(believed_map), np.inf)
        if self.mode != "graph":
            return grid_plan(cost, position, goal, resolution=frame.resolution).cells
        return self._portal_track(graph, route, cost, position, goal, frame.resolution)

    @staticmethod
    def _portal_track(graph: RegionGraph, route: np.ndarray, cost: np.ndarray, position, goal, res: float):
        """The graph plan's portal sequence, joined by local grid motions inside X_G."""
        n = graph.num_nodes
        a, b = np.minimum(route[:-1], route[1:]), np.maximum(route[:-1], route[1:])
        where = np.searchsorted(graph.edges[:, 0] * n + graph.edges[:, 1], a * n + b)
        portals = graph.frame.world_to_cell(graph.portal[where]) if len(where) else np.zeros((0, 2), np.int64)
        stops = [position, *[tuple(int(v) for v in p) for p in portals if np.isfinite(cost[tuple(p)])], goal]
        cells = [np.array([position])]
        for here, there in itertools.pairwise(stops):
            if here == there:
                continue
            leg = grid_plan(cost, here, there, resolution=res).cells
            if leg is None:
                return None
            cells.append(leg[1:])
        return np.concatenate(cells)


def learned_policy(artifacts_dir: str | Path, params: SuReNavParams, variant: str = "gps", seed: int | None = None,
                   device: str | torch.device = "cpu") -> Callable[[], SuReNavPolicy]:
    """A factory of fresh SuReNav policies (one per episode) driven by a trained estimator of the
    ``surenav_estimator`` stage: ``variant`` "gps" (the method) or "mpnn" (the no-attention ablation),
    ``seed`` one of ``params.train.seeds`` (default the first). The model is loaded once."""
    seed = params.train.seeds[0] if seed is None else seed
    cost = estimator_cost(load_estimator(model_path(artifacts_dir, variant, seed), device=device), device)
    return lambda: SuReNavPolicy(cost, params.planner.mode, params.model.window_margin_m)
