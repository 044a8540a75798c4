"""Semi-static map changes that obstruct a route (SuReNav Sec. VI-A).

The paper samples superpixel seeds along a route and alters the neighbouring superpixels so that the
pathway is blocked, in two ways: a *new obstacle* (the cells become a hard label) or an *obfuscated
prior map* (the cells get another soft label, so walking there now needs a relaxation). Whatever the
route walked on inside the altered superpixels stops being free space, so the old route is cut.

Works on a superpixel id raster (graphs.superpixels output, -1 outside free+soft space), not on a
graph object, so it stays in the maps layer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from navlab.core.labels import FREE_IDS, SOFT_IDS, label_id

OBSTACLE = label_id("building")
CROSSWALK = label_id("crosswalk")
NO_REGION = -1


@dataclass(frozen=True)
class Perturbation:
    labels: np.ndarray  # the new label raster
    changed: np.ndarray  # bool raster of altered cells
    seeds: np.ndarray  # superpixel ids picked along the route
    kinds: tuple[str, ...]  # per seed: "obstacle" or "obfuscated"

    def delta(self) -> tuple[np.ndarray, np.ndarray]:
        """(flat cell indices, new labels) of the change: what a data file needs to store."""
        cells = np.flatnonzero(self.changed)
        return cells.astype(np.int64), self.labels.ravel()[cells].astype(np.uint8)


def adjacent_superpixels(superpixels: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Superpixel ids 4-adjacent to any of ``ids`` (``ids`` themselves excluded)."""
    inside = np.isin(superpixels, ids)
    grown = inside.copy()
    grown[1:] |= inside[:-1]
    grown[:-1] |= inside[1:]
    grown[:, 1:] |= inside[:, :-1]
    grown[:, :-1] |= inside[:, 1:]
    found = np.unique(superpixels[grown & ~inside])
    return found[(found != NO_REGION) & ~np.isin(found, ids)]


def obstruct_route(labels: np.ndarray, superpixels: np.ndarray, route_cells: np.ndarray, k: int,
                   rng: np.random.Generator, *, obstacle_probability: float,
                   clearance_cells: int = 0) -> Perturbation:
    """Alter up to ``k`` superpixels on the route (and their neighbours of the same label) to block it.

    Seeds are drawn among the superpixels the route passes through, except those within
    ``clearance_cells`` of the route's ends (start and goal stay reachable).
    """
    route_cells = np.asarray(route_cells, dtype=np.int64)
    if route_cells.ndim != 2 or route_cells.shape[1] != 2 or len(route_cells) < 2:
        raise ValueError(f"route_cells must be a (K >= 2, 2) array of (row, col), got {route_cells.shape}")
    if labels.shape != superpixels.shape:
        raise ValueError(f"labels {labels.shape} and superpixels {superpixels.shape} must have one shape")
    on_route = superpixels[route_cells[:, 0], route_cells[:, 1]]
    ends = np.concatenate([route_cells[:1], route_cells[-1:]])
    near_end = (np.abs(route_cells[:, None, :] - ends[None]).max(axis=2) <= clearance_cells).any(axis=1)
    protected = np.unique(on_route[near_end])
    candidates = np.unique(on_route[(on_route != NO_REGION) & ~np.isin(on_route, protected)])
    on_free = np.isin(_label_of(labels, superpixels, candidates), FREE_IDS)
    if on_free.any():  # block the pathway itself where the route walks on free ground
        candidates = candidates[on_free]
    new_labels = labels.copy()
    changed = np.zeros(labels.shape, dtype=bool)
    if len(candidates) == 0:
        return Perturbation(new_labels, changed, np.zeros(0, dtype=np.int64), ())
    seeds = rng.choice(candidates, size=min(k, len(candidates)), replace=False)
    kinds = []
    for seed in seeds:
        seed_label = _label_of(labels, superpixels, np.array([seed]))[0]
        same = adjacent_superpixels(superpixels, np.array([seed]))
        same = same[_label_of(labels, superpixels, same) == seed_label]
        region = np.isin(superpixels, np.concatenate([[seed], same[~np.isin(same, protected)]]))
        if rng.random() < obstacle_probability:
            kinds.append("obstacle")
            new_labels[region] = OBSTACLE
        else:
            kinds.append("obfuscated")
            others = SOFT_IDS[(SOFT_IDS != seed_label) & (SOFT_IDS != CROSSWALK)]  # a crosswalk obstructs nothing
            new_labels[region] = others[rng.integers(len(others))]
        changed |= region
    return Perturbation(new_labels, changed, seeds.astype(np.int64), tuple(kinds))


def _label_of(labels: np.ndarray, superpixels: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """The label of each superpixel id (superpixels are single-label)."""
    flat = superpixels.ravel()
    order = np.argsort(flat, kind="stable")
    first = order[np.searchsorted(flat[order], ids)]
    return labels.ravel()[first]
