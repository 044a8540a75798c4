"""Incremental graph update on a new observation (SuReNav Algorithm 1, "G_t <- update(G_{t-1}, R_t)").

Only the superpixels that the observation touched are segmented again; every other superpixel keeps
its id and its cells, so node features learned or cached for them stay valid. The re-segmented area
gets about the same superpixel density as the rest of the map, and edges are rebuilt from the raster.
"""

from __future__ import annotations

import numpy as np

from navlab.graphs.region_graph import RegionGraph, build_region_graph
from navlab.graphs.superpixels import HARD, label_consistent_slic, traversable_mask


def resegment(superpixels: np.ndarray, new_labels: np.ndarray, changed: np.ndarray, compactness: float) -> np.ndarray:
    """The superpixel raster after a change: touched superpixels re-segmented under fresh ids, the rest kept."""
    changed = np.asarray(changed, dtype=bool)
    if changed.shape != superpixels.shape or new_labels.shape != superpixels.shape:
        raise ValueError(f"changed {changed.shape} and new_labels {new_labels.shape} must match the map "
                         f"{superpixels.shape}")
    inside = superpixels != HARD
    ids = np.unique(superpixels[inside])
    touched = np.unique(superpixels[changed & inside])
    affected = np.isin(superpixels, touched) | changed
    redo = affected & traversable_mask(new_labels)
    out = np.where(affected, HARD, superpixels).astype(np.int32)
    if redo.any():
        density = len(ids) / max(int(inside.sum()), 1)  # superpixels per cell
        fresh = label_consistent_slic(new_labels, max(1, round(density * redo.sum())), compactness, mask=redo)
        out[redo] = fresh[redo] + (int(ids.max()) + 1 if len(ids) else 0)
    return out


def update_graph(graph: RegionGraph, new_labels: np.ndarray, changed: np.ndarray, *, compactness: float,
                 tau: float) -> RegionGraph:
    """G_t from G_{t-1}: re-segment the superpixels that ``changed`` (bool raster) touches, keep the rest."""
    superpixels = resegment(graph.superpixels, new_labels, changed, compactness)
    return build_region_graph(superpixels, new_labels, graph.frame, tau)
