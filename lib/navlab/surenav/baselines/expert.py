"""The synthetic expert as a policy: the reference row of Table I, not a baseline.

It plans the way the demonstrations were made (``experts.pedestrian.plan_route``: the persona's
context-dependent costs, jaywalking only when the crosswalk detour is too long) on the walker's
belief, without the hand wobble. Its distance to the demonstrations is therefore the floor the
executor itself imposes: discovering the change with a sensor instead of redrawing from a few metres
before it.
"""

from __future__ import annotations

import numpy as np

from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.experts.pedestrian import CostCache, plan_route
from navlab.surenav.experts.personas import Persona


class ExpertPolicy:
    uses_graph = False

    def __init__(self, persona: Persona, margin_cells: int):
        self.persona, self.margin_cells = persona, margin_cells

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position, goal) -> np.ndarray | None:
        costs = CostCache(believed_map.labels, believed_map.frame.resolution)
        route = plan_route(costs, self.persona, np.asarray(position), np.asarray(goal), self.margin_cells)
        return None if route is None else route[0]
