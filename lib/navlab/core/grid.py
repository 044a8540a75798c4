"""Raster frames: how a 2-D array of cells maps to metric world coordinates.

Convention everywhere in navlab: arrays are indexed ``[row, col]``; world ``x`` grows with ``col``
and world ``y`` grows with ``row`` (y points "down" the image), both in metres from ``origin``;
cell ``(r, c)`` covers ``[origin + c*res, origin + (c+1)*res)`` in x and likewise in y.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class RasterFrame:
    shape: tuple[int, int]  # (rows, cols)
    resolution: float  # metres per cell
    origin: tuple[float, float] = (0.0, 0.0)  # world (x, y) of the corner of cell (0, 0)

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(x_min, x_max, y_max, y_min): matplotlib ``imshow(extent=...)`` with y down."""
        x0, y0 = self.origin
        return (x0, x0 + self.shape[1] * self.resolution, y0 + self.shape[0] * self.resolution, y0)

    def world_to_cell(self, xy: np.ndarray) -> np.ndarray:
        """(…, 2) world points -> (…, 2) integer (row, col); points outside are not clipped."""
        xy = np.asarray(xy, dtype=float)
        col = np.floor((xy[..., 0] - self.origin[0]) / self.resolution)
        row = np.floor((xy[..., 1] - self.origin[1]) / self.resolution)
        return np.stack([row, col], axis=-1).astype(np.int64)

    def cell_to_world(self, rc: np.ndarray) -> np.ndarray:
        """(…, 2) (row, col) -> (…, 2) world points at cell centres."""
        rc = np.asarray(rc, dtype=float)
        x = self.origin[0] + (rc[..., 1] + 0.5) * self.resolution
        y = self.origin[1] + (rc[..., 0] + 0.5) * self.resolution
        return np.stack([x, y], axis=-1)

    def contains(self, rc: np.ndarray) -> np.ndarray:
        rc = np.asarray(rc)
        return (rc[..., 0] >= 0) & (rc[..., 0] < self.shape[0]) & (rc[..., 1] >= 0) & (rc[..., 1] < self.shape[1])
