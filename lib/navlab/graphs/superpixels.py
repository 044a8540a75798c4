"""Label-consistent SLIC superpixels over the traversable space (SuReNav Sec. IV-B; Achanta et al., SLIC, 2010).

SuReNav's nodes must each carry one semantic label, so that relaxing a node relaxes exactly one kind of
ground. SLIC runs on a one-hot image of the labels (so its colour term already pulls clusters along label
boundaries); hard cells take part as one more colour and are dropped afterwards; the clusters are then split wherever a label boundary still
runs through one, and every connected piece becomes its own superpixel.
"""

from __future__ import annotations

import numpy as np
from skimage.measure import label as connected_regions
from skimage.segmentation import slic

from navlab.core.labels import HARD_IDS, NUM_LABELS

HARD = -1  # superpixel id of cells that belong to no node (hard regions)


def traversable_mask(labels: np.ndarray) -> np.ndarray:
    """Free + soft cells: the space SuReNav partitions into nodes."""
    return ~np.isin(labels, HARD_IDS)


def label_consistent_slic(labels: np.ndarray, n_segments: int, compactness: float,
                          mask: np.ndarray | None = None) -> np.ndarray:
    """An int32 raster of superpixel ids 0..N-1 (HARD outside ``mask``); each id is one 4-connected,
    single-label region. ``mask`` defaults to the traversable cells; ``n_segments`` is SLIC's target.
    """
    labels = np.asarray(labels)
    if labels.ndim != 2:
        raise ValueError(f"labels must be a 2-D raster, got shape {labels.shape}")
    if n_segments < 1:
        raise ValueError(f"n_segments = {n_segments}: must be at least 1 (surenav.graph.target_nodes)")
    mask = traversable_mask(labels) if mask is None else np.asarray(mask, dtype=bool) & traversable_mask(labels)
    out = np.full(labels.shape, HARD, dtype=np.int32)
    if not mask.any():
        return out
    rows, cols = np.nonzero(mask)
    box = (slice(rows.min(), rows.max() + 1), slice(cols.min(), cols.max() + 1))
    crop_labels, crop_mask = labels[box], mask[box]
    # SLIC's own mask option is ~10x slower; cluster the whole box (hard cells are one more colour)
    # and ask for proportionally more clusters so the masked part still gets about n_segments
    scale = crop_mask.size / crop_mask.sum()
    one_hot = np.eye(NUM_LABELS + 1, dtype=np.float32)[np.where(crop_mask, crop_labels, NUM_LABELS)]
    clusters = slic(one_hot, n_segments=max(1, round(n_segments * scale)), compactness=float(compactness),
                    channel_axis=-1, start_label=1, enforce_connectivity=True, convert2lab=False)
    # one key per (cluster, label); connected pieces of equal key become the superpixels
    key = np.where(crop_mask, clusters.astype(np.int64) * NUM_LABELS + crop_labels + 1, 0)
    pieces = connected_regions(key, background=0, connectivity=1)
    out[box][crop_mask] = pieces[crop_mask] - 1
    return out

