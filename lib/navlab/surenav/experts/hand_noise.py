"""A drawn-by-hand look for a planned path: smoothed corners, low-frequency wobble, uneven spacing.

Demonstrations in the paper are mouse strokes. Here the planner's cell path is smoothed, offset
sideways by band-limited noise (a few wavelengths of tens of metres, tapered to zero at both ends),
and resampled. The wobble is pulled back toward the planned path wherever it would leave the
``admissible`` cells (free ground plus the soft regions the walker chose), so it never enters a hard
region and never relaxes a region the walker did not choose.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from navlab.core.grid import RasterFrame


def resample(path_xy: np.ndarray, spacing: np.ndarray | float) -> np.ndarray:
    """Points along the polyline at arc-length steps ``spacing`` (scalar or per-step), ends kept."""
    seg = np.linalg.norm(np.diff(path_xy, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    if s[-1] == 0:
        return path_xy[:1].copy()
    steps = np.full(int(np.ceil(s[-1] / np.min(spacing))) + 1, spacing) if np.isscalar(spacing) else spacing
    t = np.concatenate([[0.0], np.cumsum(steps)])
    t = np.concatenate([t[t < s[-1]], [s[-1]]])
    return np.stack([np.interp(t, s, path_xy[:, 0]), np.interp(t, s, path_xy[:, 1])], axis=1)


def dense_cells(path_xy: np.ndarray, frame: RasterFrame) -> np.ndarray:
    """Cells under the polyline sampled every quarter cell (what "the path enters a cell" means here)."""
    return frame.world_to_cell(resample(path_xy, frame.resolution / 4))


def hand_drawn(cells: np.ndarray, frame: RasterFrame, admissible: np.ndarray, rng: np.random.Generator,
               amplitude_m: float, wavelength_m: float) -> np.ndarray:
    """World path (K, 2) of a hand stroke along the cell path ``cells``; every sample stays admissible."""
    res = frame.resolution
    planned = resample(frame.cell_to_world(cells), res / 2)
    if len(planned) < 3:
        return planned
    step = res / 2
    sigma = max(wavelength_m / (4 * step), 1.0)
    smooth = ndimage.gaussian_filter1d(planned, sigma=min(2.0 / step, sigma), axis=0, mode="nearest")
    wobble = ndimage.gaussian_filter1d(rng.standard_normal(len(planned)), sigma=sigma, mode="reflect")
    wobble *= amplitude_m / max(np.abs(wobble).max(), 1e-9)
    taper = np.minimum(1.0, np.minimum(np.arange(len(planned)), np.arange(len(planned))[::-1]) * step / wavelength_m)
    tangent = np.gradient(smooth, axis=0)
    normal = np.stack([-tangent[:, 1], tangent[:, 0]], axis=1) / np.maximum(
        np.linalg.norm(tangent, axis=1, keepdims=True), 1e-9)
    target = smooth + (wobble * taper)[:, None] * normal
    target[0], target[-1] = planned[0], planned[-1]
    weight = np.ones(len(planned))
    for _ in range(12):  # pull the stroke back toward the plan where it leaves the admissible cells
        drawn = planned + weight[:, None] * (target - planned)
        bad = ~_polyline_admissible(drawn, frame, admissible)
        if not bad.any():
            break
        weight = np.where(ndimage.maximum_filter1d(bad, size=9), 0.5 * weight, weight)
        weight = np.minimum(weight, ndimage.gaussian_filter1d(weight, 3.0, mode="nearest"))
    else:
        drawn = planned  # the plan itself runs through admissible cell centres
    # uneven spacing, like a hand slowing down and speeding up
    out = resample(drawn, step * rng.uniform(0.6, 1.0, size=int(2 * len(drawn)) + 2))
    for candidate in (out, drawn):
        if _admissible_points(resample(candidate, res / 4), frame, admissible).all():  # as dense_cells sees it
            return candidate
    return planned


def _polyline_admissible(points: np.ndarray, frame: RasterFrame, admissible: np.ndarray) -> np.ndarray:
    """Per vertex: it and the quarter points of its two segments lie in admissible cells."""
    ok = _admissible_points(points, frame, admissible)
    seg = np.diff(points, axis=0)
    for f in (0.25, 0.5, 0.75):
        mid = _admissible_points(points[:-1] + f * seg, frame, admissible)
        ok[:-1] &= mid
        ok[1:] &= mid
    return ok


def _admissible_points(points: np.ndarray, frame: RasterFrame, admissible: np.ndarray) -> np.ndarray:
    rc = frame.world_to_cell(points)
    ok = frame.contains(rc)
    ok[ok] = admissible[rc[ok, 0], rc[ok, 1]]
    return ok
