"""The binary heaps of the numba-compiled searches: one module, so the tie-breaking rules live in one place.

(a) A lazy min-heap ordered lexicographically by a row of float keys, then an int64 id (``new_heap``,
``push``, ``pop``). Searches that rank a node by a vector of numbers of any length (COA*'s per-class
traversal counts, then f, then g) keep their open list here and skip stale entries when popped. Entries
compare by their keys column by column, then by id, so the pop order over any set of pushed entries is
one fixed total order: the same as Python's ``heapq`` on ``(*keys, id)`` tuples. The heap is a tuple of
arrays ``(keys, ids, size)``, where ``size`` is a one-element int64 array so the functions can grow it in
place; ``push`` returns the (possibly reallocated) arrays.

(b) An indexed min-heap with decrease-key over items 0..n-1 (``new_indexed``, ``before``, ``pop_top``,
``insert_or_decrease``, ``insert_or_update``, ``remove``): at most one entry per item, ordered by the
item's row of ``key`` column by column, then by the item index (``before``). A cell whose key changes
moves in place instead of being pushed again, so the heap never holds stale entries (3x faster than lazy
deletion on the grid A* benchmark maps). The order is total, so the items come out exactly as from
``heapq`` on ``(*key, index)`` tuples with lazy deletion (``grid_reference.astar_reference``), which keeps
every dataset built on these planners byte-identical. The queue travels as one tuple
``queue = (heap, pos, size, key)``: ``heap[:size[0]]`` the queued items in heap order, ``pos[s]`` the heap
slot of s (< 0: not queued; callers may keep their own negative marks, e.g. -2 for closed), ``size`` (1,)
the queue length, ``key`` (n, width) the keys, which the caller writes before it moves an item.
D* Lite (key (k1, k2)) calls these functions. Grid A* (key (f, g)) orders by ``before`` on the same
layout but writes ``pop_top`` and ``insert_or_decrease`` out in its loop: called per cell they made it
20-30% slower (see ``grid_astar._search``); the two copies must stay the same algorithm.

(c) A lazy min-heap on three parallel arrays (key, g, node) ordered by the key, then by the larger g: of
two entries with one key the deeper node comes first, the usual tie rule of A* and ANA* (it reaches the goal
sooner). Entries equal in both come out in heap order, not by node. The Dubins-lattice search
(``lattice_search._search``) keeps its open list here; ``deeper_first_push`` returns the arrays and the
length, ``deeper_first_pop`` the popped g and node and the length.
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


# ---- (b) indexed heap with decrease-key ------------------------------------------------------------------

@njit(cache=True)
def new_indexed(n, width):
    """An empty indexed heap over ``n`` items with ``width`` key columns: ``(heap, pos, size, key)``.

    int32 slots (n < 2**31) halve the memory the sifts walk through; ``key`` starts as inf (no item's
    key is read before the caller writes it)."""
    return (np.empty(n, np.int32), np.full(n, -1, np.int32), np.zeros(1, np.int64),
            np.full((n, width), np.inf))


@njit(cache=True, inline="always")
def before(key, a, b):
    """Item a precedes item b: their key rows column by column, then the smaller index (a total order).

    Public so that a search which inlines its own sift loops (grid A*) orders by this very rule."""
    for k in range(key.shape[1]):
        if key[a, k] != key[b, k]:
            return key[a, k] < key[b, k]
    return a < b


@njit(cache=True, inline="always")
def _slot(heap, pos, i, item):
    """Put ``item`` in slot ``i`` and record the slot in ``pos`` (what every sift step does)."""
    heap[i] = item
    pos[item] = i


@njit(cache=True, inline="always")
def _sift_up(heap, pos, key, i, item):
    """Place ``item`` at slot ``i`` or above, moving larger parents down (a hole, not swaps)."""
    while i > 0:
        parent = (i - 1) >> 1
        if not before(key, item, heap[parent]):
            break
        _slot(heap, pos, i, heap[parent])
        i = parent
    _slot(heap, pos, i, item)


@njit(cache=True, inline="always")
def _sift_down(heap, pos, key, i, n):
    """Move the item at slot ``i`` of ``heap[:n]`` down below its smaller children."""
    item = heap[i]
    while True:
        child = 2 * i + 1
        if child >= n:
            break
        if child + 1 < n and before(key, heap[child + 1], heap[child]):
            child += 1
        if not before(key, heap[child], item):
            break
        _slot(heap, pos, i, heap[child])
        i = child
    _slot(heap, pos, i, item)


@njit(cache=True)
def pop_top(queue):
    """Remove and return the first item (the queue must not be empty); its ``pos`` becomes -1."""
    heap, pos, size, key = queue
    top = heap[0]
    pos[top] = -1
    n = size[0] - 1
    size[0] = n
    if n > 0:  # the last item fills the root and sinks
        heap[0] = heap[n]
        _sift_down(heap, pos, key, 0, n)
    return top


@njit(cache=True, inline="always")
def _open_slot(pos, size, s):
    """``s``'s slot in the heap, or a new one at the end when ``s`` is not queued."""
    i = pos[s]
    if i < 0:
        i = size[0]
        size[0] = i + 1
    return i


