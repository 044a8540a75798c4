"""Preference contexts (PACER Sec. IV-A, V-A): n pairs of terrain patches, the preferred one on top.

From an ordering ``tau_1 > ... > tau_L`` we choose n of its L(L-1)/2 ordered pairs without replacement
(with repeats only when L(L-1)/2 < n; a lone terrain pairs with itself), first pairing off the terrains
that must be named (those in view) so each appears where 2n allows, shuffle them, and draw for each
terrain a fresh h x w patch from the *context part* of one of its photographs (never the part BEV
images are rendered from), at a ground scale like the images' and under its own brightness. Pair i
fills channels 3i..3i+2 of a float32 ``(3n, 2h, w)`` tensor: rows 0..h-1 the preferred patch, rows
h..2h-1 the other one.

As at deployment, the ordering a context is drawn from may be a *superset* of the terrains in view
(:func:`superset_terrains`: the terrains in view plus a few others of the same kind, the way a map's
3-5 terrains are more than one window shows; the released code draws 3 pairs from a whole 6-class
ordering whatever is in view).

An *uninformative* context (Sec. VI, questions 1b/2b) has the same form but is built from terrains of
another group than the image shows, so it says nothing about the image's terrains.
"""

from __future__ import annotations

from typing import Literal

import cv2
import numpy as np

from navlab.core.params.pacer import PacerDataParams
from navlab.pacer.bev import texels_per_pixel
from navlab.pacer.preferences import Preference, order_terrains
from navlab.pacer.terrain import TerrainBank, pyramid_level


def preference_pairs(ordering: np.ndarray, n_pairs: int, rng: np.random.Generator,
                     cover: np.ndarray | None = None) -> np.ndarray:
    """int64 (n_pairs, 2): rows (preferred terrain, less preferred terrain), consistent with ``ordering``.

    Every terrain of ``cover`` (default: all of ``ordering``) appears in some pair when ``n_pairs``
    allows: the covered terrains, shuffled, are paired off two by two (the last of an odd count with a
    random other terrain); the remaining pairs are distinct pairs of ``ordering`` drawn at random.
    """
    ordering = np.asarray(ordering, dtype=np.int64)
    count = len(ordering)
    if count == 0:
        raise ValueError("ordering is empty; a preference context needs at least one terrain")
    if count == 1:
        return np.repeat(ordering[None, [0, 0]], n_pairs, axis=0)
    rank = {int(t): r for r, t in enumerate(ordering)}
    cover = ordering if cover is None else np.unique(np.asarray(cover, dtype=np.int64))
    if any(int(t) not in rank for t in cover):
        raise ValueError(f"cover {np.asarray(cover).tolist()} names terrains the ordering {ordering.tolist()} "
                         "does not rank; the ordering must be a superset of the terrains to cover")
    ranks = [rank[int(t)] for t in rng.permutation(cover)]
    chosen: list[tuple[int, int]] = []
    for k in range(0, len(ranks), 2):
        if len(chosen) == n_pairs:
            break
        a = ranks[k]
        b = ranks[k + 1] if k + 1 < len(ranks) else int(rng.choice([r for r in range(count) if r != a]))
        chosen.append((min(a, b), max(a, b)))
    upper, lower = np.triu_indices(count, k=1)  # rank upper < rank lower: upper is preferred
    rest = [p for p in zip(upper.tolist(), lower.tolist()) if p not in chosen]
    rest = [rest[k] for k in rng.permutation(len(rest))]
    chosen += rest[: n_pairs - len(chosen)]
    while len(chosen) < n_pairs:  # fewer distinct pairs than n_pairs: repeat some
        chosen.append(chosen[int(rng.integers(len(chosen)))])
    chosen = [chosen[k] for k in rng.permutation(len(chosen))]
    return np.asarray([[ordering[a], ordering[b]] for a, b in chosen], dtype=np.int64)


def context_patch(bank: TerrainBank, terrain: int, rng: np.random.Generator, patch_size: int,
                  scale: float) -> np.ndarray:
    """float32 (h, w, 3): a random square crop of a context part of ``terrain``, ``scale`` photograph
    pixels per patch pixel (as far as the part allows), randomly turned by a multiple of 90 degrees."""
    instances = bank.context_parts[terrain]
    pyramid = instances[int(rng.integers(len(instances)))]
    level = pyramid_level(scale)
    part = pyramid[level]
    side = int(np.clip(round(patch_size * scale / 2**level), 1, min(part.shape[:2])))
    top = int(rng.integers(0, part.shape[0] - side + 1))
    left = int(rng.integers(0, part.shape[1] - side + 1))
    crop = part[top : top + side, left : left + side]
    interpolation = cv2.INTER_AREA if side >= patch_size else cv2.INTER_LINEAR
    patch = cv2.resize(crop, (patch_size, patch_size), interpolation=interpolation)
    return np.ascontiguousarray(np.rot90(patch, k=int(rng.integers(4))), dtype=np.float32)


