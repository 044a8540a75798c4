"""The four heuristics of the HJ-search paper (Sec. VI-A, Fig. 2) as compiled look-ups for the lattice.

- ``dist_heuristic``: general Dist, max(|p − goal| − tol, 0) / v_max (admissible: the car is never faster);
- ``map_dist_heuristic``: map-based Dist, the obstacle-aware shortest path / v_max from an 8-connected
  Dijkstra (``geodesic_time_field``, the field Fig. 2 plots; ``euclidean_time`` is general Dist's). Kept admissible by construction: the raster is
  inflated by ``radius − res·√2/2`` only (every cell a feasible centre passes through stays free), the
  octile length is divided by 1/cos(22.5°) (its worst excess over Euclidean), and res·√2 plus the goal
  tolerance is taken off before dividing by v_max;
- ``ttr_heuristic``: the general goal-centred TTR grid, looked up in the goal frame; off its grid the
  admissible Euclidean bound (as ``reach.lookup.TTRLookup``);
- ``map_ttr_heuristic``: the map-based TTR of one room and goal; off the grid the solver's horizon.

Each returns a ``search.lattice_search.Heuristic``; calling it on (N, 4) states evaluates the batch in
one compiled call (the simulator's and the benchmarks' entry point).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from navlab.core.grid import RasterFrame
from navlab.maps.rooms import Room
from navlab.reach.lookup import MapTTRLookup, TTRLookup
from navlab.search.lattice_fields import H_DIST, H_GOAL_GRID, H_RASTER, H_ROOM_GRID, GridField
from navlab.search.lattice_search import Heuristic

OCTILE_EXCESS = 1.0 / math.cos(math.pi / 8)  # max octile / Euclidean length ratio of an 8-connected path


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


def grid_field(values: np.ndarray, grid) -> GridField:
    """A stored value function (reach.grid.Grid) as a compiled-look-up field (float32)."""
    return GridField.from_grid(np.asarray(values, dtype=np.float32), grid.lo, grid.spacing, grid.periodic)


def _par(goal_xy, v_max, tolerance, off_grid=0.0, heading=0.0) -> np.ndarray:
    return np.array([goal_xy[0], goal_xy[1], heading, v_max, tolerance, off_grid, math.cos(heading),
                     math.sin(heading)], np.float64)


def dist_heuristic(goal_xy, v_max: float, tolerance: float) -> Heuristic:
    return Heuristic(H_DIST, GridField.empty(2), _par(goal_xy, v_max, tolerance), "Dist")


def map_dist_heuristic(room: Room, goal_xy, v_max: float, robot_radius: float, tolerance: float,
                       resolution: float = 0.05) -> Heuristic:
    relaxed = max(robot_radius - resolution * math.sqrt(2) / 2, 0.0)
    time_field, _ = geodesic_time_field(room, goal_xy, v_max, relaxed, resolution)
    dist = time_field.T * v_max  # [i_x, i_y] at cell centres
    finite = np.isfinite(dist)
    if not finite.any():
        raise ValueError(f"map Dist: no free cell reaches the goal {tuple(goal_xy)} in {room.name}")
    # blocked / unreachable cells: the smallest finite neighbour (grown outwards), so that interpolating
    # next to a wall never mixes in a large value; unreachable components keep the largest finite value
    filled = np.where(finite, dist, np.inf)
    for _ in range(3):
        grown = ndimage.grey_erosion(filled, size=3, mode="nearest")
        filled = np.where(np.isfinite(filled), filled, grown)
    filled = np.where(np.isfinite(filled), filled, dist[finite].max())
    lower = np.maximum(filled / OCTILE_EXCESS - resolution * math.sqrt(2) - tolerance, 0.0) / v_max
    field = GridField.from_grid(lower.astype(np.float32), (resolution / 2, resolution / 2),
                                (resolution, resolution), (False, False))
    return Heuristic(H_RASTER, field, _par(goal_xy, v_max, tolerance), "map Dist")


def ttr_heuristic(lookup: TTRLookup, goal_xy, goal_heading: float = 0.0) -> Heuristic:
    return Heuristic(H_GOAL_GRID, grid_field(lookup.stored.values, lookup.grid),
                     _par(goal_xy, lookup.v_max, lookup.goal_radius, heading=goal_heading), "TTR")


def map_ttr_heuristic(lookup: MapTTRLookup, goal_xy) -> Heuristic:
    solved_for = tuple(lookup.stored.meta["inputs"]["map_ttr"]["goal_xy"])
    if not np.allclose(solved_for, goal_xy):
        raise ValueError(f"map TTR was solved for the goal {solved_for}, not {tuple(goal_xy)}; set "
                         f"hj.grids.map_ttr.goal_xy to this goal and re-run `dvc repro hj_grids`")
    v_max = float(lookup.stored.meta["inputs"]["robot"]["v_max"])
    return Heuristic(H_ROOM_GRID, grid_field(lookup.stored.values, lookup.grid),
                     _par(goal_xy, v_max, 0.0, off_grid=lookup.horizon), "map TTR")
