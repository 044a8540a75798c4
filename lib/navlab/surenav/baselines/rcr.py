"""Rule-based constraint relaxation, RCR (Kim, Koh, Lee, Park & Park, "Reactive constraint relaxation
for urban environment navigation", RiTA 2024; SuReNav Sec. VI-A).

Soft regions start forbidden. When the free space plus the regions relaxed so far does not connect
the walker to the goal, RCR scores every soft region on the border of the walker's reachable space by
a fixed label-to-risk table plus the distance from the region to the goal (relative to the walker's
own), relaxes the best-scoring one, and tries again; once connected, grid A* finds the shortest path
through the admissible space. Relaxations persist for the episode (a region whose cells change is
re-segmented under a new id and must be relaxed again).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from navlab.core.labels import FREE_IDS, LABELS, SOFT_IDS
from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.search.grid_astar import plan

_EIGHT = np.ones((3, 3), dtype=bool)


def risk_table(label_risk: dict[str, float]) -> np.ndarray:
    """(NUM_LABELS,) RCR risk per label from the params table (every soft label; others unused: 0)."""
    soft = [lab.name for lab in LABELS if lab.constraint == "soft"]
    missing = sorted(set(soft) - set(label_risk))
    if missing:
        raise ValueError(f"rcr.label_risk lacks {missing}; give one 0-1 risk per soft label")
    return np.array([float(label_risk[lab.name]) if lab.name in label_risk else 0.0 for lab in LABELS])


class RCRPolicy:
    uses_graph = True

    def __init__(self, risk: np.ndarray, goal_weight: float):
        self.risk, self.goal_weight = np.asarray(risk, dtype=float), float(goal_weight)
        self.relaxed: set[int] = set()  # raster ids of the relaxed superpixels

    def score(self, graph: RegionGraph, nodes: np.ndarray, position_xy: np.ndarray, goal_xy: np.ndarray) -> np.ndarray:
        """Lower is better: label risk + goal_weight · (region-to-goal / walker-to-goal distance)."""
        here = max(float(np.linalg.norm(goal_xy - position_xy)), 1e-9)
        to_goal = np.linalg.norm(graph.anchor[nodes] - goal_xy, axis=1) / here
        return self.risk[graph.node_label[nodes]] + self.goal_weight * to_goal

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position, goal) -> np.ndarray | None:
        if graph is None:
            raise ValueError("RCR relaxes superpixels: it needs the region graph (uses_graph = True)")
        labels, frame = believed_map.labels, believed_map.frame
        position, goal = tuple(position), tuple(goal)
        for cell in (position, goal):  # standing on (or aiming at) a soft region relaxes it
            node = graph.node_raster[cell]
            if node >= 0 and np.isin(labels[cell], SOFT_IDS):
                self.relaxed.add(int(graph.region_ids[node]))
        free = np.isin(labels, FREE_IDS)
        soft = np.isin(labels, SOFT_IDS)
        xy = frame.cell_to_world(np.array([position, goal]))
        while True:
            admissible = free | (soft & np.isin(graph.superpixels, list(self.relaxed)))
            parts, _ = ndimage.label(admissible, structure=_EIGHT)
            if parts[position] == parts[goal]:
                cost = np.where(admissible, 1.0, np.inf)
                return plan(cost, position, goal, resolution=frame.resolution).cells
            border = ndimage.binary_dilation(parts == parts[position], structure=_EIGHT) & soft & ~admissible
            nodes = np.unique(graph.node_raster[border])
            nodes = nodes[nodes >= 0]
            if len(nodes) == 0:
                return None
            best = nodes[int(np.argmin(self.score(graph, nodes, xy[0], xy[1])))]
            self.relaxed.add(int(graph.region_ids[best]))
