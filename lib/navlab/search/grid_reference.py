"""Reference optimal path costs on a cost grid, from scikit-image's MCP_Geometric (Cython Dijkstra).

It uses the same cost model as ``grid_astar`` (step length times the mean cost of the two cells), so
it serves as the independent solver that A* results are checked against in tests, notebooks and
benchmarks.
"""

from __future__ import annotations

import numpy as np
from skimage.graph import MCP_Geometric


def dijkstra_cost(cost: np.ndarray, start, goal, *, resolution: float = 1.0) -> float:
    """Optimal cost from ``start`` to ``goal`` over an 8-connected grid (``inf`` when unreachable)."""
    blocked_as_negative = np.where(np.isfinite(cost), cost, -1.0)  # MCP: negative = impassable
    cumulative, _ = MCP_Geometric(blocked_as_negative, fully_connected=True).find_costs([tuple(start)], [tuple(goal)])
    return float(cumulative[tuple(goal)]) * resolution