def stack_context(preferred: np.ndarray, other: np.ndarray) -> np.ndarray:
    """(3n, 2h, w) from n preferred and n other patches (each (n, h, w, 3)): preferred on top."""
    pairs = np.concatenate([preferred, other], axis=1)  # (n, 2h, w, 3)
    return np.ascontiguousarray(pairs.transpose(0, 3, 1, 2).reshape(-1, *pairs.shape[1:3]), dtype=np.float32)


def preference_context(bank: TerrainBank, ordering: np.ndarray, rng: np.random.Generator,
                       params: PacerDataParams, cover: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(context float32 (3n, 2h, w), pairs int64 (n, 2)) for ``ordering`` (terrain ids, most preferred
    first), with n = ``params.n_pairs`` and h = w = ``params.patch_size``; the pairs cover ``cover``
    (default: every terrain of ``ordering``) where n allows (:func:`preference_pairs`)."""
    pairs = preference_pairs(ordering, params.n_pairs, rng, cover)
    return pair_context(bank, pairs, rng, params), pairs


def pair_context(bank: TerrainBank, pairs: np.ndarray, rng: np.random.Generator,
                 params: PacerDataParams) -> np.ndarray:
    """The context tensor float32 (3n, 2h, w) of given ``pairs`` (int64 (n, 2), (preferred, other)):
    one ground scale, a fresh patch per terrain and pair, each under its own brightness."""
    scale = texels_per_pixel(rng, params)
    patches = np.stack([[context_patch(bank, t, rng, params.patch_size, scale) for t in pair] for pair in pairs])
    jitter = params.photometric.brightness  # patches come from other photographs, under other light
    gains = 1.0 + rng.uniform(-jitter, jitter, size=(*pairs.shape, 1, 1, 1)).astype(np.float32)
    patches = np.clip(patches * gains, 0.0, 1.0)
    return stack_context(patches[:, 0], patches[:, 1])


def chain_pairs(ordering: np.ndarray, n_pairs: int, rng: np.random.Generator) -> np.ndarray:
    """int64 (n_pairs, 2): a *chain* context, t1 > t2, t2 > t3, ... of consecutive terrains of
    ``ordering`` (most preferred first), in shuffled order. Where the ordering has more than n_pairs + 1
    terrains the chain runs over n_pairs + 1 of them drawn at random (kept in the ordering's order), so the
    terrain it leaves open is any, not always the last; where it has fewer, the chain names every terrain
    and the remaining pairs are other distinct pairs of the ordering (which the chain already implies)."""
    ordering = np.asarray(ordering, dtype=np.int64)
    if len(ordering) < 2:
        return preference_pairs(ordering, n_pairs, rng)
    if len(ordering) > n_pairs + 1:
        ordering = ordering[np.sort(rng.choice(len(ordering), size=n_pairs + 1, replace=False))]
    chain = [(k, k + 1) for k in range(len(ordering) - 1)]
    upper, lower = np.triu_indices(len(ordering), k=1)
    rest = [p for p in zip(upper.tolist(), lower.tolist()) if p not in chain]
    chosen = chain + [rest[k] for k in rng.permutation(len(rest))][: n_pairs - len(chain)]
    while len(chosen) < n_pairs:
        chosen.append(chosen[int(rng.integers(len(chosen)))])
    chosen = [chosen[k] for k in rng.permutation(len(chosen))]
    return np.asarray([[ordering[a], ordering[b]] for a, b in chosen], dtype=np.int64)


def uninformative_context(bank: TerrainBank, shown: Literal["seen", "unseen"], preference: Preference,
                          rng: np.random.Generator, params: PacerDataParams) -> tuple[np.ndarray, np.ndarray]:
    """(context, pairs) like :func:`preference_context`, but over terrains of the group the environment
    does *not* show (``shown`` seen -> unseen terrains and vice versa): the fewest such terrains that give
    ``n_pairs`` distinct pairs, drawn at random and ordered by ``preference``."""
    other = bank.ids("unseen" if shown == "seen" else "seen")
    terrains = uninformative_terrains(other, params.n_pairs, rng)
    return preference_context(bank, order_terrains(terrains, preference, bank, rng), rng, params)


def uninformative_terrains(candidates: np.ndarray, n_pairs: int, rng: np.random.Generator) -> np.ndarray:
    """The fewest of ``candidates`` (terrain ids of a group the image does not show) that give ``n_pairs``
    distinct pairs, drawn at random: the terrains of an uninformative context (unordered)."""
    count = 2
    while count * (count - 1) // 2 < n_pairs:
        count += 1
    return rng.choice(np.asarray(candidates, dtype=np.int64), size=min(count, len(candidates)), replace=False)


def superset_terrains(in_view: np.ndarray, candidates: np.ndarray, extra: int, rng: np.random.Generator) -> np.ndarray:
    """The terrains in view plus ``extra`` others drawn from ``candidates`` (fewer if too few remain),
    unordered: what a deployment context is drawn over when it was written for a whole map."""
    in_view = np.unique(np.asarray(in_view, dtype=np.int64))
    others = np.setdiff1d(np.asarray(candidates, dtype=np.int64), in_view)
    drawn = rng.choice(others, size=min(extra, len(others)), replace=False)
    return np.concatenate([in_view, drawn]).astype(np.int64)
