"""Start-goal queries on a map: pairs of cells of chosen labels, a chosen straight-line distance apart."""

from __future__ import annotations

import numpy as np

from navlab.maps.semantic_map import SemanticMap


def sample_pairs(
    semantic_map: SemanticMap, label_ids, n: int, min_distance_m: float, max_distance_m: float,
    rng: np.random.Generator, max_tries: int = 200,
) -> np.ndarray:
    """(n, 2, 2) int (row, col) start-goal pairs on cells whose label is in ``label_ids``.

    Candidates are drawn in batches and filtered by distance in one vectorised step, so the cost does
    not grow with the map size beyond one ``argwhere``.
    """
    cells = np.argwhere(np.isin(semantic_map.labels, label_ids))
    if len(cells) < 2:
        raise ValueError(f"{semantic_map.name}: fewer than two cells with labels {list(label_ids)}")
    res = semantic_map.frame.resolution
    found: list[np.ndarray] = []
    for _ in range(max_tries):
        a, b = cells[rng.integers(len(cells), size=4 * n)], cells[rng.integers(len(cells), size=4 * n)]
        d = np.hypot(*(a - b).T) * res
        keep = (d >= min_distance_m) & (d <= max_distance_m)
        found.extend(np.stack([a[keep], b[keep]], axis=1))
        if len(found) >= n:
            return np.asarray(found[:n], dtype=np.int64)
    raise ValueError(f"{semantic_map.name}: found only {len(found)} of {n} pairs {min_distance_m}-{max_distance_m} m "
                     "apart; widen the distance range or use a larger map")
