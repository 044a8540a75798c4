"""Procedural label layouts: where each terrain lies on the ground, before any texture is drawn.

A layout is an int64 raster of *region* indices 0..k-1; the caller decides which terrain fills each
region. Regions are Voronoi cells whose boundaries are wobbled by a smooth random displacement field,
plus trails: bands along random quadratic Bezier curves, drawn over the cells (the last indices).
Keeping layouts as labels, not images, is what lets PACER draw a preference ordering at load time.
"""

from __future__ import annotations

import cv2
import numpy as np

from navlab.core.params.pacer import PacerAerialParams, PacerLayoutParams


def bev_layout(rng: np.random.Generator, size: int, layout: PacerLayoutParams, near_width: float) -> np.ndarray:
    """Regions of one BEV image: Voronoi seeds inside the field-of-view trapezoid, so each region shows.

    The optional trail enters at the near (bottom) edge, where the robot stands, and leaves at the top.
    """
    k = int(rng.integers(layout.regions[0], layout.regions[1] + 1))
    seeds = rng.uniform(0.05, 0.95, size=(k, 2))  # (y, x) in the unit square
    seeds[:, 1] = 0.5 + (seeds[:, 1] - 0.5) * (1.0 - (1.0 - near_width) * seeds[:, 0])
    regions = _voronoi(size, seeds)
    if rng.uniform() < layout.path_probability:
        half = 0.5 * near_width
        start = (1.05, rng.uniform(0.5 - half, 0.5 + half))
        end = (-0.05, rng.uniform(0.1, 0.9))
        width = rng.uniform(*layout.path_width)
        _draw_trail(regions, rng, start, end, width, k)
    return _wobble(regions, rng, layout.boundary_warp)


def aerial_layout(rng: np.random.Generator, aerial: PacerAerialParams, layout: PacerLayoutParams,
                  bev_size: int) -> np.ndarray:
    """Regions of a large aerial map: many Voronoi cells plus trails from one map edge to another.

    Trail widths and boundary wobble are measured in BEV images (``bev_size`` pixels), so a trail is as
    wide on an aerial map as in the training images, not as wide as the map.
    """
    size = aerial.size
    scale = bev_size / size
    k = int(rng.integers(aerial.regions[0], aerial.regions[1] + 1))
    regions = _voronoi(size, rng.uniform(0.0, 1.0, size=(k, 2)))
    for trail in range(int(rng.integers(aerial.paths[0], aerial.paths[1] + 1))):
        start, end = _edge_point(rng), _edge_point(rng)
        while abs(start[0] - end[0]) + abs(start[1] - end[1]) < 0.8:  # cross the map, do not hug one edge
            end = _edge_point(rng)
        _draw_trail(regions, rng, start, end, rng.uniform(*layout.path_width) * scale, k + trail)
    return _wobble(regions, rng, layout.boundary_warp * scale)


def _voronoi(size: int, seeds: np.ndarray) -> np.ndarray:
    centres = (np.arange(size, dtype=np.float32) + 0.5) / size
    d2 = (centres[:, None, None] - seeds[None, None, :, 0]) ** 2 + (centres[None, :, None] - seeds[None, None, :, 1]) ** 2
    return np.argmin(d2, axis=-1).astype(np.int64)


def _draw_trail(regions: np.ndarray, rng: np.random.Generator, start, end, width: float, index: int) -> None:
    """Paint region ``index`` along a quadratic Bezier from ``start`` to ``end`` ((y, x), unit square)."""
    size = regions.shape[0]
    p0, p2 = np.asarray(start), np.asarray(end)
    p1 = 0.5 * (p0 + p2) + rng.normal(0.0, 0.25, size=2)
    t = np.linspace(0.0, 1.0, 64)[:, None]
    curve = (1 - t) ** 2 * p0 + 2 * (1 - t) * t * p1 + t**2 * p2
    points = np.round(curve[:, ::-1] * size * 16).astype(np.int32)  # (x, y), 4 fractional bits
    canvas = np.zeros((size, size), np.uint8)
    cv2.polylines(canvas, [points], False, 1, thickness=max(1, round(width * size)), lineType=cv2.LINE_8, shift=4)
    regions[canvas > 0] = index


def _edge_point(rng: np.random.Generator) -> tuple[float, float]:
    along, side = rng.uniform(0.1, 0.9), int(rng.integers(4))
    return ((0.0, along), (1.0, along), (along, 0.0), (along, 1.0))[side]


def _wobble(regions: np.ndarray, rng: np.random.Generator, amplitude: float) -> np.ndarray:
    """Displace the raster by a smooth random field, so boundaries look natural rather than polygonal."""
    if amplitude == 0.0:
        return regions
    size = regions.shape[0]
    coarse = rng.normal(0.0, amplitude * size, size=(2, 6, 6)).astype(np.float32)
    dy, dx = (cv2.resize(c, (size, size), interpolation=cv2.INTER_CUBIC) for c in coarse)
    grid = np.arange(size, dtype=np.float32)
    map_x = grid[None, :] + dx
    map_y = grid[:, None] + dy
    warped = cv2.remap(regions.astype(np.float32), map_x, map_y, cv2.INTER_NEAREST, borderMode=cv2.BORDER_REFLECT_101)
    return warped.astype(np.int64)
