"""Safety-efficiency metrics of an executed trajectory (SuReNav Sec. VI-A, Fig. 4).

- Success: the goal is reached and no hard cell is entered.
- SPL (Anderson et al. 2018): S · ℓ* / max(ℓ, ℓ*), with ℓ* the shortest feasible path on the true map
  (any free or soft cell, no hard one) on the same 8-connected grid the methods move on.
- Total risk: the trajectory's cumulative per-cell risk as a path integral — each step between two
  cells costs its length times the mean unit risk of the two cells (the grid planners' cost model) —
  so it is in risk-metres, grows with both risk magnitude and exposure length, and does not change
  with the map resolution. The paper's unit risks are the
  mean 0-1 scaled scores of three language models; ours are a fixed table in params.yaml.
"""

from __future__ import annotations

import numpy as np

from navlab.core.labels import HARD_IDS, LABELS, constraint_mask
from navlab.search.grid_astar import plan


def path_length(cells: np.ndarray, resolution: float) -> float:
    """Length in metres of a cell path ((K, 2) row, col) walked cell centre to cell centre."""
    cells = np.asarray(cells, dtype=float).reshape(-1, 2)
    return float(np.linalg.norm(np.diff(cells, axis=0), axis=1).sum() * resolution)


def success(cells: np.ndarray, labels: np.ndarray, goal) -> bool:
    """Reached ``goal`` (row, col) without entering a hard cell of ``labels`` (the true map)."""
    cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    if len(cells) == 0:
        return False
    reached = bool(np.array_equal(cells[-1], np.asarray(goal, dtype=np.int64)))
    return reached and not constraint_mask(labels[cells[:, 0], cells[:, 1]], "hard").any()


def shortest_feasible_length(labels: np.ndarray, start, goal, resolution: float) -> float:
    """ℓ*: the shortest 8-connected path length through non-hard cells (inf when there is none)."""
    cost = np.where(np.isin(labels, HARD_IDS), np.inf, 1.0)
    return plan(cost, start, goal, resolution=resolution).cost


def spl(succeeded: bool, length: float, shortest: float) -> float:
    """Success weighted by path length; a failure scores 0."""
    if not succeeded:
        return 0.0
    if not (np.isfinite(shortest) and shortest >= 0 and length >= 0):
        raise ValueError(f"spl: need finite lengths >= 0, got length {length}, shortest {shortest}")
    return 1.0 if max(length, shortest) == 0 else shortest / max(length, shortest)


def risk_table(unit_risk: dict[str, float]) -> np.ndarray:
    """Per-label-id unit risk from the params table (free and soft labels); hard labels get 1.0, the
    top of the 0-1 scale (a successful trajectory never pays it)."""
    missing = [lab.name for lab in LABELS if lab.constraint != "hard" and lab.name not in unit_risk]
    if missing:
        raise ValueError(f"unit_risk lacks {missing}; give a 0-1 risk for every free and soft label")
    return np.array([1.0 if lab.constraint == "hard" else float(unit_risk[lab.name]) for lab in LABELS])


def total_risk(cells: np.ndarray, labels: np.ndarray, table: np.ndarray, resolution: float) -> float:
    """Risk integrated along the trajectory ((K, 2) cells in walking order), in risk-metres."""
    cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    risk = table[labels[cells[:, 0], cells[:, 1]]]
    steps = np.linalg.norm(np.diff(cells, axis=0), axis=1) * resolution
    return float((steps * (risk[1:] + risk[:-1]) / 2).sum())
