"""Distance-based baselines of the HJ-search paper (Sec. VI-A, "Dist"): time = distance / v_max.

The general Dist uses the straight-line distance to the goal; the map-based Dist the shortest
obstacle-free path length (8-connected Dijkstra on the room raster inflated by the robot radius,
so it ignores the dynamics but not the obstacles).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from navlab.core.grid import RasterFrame
from navlab.maps.rooms import Room


def euclidean_time(xy: np.ndarray, goal_xy, v_max: float) -> np.ndarray:
    """General Dist: |p - goal| / v_max for (..., 2) positions."""
    return np.linalg.norm(np.asarray(xy, float) - np.asarray(goal_xy, float), axis=-1) / v_max


def geodesic_time_field(room: Room, goal_xy, v_max: float, robot_radius: float,
                        resolution: float = 0.05) -> tuple[np.ndarray, RasterFrame]:
    """Map-based Dist on the room raster: shortest free path to the goal / v_max (inf where unreachable)."""
    blocked, frame = room.occupancy(resolution, robot_radius)
    goal_rc = tuple(frame.world_to_cell(np.asarray(goal_xy, float)))
    if not frame.contains(np.array(goal_rc)) or blocked[goal_rc]:
        raise ValueError(f"geodesic_time_field: goal {tuple(goal_xy)} is outside {room.name} or inside an obstacle")
    rows, cols = frame.shape
    ids = np.arange(rows * cols).reshape(rows, cols)
    src, dst, w = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        a = ids[max(0, -dr):rows - max(0, dr), max(0, -dc):cols - max(0, dc)]
        b = ids[max(0, dr):rows - max(0, -dr), max(0, dc):cols - max(0, -dc)]
        ok = ~blocked.ravel()[a.ravel()] & ~blocked.ravel()[b.ravel()]
        src.append(a.ravel()[ok])
        dst.append(b.ravel()[ok])
        w.append(np.full(ok.sum(), np.hypot(dr, dc) * resolution))
    graph = coo_matrix((np.concatenate(w), (np.concatenate(src), np.concatenate(dst))),
                       shape=(rows * cols,) * 2).tocsr()
    dist = dijkstra(graph, directed=False, indices=ids[goal_rc])
    return dist.reshape(rows, cols) / v_max, frame
