"""Preference orderings over terrains and the target costs they imply (PACER Sec. V-A).

An *ordering* is an int64 array of terrain ids, most preferred first: ``tau_1 > tau_2 > ... > tau_L``.
The terrain at rank l (1-based) costs ``H(tau_l) = (l - 1) / (L - 1)``: 0 for the most preferred, 1 for
the least; a single terrain (L = 1) costs 0. Datasets store terrain-label rasters, never costmaps, and
draw the ordering when an item is made:

* realistic: the hidden total ordering of params.yaml (``pacer.data.realistic_ordering``);
* inverted: the realistic ordering reversed (every pairwise preference flipped);
* random: a uniformly random permutation (D_shuffled and D_synthetic), not only reversals.

Tiers (low / medium / high, for Tables I-IV) come from the ordering of each environment's own
terrains (:func:`environment_tiers`); inverting a preference swaps low and high.
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


def environment_tiers(ordering: np.ndarray, n_terrains: int) -> np.ndarray:
    """int64 (n_terrains,): the cost tier of each terrain of an environment (0 low, 1 medium, 2 high;
    -1 for terrains not in ``ordering``), from the hidden total ordering of *that environment's*
    terrains (PACER Sec. VI: "based on a hidden total ordering of all the terrains which appear in the
    environment").

    The terrain at rank l of L has cost (l-1)/(L-1); it is low below 1/3, high above 2/3, medium
    otherwise (integer arithmetic, so the split is exact): two terrains give one low and one high,
    three one of each, and reversing the ordering swaps low and high.
    """
    ordering = np.asarray(ordering, dtype=np.int64)
    ordering = ordering[ordering != IGNORE]
    if len(ordering) == 0:
        raise ValueError("ordering is empty; an environment needs at least one terrain to have tiers")
    if len(np.unique(ordering)) != len(ordering) or ordering.max() >= n_terrains or ordering.min() < 0:
        raise ValueError(f"ordering {ordering.tolist()} must rank distinct terrain ids in 0..{n_terrains - 1}")
    step = np.arange(len(ordering), dtype=np.int64) * 3  # 3(l-1), compared with (L-1) and 2(L-1)
    span = len(ordering) - 1
    tier = np.where(step < span, 0, np.where(step > 2 * span, 2, 1))
    tier[0] = 0  # a lone terrain is low (cost 0)
    out = np.full(n_terrains, -1, dtype=np.int64)
    out[ordering] = tier
    return out


def pad_ordering(ordering: np.ndarray, length: int) -> np.ndarray:
    """``ordering`` padded with IGNORE to ``length``, so a DataLoader can stack items."""
    if len(ordering) > length:
        raise ValueError(f"ordering of {len(ordering)} terrains does not fit length {length}")
    out = np.full(length, IGNORE, dtype=np.int64)
    out[: len(ordering)] = ordering
    return out


def mean_consistent_ranks(terrains: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """float64 (L,): each of ``terrains``' mean 0-based rank over every ordering of them (most preferred
    first) that agrees with ``pairs`` ((preferred, other) ids; pairs naming other terrains constrain
    nothing). Counts linear extensions by dynamic programming over subsets, O(2^L L), exact for the
    3-16 terrains of a map: ``prefix[S]`` orders S first, ``suffix[S]`` orders the rest after S."""
    terrains = np.asarray(terrains, dtype=np.int64)
    count = len(terrains)
    if count > 20:
        raise ValueError(f"{count} terrains: exact mean ranks need 2^L states; use at most 20")
    index = {int(t): k for k, t in enumerate(terrains)}
    before = [0] * count  # bitmask of the terrains each must follow
    for a, b in np.asarray(pairs, dtype=np.int64).reshape(-1, 2):
        if int(a) in index and int(b) in index and a != b:
            before[index[int(b)]] |= 1 << index[int(a)]
    full = (1 << count) - 1
    prefix = [0] * (1 << count)
    prefix[0] = 1
    for s in range(1 << count):
        if prefix[s]:
            for k in range(count):
                if not s >> k & 1 and before[k] & s == before[k]:
                    prefix[s | 1 << k] += prefix[s]
    suffix = [0] * (1 << count)
    suffix[full] = 1
    for s in range(full, -1, -1):
        for k in range(count):
            if not s >> k & 1 and before[k] & s == before[k]:
                suffix[s] += suffix[s | 1 << k]
    if prefix[full] == 0:
        raise ValueError(f"pairs {np.asarray(pairs).tolist()} contradict each other: no ordering agrees with them")
    ranks = np.zeros(count)
    for s in range(1 << count):
        if prefix[s]:
            for k in range(count):
                if not s >> k & 1 and before[k] & s == before[k]:
                    ranks[k] += s.bit_count() * prefix[s] * suffix[s | 1 << k]
    return ranks / prefix[full]


def context_limited_costs(terrains: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """float64 (L,) in [0, 1]: each of ``terrains``' cost H(τ_l) = (l-1)/(L-1) (Sec. V-A) averaged over every
    ordering of them that agrees with ``pairs``: what a perfect follower of the context with no prior assigns
    (the context-limited oracle's costs); pairs the context leaves open average out."""
    return mean_consistent_ranks(terrains, pairs) / max(len(terrains) - 1, 1)


def implied_pairs(terrains: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """bool (L, L): [i, j] when ``pairs`` ((preferred, other) ids) imply, by transitivity, that
    ``terrains[i]`` is preferred to ``terrains[j]`` (the pairs a context *decides*; the rest it leaves
    open). Pairs naming terrains outside ``terrains`` still chain through them (a > x > b decides a > b)."""
    terrains = np.asarray(terrains, dtype=np.int64)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    named = np.unique(np.concatenate([terrains, pairs.ravel()]))
    index = {int(t): k for k, t in enumerate(named)}
    closure = np.zeros((len(named), len(named)), dtype=bool)
    for a, b in pairs:
        if a != b:
            closure[index[int(a)], index[int(b)]] = True
    for k in range(len(named)):  # Warshall
        closure |= closure[:, k:k + 1] & closure[k:k + 1, :]
    keep = [index[int(t)] for t in terrains]
    return closure[np.ix_(keep, keep)]
