"""Cost-tier proportions of a path (PACER Sec. VI, Tables I-IV).

PACER scores a planned path not by its distance to a demonstration but by where it drives: every
terrain of the environment is put in a low, medium or high cost tier of a hidden total ordering, and
the metric is the share of the path on each tier. Shares are per path cell (each grid cell visited
counts once, as A* returns them).
"""

from __future__ import annotations

import numpy as np

TIER_NAMES = ("low", "medium", "high")


def cost_tier_proportions(path_cells: np.ndarray, labels: np.ndarray, tiers: np.ndarray) -> dict[str, float]:
    """{"low", "medium", "high"}: fraction of ``path_cells`` ((K, 2) row, col) whose label in ``labels``
    ((H, W) terrain ids) lies in each tier; ``tiers[label]`` is 0 (low), 1 (medium) or 2 (high)."""
    cells = np.asarray(path_cells, dtype=np.int64).reshape(-1, 2)
    labels, tiers = np.asarray(labels), np.asarray(tiers, dtype=np.int64)
    if len(cells) == 0:
        raise ValueError("path_cells is empty; score a path of at least one cell (an unreachable goal has no path)")
    rows, cols = cells[:, 0], cells[:, 1]
    if rows.min() < 0 or cols.min() < 0 or rows.max() >= labels.shape[0] or cols.max() >= labels.shape[1]:
        raise ValueError(f"path_cells leave the label raster of shape {labels.shape}")
    path_labels = labels[rows, cols]
    if path_labels.min() < 0 or path_labels.max() >= len(tiers):
        raise ValueError(f"path crosses labels {sorted(set(path_labels.tolist()))} outside the tier table "
                         f"(ids 0..{len(tiers) - 1})")
    path_tiers = tiers[path_labels]
    if not np.isin(path_tiers, (0, 1, 2)).all():
        untiered = sorted(set(path_labels[~np.isin(path_tiers, (0, 1, 2))].tolist()))
        raise ValueError(f"path crosses labels {untiered} that have no tier; give every terrain on the map a tier")
    counts = np.bincount(path_tiers, minlength=3)
    return {name: float(c) / len(cells) for name, c in zip(TIER_NAMES, counts, strict=True)}
