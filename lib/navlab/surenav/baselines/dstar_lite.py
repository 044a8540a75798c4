"""The D* Lite baseline (Koenig & Likhachev 2002; SuReNav Sec. VI-A): pixel-level incremental search
on a fixed per-label cost field derived from the training demonstrations (``demo_priors``).

One search per episode: when the walker's belief changes, the cells whose cost changed are handed to
D* Lite (``update_costs``) after the move (``move_to``, which raises k_m), and the path is repaired
rather than searched again.
"""

from __future__ import annotations

import numpy as np

from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.search.dstar_lite import DStarLite


class DStarLitePolicy:
    uses_graph = False

    def __init__(self, label_costs: np.ndarray):
        self.label_costs = np.asarray(label_costs, dtype=np.float64)  # (NUM_LABELS,) per metre, inf = blocked
        self._search: DStarLite | None = None
        self._cost: np.ndarray | None = None

    def cell_costs(self, believed_map: SemanticMap) -> np.ndarray:
        """Per-metre cost of every cell of the believed map: its label's (a subclass may price the ground too)."""
        return self.label_costs[believed_map.labels]

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position, goal) -> np.ndarray | None:
        cost = self.cell_costs(believed_map)
        if self._search is None:
            self._search = DStarLite(cost, tuple(position), tuple(goal), resolution=believed_map.frame.resolution)
        else:
            self._search.move_to(tuple(position))
            changed = np.argwhere(cost != self._cost)
            if len(changed):
                self._search.update_costs(changed, cost[changed[:, 0], changed[:, 1]])
        self._cost = cost
        return self._search.plan().cells
