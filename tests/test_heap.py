"""The heaps of ``search.heap`` pop exactly what Python's ``heapq`` pops on ``(*keys, index)`` tuples: the
lazy heap for any pushes, the indexed heap (grid A*, D* Lite) for any mix of inserts, decrease-keys,
key changes either way and removals; the lattice search's deeper-first heap pops by key, then the larger g. Few distinct key values make many ties, so the tie-breaking by
index is checked too (the planners' outputs, and the datasets built on them, depend on it)."""

import heapq

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.search import heap

_VALUES = st.sampled_from([0.0, 1.0, 1.5, 2.0, 3.0])


def _check_layout(queue):
    """Every queued item sits at its pos slot, and no child precedes its parent."""
    slots, pos, size, key = queue
    n = int(size[0])
    for i in range(n):
        assert pos[slots[i]] == i
        if i:
            parent = slots[(i - 1) >> 1]
            assert (*key[parent], parent) < (*key[slots[i]], slots[i])
    assert (pos >= 0).sum() == n


@settings(max_examples=80, deadline=None)
@given(rows=st.lists(st.tuples(_VALUES, _VALUES, st.integers(0, 6)), min_size=1, max_size=60),
       width=st.integers(1, 2))
def test_lazy_heap_pops_in_heapq_order(rows, width):
    keys, ids, size = heap.new_heap(4, width)  # small: pushing must grow it
    reference = []
    for k1, k2, item in rows:
        row = np.array([k1, k2][:width])
        keys, ids = heap.push(keys, ids, size, row, item)
        heapq.heappush(reference, (*row.tolist(), item))
    out = np.empty(width)
    while reference:
        expected = heapq.heappop(reference)
        item = heap.pop(keys, ids, size, out)
        assert (*out.tolist(), item) == expected
    assert size[0] == 0


@settings(max_examples=80, deadline=None)
@given(rows=st.lists(st.tuples(_VALUES, _VALUES, st.integers(0, 6)), min_size=1, max_size=60),
       pops=st.lists(st.booleans(), max_size=60))
def test_deeper_first_heap_pops_the_smallest_key_then_the_largest_g(rows, pops):
    """The lattice search's open list: pushes and pops interleaved; each pop is an entry of the smallest key and,
    among those, of the largest g (the node is free among entries equal in both), and nothing is lost."""
    heap_k, heap_g, heap_c, n = np.empty(2), np.empty(2), np.empty(2, np.int64), 0  # small: pushing must grow it
    queued = []

    def pop_one():
        nonlocal n
        g, node, n = heap.deeper_first_pop(heap_k, heap_g, heap_c, n)
        best = min(queued, key=lambda e: (e[0], -e[1]))
        assert (best[0], best[1]) in [(k, gg) for k, gg, c in queued if c == node] and g == best[1]
        queued.remove(next(e for e in queued if e[1] == g and e[2] == node and e[0] == best[0]))

    for (k, g, node), pop_now in zip(rows, pops + [False] * len(rows)):
        heap_k, heap_g, heap_c, n = heap.deeper_first_push(heap_k, heap_g, heap_c, n, k, g, node)
        queued.append((k, g, node))
        if pop_now:
            pop_one()
    while queued:
        pop_one()
    assert n == 0


_OPS = st.lists(st.tuples(st.sampled_from(["set", "decrease", "remove", "pop"]), st.integers(0, 11),
                          _VALUES, _VALUES), min_size=1, max_size=120)


@settings(max_examples=150, deadline=None)
@given(ops=_OPS)
def test_indexed_heap_equals_heapq_with_lazy_deletion(ops):
    """``insert_or_update`` sets any key, ``insert_or_decrease`` a key no larger than the queued one (A*'s
    only move); the reference pushes every new key and skips the entries that are no longer current."""
    n = 12
    queue = heap.new_indexed(n, 2)
    key = queue[3]
    current, reference = {}, []

    def pop_reference():
        while True:
            k1, k2, s = heapq.heappop(reference)
            if current.get(s) == (k1, k2):
                del current[s]
                return s

    for op, s, k1, k2 in ops:
        if op == "set":
            key[s] = k1, k2
            heap.insert_or_update(queue, s)
            current[s] = (k1, k2)
            heapq.heappush(reference, (k1, k2, s))
        elif op == "decrease":
            if s in current:
                k1, k2 = min((k1, k2), current[s])
            key[s] = k1, k2
            heap.insert_or_decrease(queue, s)
            current[s] = (k1, k2)
            heapq.heappush(reference, (k1, k2, s))
        elif op == "remove" and s in current:
            heap.remove(queue, s)
            del current[s]
        elif op == "pop" and current:
            assert heap.pop_top(queue) == pop_reference()
        _check_layout(queue)
        assert queue[2][0] == len(current)
    while current:  # drain: the whole remaining order
        assert heap.pop_top(queue) == pop_reference()
    assert queue[2][0] == 0 and (queue[1] == -1).all()