@njit(cache=True)
def insert_or_decrease(queue, s):
    """Queue ``s`` (``pos[s] < 0``) or move it up after its key row dropped; the caller wrote the new key.

    Only sifts up: the cheap path of A*, whose keys of open items never grow."""
    heap, pos, size, key = queue
    _sift_up(heap, pos, key, _open_slot(pos, size, s), s)


@njit(cache=True, inline="always")
def insert_or_update(queue, s):
    """Queue ``s`` or move it to its new key row, up or down (D* Lite's U.Insert / U.Update).

    Inlined into its caller: D* Lite's walks on the benchmark maps ran 5-8% faster than with a call."""
    heap, pos, size, key = queue
    queued = pos[s] >= 0
    _sift_up(heap, pos, key, _open_slot(pos, size, s), s)
    if queued:
        _sift_down(heap, pos, key, pos[s], size[0])


@njit(cache=True)
def remove(queue, s):
    """Take the queued item ``s`` out (U.Remove); its ``pos`` becomes -1."""
    heap, pos, size, key = queue
    i = pos[s]
    pos[s] = -1
    n = size[0] - 1
    size[0] = n
    if i == n:
        return
    item = heap[n]
    _sift_up(heap, pos, key, i, item)
    _sift_down(heap, pos, key, pos[item], n)


# ---- (c) lazy heap on parallel arrays, deeper node first ------------------------------------------------


@njit(cache=True)
def _deeper_first(ka, kb, ga, gb):
    return ka < kb or (ka == kb and ga > gb)  # ties: deeper node first


@njit(cache=True)
def deeper_first_push(heap_k, heap_g, heap_c, n, k, g, c):
    """Add node ``c`` with key ``k`` and cost-to-come ``g`` to the ``n`` entries of the parallel arrays; returns
    the arrays (reallocated when full) and the new length."""
    if n == heap_k.shape[0]:
        heap_k = np.concatenate((heap_k, np.empty_like(heap_k)))
        heap_g = np.concatenate((heap_g, np.empty_like(heap_g)))
        heap_c = np.concatenate((heap_c, np.empty_like(heap_c)))
    i = n
    while i > 0:
        p = (i - 1) >> 1
        if not _deeper_first(k, heap_k[p], g, heap_g[p]):
            break
        heap_k[i], heap_g[i], heap_c[i] = heap_k[p], heap_g[p], heap_c[p]
        i = p
    heap_k[i], heap_g[i], heap_c[i] = k, g, c
    return heap_k, heap_g, heap_c, n + 1


@njit(cache=True)
def deeper_first_pop(heap_k, heap_g, heap_c, n):
    """Remove the first entry: returns its g, its node and the new length."""
    top_g, top_c = heap_g[0], heap_c[0]
    n -= 1
    k, g, c = heap_k[n], heap_g[n], heap_c[n]
    i = 0
    while True:
        child = 2 * i + 1
        if child >= n:
            break
        if child + 1 < n and _deeper_first(heap_k[child + 1], heap_k[child], heap_g[child + 1], heap_g[child]):
            child += 1
        if not _deeper_first(heap_k[child], k, heap_g[child], g):
            break
        heap_k[i], heap_g[i], heap_c[i] = heap_k[child], heap_g[child], heap_c[child]
        i = child
    heap_k[i], heap_g[i], heap_c[i] = k, g, c
    return top_g, top_c, n
