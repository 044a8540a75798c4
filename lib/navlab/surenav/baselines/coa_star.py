"""The COA* baseline (Lim & Tsiotras, "A generalized A* algorithm for finding globally optimal paths in
weighted colored graphs", ICRA 2021; SuReNav Sec. VI-A): class-ordered A* on the 8-connected pixel
grid of the believed map (``search.coa_star.coa_star_grid``), with the soft classes ranked by the
training demonstrations' traversal frequency (``demo_priors.class_order``; free space is not counted).
It minimises, lexicographically, the steps on the most critical class first, then the next, and path
length last — so it relaxes as little of a critical class as it can, whatever the detour. It
re-plans from scratch whenever the belief changes.
"""

from __future__ import annotations

import numpy as np

from navlab.core.labels import HARD_IDS
from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.search.coa_star import coa_star_grid


class ClassOrderedPolicy:
    uses_graph = False

    def __init__(self, order: np.ndarray):
        self.order = np.asarray(order, dtype=np.int64)  # soft label ids, most critical first

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position, goal) -> np.ndarray | None:
        labels = believed_map.labels
        cost = np.where(np.isin(labels, HARD_IDS), np.inf, 1.0)
        found = coa_star_grid(labels, cost, self.order, tuple(position), tuple(goal),
                              resolution=believed_map.frame.resolution)
        return found.path
