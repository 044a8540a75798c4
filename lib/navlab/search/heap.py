"""A binary min-heap for numba-compiled searches, ordered lexicographically by a row of float keys.

Searches that rank a node by a vector of numbers of any length (COA*'s per-class traversal counts,
then f, then g) keep their open list here. Each entry is a row of ``keys`` plus an int64 id; entries
compare by their keys column by column, then by id, so the pop order over any set of pushed entries is
one fixed total order: the same as Python's ``heapq`` on ``(*keys, id)`` tuples. (Grid A*, whose key is
always (f, g) of a cell, keeps an indexed heap of cells with decrease-key instead.)

The heap is a tuple of arrays ``(keys, ids, size)``, where ``size`` is a one-element int64 array so the
functions can grow it in place; ``push`` returns the (possibly reallocated) arrays.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def new_heap(capacity, width):
    """An empty heap of ``capacity`` rows (it grows when full) with ``width`` key columns."""
    return np.empty((max(capacity, 16), width)), np.empty(max(capacity, 16), np.int64), np.zeros(1, np.int64)


@njit(cache=True, inline="always")
def _less(keys, ids, a, b):
    for k in range(keys.shape[1]):
        if keys[a, k] != keys[b, k]:
            return keys[a, k] < keys[b, k]
    return ids[a] < ids[b]


@njit(cache=True, inline="always")
def _swap(keys, ids, a, b):
    for k in range(keys.shape[1]):
        keys[a, k], keys[b, k] = keys[b, k], keys[a, k]
    ids[a], ids[b] = ids[b], ids[a]


@njit(cache=True)
def push(keys, ids, size, key, item):
    """Add ``item`` with the key row ``key``; returns ``(keys, ids)``, reallocated when the heap was full."""
    n = size[0]
    if n == ids.size:
        grown_keys = np.empty((2 * n, keys.shape[1]))
        grown_keys[:n] = keys
        grown_ids = np.empty(2 * n, np.int64)
        grown_ids[:n] = ids
        keys, ids = grown_keys, grown_ids
    keys[n] = key
    ids[n] = item
    size[0] = n + 1
    while n > 0:
        parent = (n - 1) >> 1
        if not _less(keys, ids, n, parent):
            break
        _swap(keys, ids, n, parent)
        n = parent
    return keys, ids


@njit(cache=True)
def pop(keys, ids, size, out_key):
    """Remove the smallest entry: its id is returned and its key row copied into ``out_key``."""
    out_key[:] = keys[0]
    item = ids[0]
    n = size[0] - 1
    size[0] = n
    if n > 0:
        keys[0] = keys[n]
        ids[0] = ids[n]
        i = 0
        while True:
            child = 2 * i + 1
            if child >= n:
                break
            if child + 1 < n and _less(keys, ids, child + 1, child):
                child += 1
            if not _less(keys, ids, child, i):
                break
            _swap(keys, ids, i, child)
            i = child
    return item
