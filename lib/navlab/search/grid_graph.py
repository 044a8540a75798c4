"""The 8-connected (or 4-connected) cost grid as an explicit sparse graph, under grid A*'s cost model.

Graph searches that take CSR arrays (COA*, scipy's Dijkstra used as the reference in tests and
benchmarks) see the raster through this: node r * cols + c is cell (r, c); an edge joins every pair of
neighbouring traversable cells, weighted by the step length times the mean of the two per-metre costs
(Hart, Nilsson and Raphael's A* in ``grid_astar`` charges the same), in both directions.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix, csr_matrix

from navlab.search.grid_astar import SQRT2, check_cost_grid, check_resolution


def grid_csr(cost: np.ndarray, *, resolution: float = 1.0, diagonal: bool = True) -> csr_matrix:
    """(rows*cols)^2 CSR matrix of the grid's edge costs (blocked cells have no edges)."""
    cost = check_cost_grid(cost)
    resolution = check_resolution(resolution)
    rows, cols = cost.shape
    ids = np.arange(rows * cols).reshape(rows, cols)
    flat = cost.ravel()
    src, dst, weight = [], [], []
    moves = ((0, 1), (1, 0), (1, 1), (1, -1)) if diagonal else ((0, 1), (1, 0))
    for dr, dc in moves:
        a = ids[max(0, -dr):rows - max(0, dr), max(0, -dc):cols - max(0, dc)].ravel()
        b = ids[max(0, dr):rows - max(0, -dr), max(0, dc):cols - max(0, -dc)].ravel()
        half = resolution * 0.5 * (SQRT2 if dr and dc else 1.0)
        w = half * (flat[a] + flat[b])
        ok = np.isfinite(w)
        src += [a[ok], b[ok]]
        dst += [b[ok], a[ok]]
        weight += [w[ok], w[ok]]
    return coo_matrix((np.concatenate(weight), (np.concatenate(src), np.concatenate(dst))),
                      shape=(rows * cols,) * 2).tocsr()
