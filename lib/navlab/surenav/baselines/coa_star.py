"""The COA* baseline (Lim & Tsiotras, "A generalized A* algorithm for finding globally optimal paths in
weighted colored graphs", ICRA 2021; SuReNav Sec. VI-A): class-ordered A* on the 8-connected pixel
grid of the believed map, with the class order taken from the training demonstrations' traversal
frequency (``demo_priors.class_order``). It minimises, lexicographically, the use of the most critical
class first, then the next, and path length last — so it relaxes as few critical cells as it can,
whatever the detour. It re-plans from scratch whenever the belief changes.
"""

from __future__ import annotations

import numpy as np

from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.search.coa_star import grid_coa_star


class ClassOrderedPolicy:
    uses_graph = False

    def __init__(self, order: np.ndarray):
        self.order = np.asarray(order, dtype=np.int64)  # walkable label ids, least critical first

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position, goal) -> np.ndarray | None:
        found = grid_coa_star(believed_map.labels, self.order, tuple(position), tuple(goal),
                              resolution=believed_map.frame.resolution)
        return found.cells
