"""Relaxation IoU (SuReNav Table I): how well a method's relaxed regions match the demonstration's.

Measured on **superpixels of the demonstration's region graph** (``experts.demo_graph``: the stored
partition after the incremental update for the perturbation), not on cells. Why: the paper's unit of
relaxation is a region; the executed paths of different methods are one cell wide and a metre apart,
so cell sets of two reasonable crossings of the same lawn barely overlap (cell IoU ~ 0 says nothing),
while the superpixels they cross are the same. Every method is projected onto one fixed partition,
the demonstration's, so the number does not depend on how a method segments the map itself.
"""

from __future__ import annotations

import numpy as np

from navlab.core.labels import SOFT_IDS


def set_iou(a, b) -> float:
    """|A ∩ B| / |A ∪ B| of two id sets; 1.0 when both are empty (nothing to relax, nothing relaxed)."""
    a, b = np.unique(np.asarray(a).ravel()), np.unique(np.asarray(b).ravel())
    union = len(np.union1d(a, b))
    return 1.0 if union == 0 else len(np.intersect1d(a, b, assume_unique=True)) / union


def relaxed_regions(cells: np.ndarray, labels: np.ndarray, superpixels: np.ndarray) -> np.ndarray:
    """Sorted superpixel ids of the soft cells among ``cells`` ((K, 2) row, col): the relaxed set R_rlx."""
    cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    if labels.shape != superpixels.shape:
        raise ValueError(f"labels {labels.shape} and superpixels {superpixels.shape} must have one shape")
    soft = np.isin(labels[cells[:, 0], cells[:, 1]], SOFT_IDS)
    ids = superpixels[cells[soft, 0], cells[soft, 1]]
    return np.unique(ids[ids >= 0])
