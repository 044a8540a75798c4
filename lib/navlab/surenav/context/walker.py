"""The context demonstrator's planner: relax regions by the rules, then walk the relaxed space.

Eq. (4) of the paper is its model of the human: least walking plus the relaxation cost of the regions
given up. The walker plans exactly that on the region graph with the rules' Psi (``rules``; graph A*
over centroid distances, the query window of ``SuReNavPolicy``), then walks grid A* through free
ground and the regions it relaxed at the routers' per-metre surface costs. One instance per episode
or demonstration: its idea of which obstacles are new is the hard space it first saw (or was given).
"""

from __future__ import annotations

import numpy as np

from navlab.core.labels import FREE_IDS, SOFT_IDS
from navlab.graphs.region_graph import RegionGraph
from navlab.graphs.superpixels import HARD
from navlab.maps.semantic_map import SemanticMap
from navlab.search.grid_astar import plan as grid_plan
from navlab.surenav.context.personas import ContextPersona
from navlab.surenav.context.regions import ROAD, graph_context
from navlab.surenav.context.rules import SURFACE_TABLE, relaxation_costs
from navlab.surenav.policy import SuReNavPolicy


class RuleCost:
    """A ``policy.RelaxationCost``: the rules' Psi on a graph, read from the graph alone (no
    demonstration). ``known_hard``: the hard cells of the walker's map; cells hard now and not there
    are a new obstacle. None: the hard space of the first graph it is called with."""

    def __init__(self, persona: ContextPersona, known_hard: np.ndarray | None = None):
        self.persona, self.known_hard = persona, known_hard

    def __call__(self, graph: RegionGraph, nodes: np.ndarray, position_xy=None, goal_xy=None) -> np.ndarray:
        hard = graph.superpixels == HARD
        if self.known_hard is None:
            self.known_hard = hard
        return relaxation_costs(graph_context(graph, hard & ~self.known_hard), self.persona)[nodes]


class ContextWalker:
    """``surenav.semi_static.Policy`` of the demonstrator (and of its reference row through the executor)."""

    uses_graph = True

    def __init__(self, persona: ContextPersona, window_margin_m: float, known_hard: np.ndarray | None = None):
        self.cost = RuleCost(persona, known_hard)
        self.relaxer = SuReNavPolicy(self.cost, "free_union", window_margin_m)
        self.admissible: np.ndarray | None = None  # free cells + the relaxed regions of the last plan
        self.jaywalked = False  # the last plan relaxed a mid-block road region

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position, goal) -> np.ndarray | None:
        if graph is None:
            raise ValueError("the context walker plans on the region graph: run it with uses_graph = True")
        frame, labels = believed_map.frame, believed_map.labels
        xy = frame.cell_to_world(np.array([position, goal]))
        nodes, psi, route = self.relaxer.relax(graph, xy[0], xy[1])
        if route is None:
            return None
        relaxed = route[np.isin(graph.node_label[route], SOFT_IDS)]
        mid_block = psi[np.searchsorted(nodes, relaxed)] >= self.cost.persona.crossing_budget_m
        self.jaywalked = bool(np.any(mid_block & (graph.node_label[relaxed] == ROAD)))
        self.admissible = np.isin(labels, FREE_IDS) | np.isin(graph.node_raster, relaxed)
        cost = np.where(self.admissible, SURFACE_TABLE[labels], np.inf)
        return grid_plan(cost, tuple(int(v) for v in position), tuple(int(v) for v in goal),
                         resolution=frame.resolution).cells
