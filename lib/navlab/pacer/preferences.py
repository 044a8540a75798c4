"""Preference orderings over terrains and the target costs they imply (PACER Sec. V-A).

An *ordering* is an int64 array of terrain ids, most preferred first: ``tau_1 > tau_2 > ... > tau_L``.
The terrain at rank l (1-based) costs ``H(tau_l) = (l - 1) / (L - 1)``: 0 for the most preferred, 1 for
the least; a single terrain (L = 1) costs 0. Datasets store terrain-label rasters, never costmaps, and
draw the ordering when an item is made:

* realistic: the hidden total ordering of params.yaml (``pacer.data.realistic_ordering``);
* inverted: the realistic ordering reversed (every pairwise preference flipped);
* random: a uniformly random permutation (D_shuffled and D_synthetic), not only reversals.

Tiers (low / medium / high, for Tables I-II) come from params.yaml; inverting a preference swaps
low and high.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from navlab.pacer.terrain import TerrainBank

IGNORE = -1  # label outside the field of view; padding in fixed-length orderings
Preference = Literal["realistic", "inverted", "random"]
PREFERENCES: tuple[Preference, ...] = ("realistic", "inverted", "random")


def rank_costs(ordering: np.ndarray) -> np.ndarray:
    """float32 (L,): (l - 1) / (L - 1) for ranks l = 1..L; [0.] when L = 1."""
    count = len(ordering)
    if count == 0:
        raise ValueError("ordering is empty; an ordering must rank at least one terrain")
    if count == 1:
        return np.zeros(1, dtype=np.float32)
    return (np.arange(count, dtype=np.float32) / (count - 1)).astype(np.float32)


def target_costmap(labels: np.ndarray, ordering: np.ndarray) -> np.ndarray:
    """float32 costmap of ``labels`` (terrain ids, IGNORE outside the view -> cost 0) under ``ordering``."""
    ordering = np.asarray(ordering, dtype=np.int64)
    ordering = ordering[ordering != IGNORE]
    if len(np.unique(ordering)) != len(ordering):
        raise ValueError(f"ordering {ordering.tolist()} repeats a terrain; an ordering ranks each terrain once")
    size = max(int(labels.max(initial=0)), int(ordering.max(initial=0))) + 1
    lookup = np.full(size + 1, np.nan, dtype=np.float32)  # last slot: IGNORE (index -1)
    lookup[ordering] = rank_costs(ordering)
    lookup[-1] = 0.0
    costs = lookup[labels]
    if np.isnan(costs).any():
        missing = sorted(set(np.unique(labels[np.isnan(costs)]).tolist()))
        raise ValueError(f"labels hold terrains {missing} that the ordering {ordering.tolist()} does not rank")
    return costs


def order_terrains(terrains: np.ndarray, preference: Preference, bank: TerrainBank,
                   rng: np.random.Generator) -> np.ndarray:
    """``terrains`` (ids, any order) ordered by ``preference``; realistic/inverted need ranked terrains."""
    terrains = np.unique(np.asarray(terrains, dtype=np.int64))
    if preference == "random":
        return rng.permutation(terrains)
    if preference not in PREFERENCES:
        raise ValueError(f"preference {preference!r}: allowed preferences are {', '.join(PREFERENCES)}")
    ranks = bank.realistic_rank[terrains]
    if (ranks < 0).any():
        names = [bank.terrains[t].name for t in terrains[ranks < 0]]
        raise ValueError(f"terrains {names} have no realistic rank (synthetic); use the 'random' preference")
    realistic = terrains[np.argsort(ranks)]
    return realistic if preference == "realistic" else realistic[::-1].copy()


def tier_table(bank: TerrainBank, preference: Literal["realistic", "inverted"]) -> np.ndarray:
    """int64 (n_terrains,): tier of every terrain id (0 low, 1 medium, 2 high; -1 synthetic) under the
    realistic preference or its inversion, for ``navlab.metrics.cost_tiers.cost_tier_proportions``."""
    if preference == "realistic":
        return bank.tier.copy()
    if preference == "inverted":
        return np.where(bank.tier >= 0, 2 - bank.tier, -1)
    raise ValueError(f"preference {preference!r}: tiers exist for 'realistic' and 'inverted' only")


def pad_ordering(ordering: np.ndarray, length: int) -> np.ndarray:
    """``ordering`` padded with IGNORE to ``length``, so a DataLoader can stack items."""
    if len(ordering) > length:
        raise ValueError(f"ordering of {len(ordering)} terrains does not fit length {length}")
    out = np.full(length, IGNORE, dtype=np.int64)
    out[: len(ordering)] = ordering
    return out
