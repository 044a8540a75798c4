"""Re-planning from scratch with grid A* on a per-label cost field (Hart, Nilsson & Raphael 1968).

Not a baseline of the paper: it is what D* Lite must reproduce. D* Lite repairs its search tree as
the belief changes; this policy throws the tree away and searches again, so on the same beliefs the
two return plans of the same cost (tests/test_surenav_benchmark.py walks both).
"""

from __future__ import annotations

import numpy as np

from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.search.grid_astar import plan


class CostFieldPolicy:
    uses_graph = False

    def __init__(self, label_costs: np.ndarray):
        self.label_costs = np.asarray(label_costs, dtype=np.float64)  # (NUM_LABELS,) per metre, inf = blocked

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position, goal) -> np.ndarray | None:
        cost = self.label_costs[believed_map.labels]
        return plan(cost, position, goal, resolution=believed_map.frame.resolution).cells
