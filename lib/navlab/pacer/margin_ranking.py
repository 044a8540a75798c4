"""Margin ranking error of a predicted costmap (PACER Sec. VI-C, Table V).

Costs are only defined up to a monotone rescaling, so PACER compares a predicted costmap with the
terrain ordering rather than with target values: sample points of the costmap, and for every pair
of points the error is 0 if the predicted costs stand in the right relation, else the difference of
the two predicted costs; report the mean over all pairs. The right relation for two points on
terrains of different rank is "the less preferred one costs more"; for two points of the same rank
it is equality (condition NC1), so there any difference counts as error.
"""

from __future__ import annotations

import numpy as np


def margin_ranking_error(pred_costmap, labels: np.ndarray, ordering: np.ndarray, n_points: int = 500, *,
                         rng: np.random.Generator) -> float:
    """Mean pairwise ranking error of ``pred_costmap`` ((H, W), array-like) over ``n_points`` pixels drawn
    without replacement among those whose label ((H, W) terrain ids) ``ordering`` ranks (terrain ids,
    most preferred first; -1 entries are padding). Pixels outside the view (label -1) are never drawn."""
    pred = np.asarray(pred_costmap, dtype=np.float64)
    labels = np.asarray(labels, dtype=np.int64)
    if pred.shape != labels.shape:
        raise ValueError(f"pred_costmap has shape {pred.shape} but labels {labels.shape}; they must match")
    ordering = np.asarray(ordering, dtype=np.int64)
    ordering = ordering[ordering >= 0]
    rank = np.full(max(int(labels.max(initial=0)), int(ordering.max(initial=0))) + 1, -1, dtype=np.int64)
    rank[ordering] = np.arange(len(ordering))
    valid = np.flatnonzero((labels >= 0) & (rank[np.maximum(labels, 0)] >= 0))
    if len(valid) < 2:
        raise ValueError("fewer than two pixels carry a ranked terrain; nothing to compare")
    chosen = rng.choice(valid, size=min(n_points, len(valid)), replace=False)
    cost = pred.ravel()[chosen]
    target = rank[labels.ravel()[chosen]]
    i, j = np.triu_indices(len(chosen), k=1)
    diff = cost[i] - cost[j]
    order = np.sign(target[i] - target[j])  # +1: point i is the less preferred, so it should cost more
    error = np.where(order == 0, np.abs(diff), np.maximum(0.0, -order * diff))
    return float(error.mean())
