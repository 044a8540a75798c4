"""The stack's route layer: SuReNav's relax-plan-execute (Algorithm 1) with the terrain layer's costs, or
D* Lite in its place (the ablation), walked by SuReNav's executor on the episode's map.

How the terrain costs enter (our design; the papers join nothing): a soft region's relaxation cost gains
w x its mean terrain cost x sqrt(area) (metres, the scale of the label-table Psi, (cost per metre - 1) x
sqrt(area)), so the graph search (Eq. 6) prefers to relax the operator's preferred ground; and the grid plan
inside R_free U R_rlx pays 1 + w c per metre instead of 1, so the path keeps to it. D* Lite pays its fitted
label cost per metre x (1 + w c): the same terrain layer, without the relaxation estimator.
"""

from __future__ import annotations

import numpy as np

from navlab.core.labels import HARD_IDS, SOFT_IDS
from navlab.core.params import Params
from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.stack.world import StackEpisode
from navlab.surenav.baselines.dstar_lite import DStarLitePolicy
from navlab.surenav.context.personas import CONTEXT_PERSONAS
from navlab.surenav.context.walker import ContextWalker
from navlab.surenav.policy import RelaxationCost, SuReNavPolicy
from navlab.surenav.semi_static import Execution, execute


def region_means(graph: RegionGraph, values: np.ndarray) -> np.ndarray:
    """(N,) the mean of ``values`` (a raster of the graph's shape) over each region's cells."""
    raster = graph.node_raster
    inside = raster >= 0
    total = np.bincount(raster[inside], weights=values[inside], minlength=graph.num_nodes)
    return total / np.maximum(np.bincount(raster[inside], minlength=graph.num_nodes), 1)


def with_terrain(cost: RelaxationCost, terrain: np.ndarray, weight: float) -> RelaxationCost:
    """Psi + w x mean terrain cost x sqrt(area) on soft regions (see the module's docstring)."""
    def relaxation(graph: RegionGraph, nodes: np.ndarray, position_xy, goal_xy) -> np.ndarray:
        base = np.asarray(cost(graph, nodes, position_xy, goal_xy), dtype=np.float64)
        soft = np.isin(graph.node_label[nodes], SOFT_IDS)
        extra = weight * region_means(graph, terrain)[nodes] * np.sqrt(graph.area[nodes])
        return base + np.where(soft, extra, 0.0)
    return relaxation


class TerrainSuReNavPolicy(SuReNavPolicy):
    """SuReNav's ``free_union`` plan (the paper's mode) on terrain costs: relax with ``with_terrain``'s Psi,
    then grid A* in R_free U R_rlx where a cell costs 1 + w c per metre."""

    def __init__(self, cost: RelaxationCost, terrain: np.ndarray, weight: float, window_margin_m: float):
        super().__init__(with_terrain(cost, terrain, weight), "free_union", window_margin_m)
        self.cell_cost = 1.0 + weight * terrain

    def cell_costs(self, believed_map: SemanticMap) -> np.ndarray:
        return self.cell_cost


class TerrainDStarLite(DStarLitePolicy):
    """D* Lite (``surenav.baselines.DStarLitePolicy``'s search) on label cost x (1 + w c) per metre."""

    def __init__(self, label_costs: np.ndarray, terrain: np.ndarray, weight: float):
        super().__init__(label_costs)
        self.factor = 1.0 + weight * terrain

    def cell_costs(self, believed_map: SemanticMap) -> np.ndarray:
        return super().cell_costs(believed_map) * self.factor


def _full_cells(params: Params) -> int:
    return round(params.data.maps.tile_size_m / params.data.maps.resolution_m) ** 2


def walk_route(episode: StackEpisode, policy, params: Params) -> Execution:
    """Algorithm 1's executor: the policy believes the mapped labels, senses the truth within the sensor
    radius, re-plans on every change; the walked cells are the route the local layer follows."""
    s = params.surenav
    return execute(episode.prior, episode.truth, episode.start, episode.goal, policy, s.benchmark.executor,
                   s.graph, full_cells=_full_cells(params))


def expert_route(episode: StackEpisode, params: Params) -> Execution:
    """SuReNav's context demonstrator (its Expert row) walked through the same executor: the reference of
    the Fréchet distance and the relaxation IoU."""
    known_hard = np.isin(episode.prior.labels, HARD_IDS)
    walker = ContextWalker(CONTEXT_PERSONAS[episode.persona], params.surenav.model.window_margin_m, known_hard)
    return walk_route(episode, walker, params)
