"""Incremental graph update on a new observation (SuReNav Algorithm 1, "G_t <- update(G_{t-1}, R_t)").

Only the superpixels that the observation touched are segmented again; every other superpixel keeps
its id and its cells, so node features learned or cached for them stay valid. The re-segmented area
gets about the same superpixel density as the rest of the map, and edges are rebuilt from the raster.
"""

from __future__ import annotations

import numpy as np

from navlab.graphs.region_graph import RegionGraph, build_region_graph
from navlab.graphs.superpixels import HARD, label_consistent_slic, traversable_mask


def update_graph(graph: RegionGraph, new_labels: np.ndarray, changed: np.ndarray, *, compactness: float,
                 tau: float) -> RegionGraph:
    """G_t from G_{t-1}: re-segment the superpixels that ``changed`` (bool raster) touches, keep the rest."""
    changed = np.asarray(changed, dtype=bool)
    if changed.shape != graph.superpixels.shape or new_labels.shape != graph.superpixels.shape:
        raise ValueError(f"changed {changed.shape} and new_labels {new_labels.shape} must match the map "
                         f"{graph.superpixels.shape}")
    old = graph.superpixels
    touched = np.unique(old[changed & (old != HARD)])
    redo = (np.isin(old, touched) | changed) & traversable_mask(new_labels)
    superpixels = np.where(np.isin(old, touched) | changed, HARD, old).astype(np.int32)
    if redo.any():
        density = graph.num_nodes / max(int((old != HARD).sum()), 1)  # superpixels per cell
        fresh = label_consistent_slic(new_labels, max(1, round(density * redo.sum())), compactness, mask=redo)
        next_id = int(graph.region_ids.max()) + 1 if graph.num_nodes else 0
        superpixels[redo] = fresh[redo] + next_id
    return build_region_graph(superpixels, new_labels, graph.frame, tau)
