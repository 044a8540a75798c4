"""Grid A* returns optimal paths: checked against scikit-image's MCP_Geometric (same cost model), and the
compiled search returns exactly what the plain-Python reference returns (path, cost bits, expansions)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.search.grid_astar import plan
from navlab.search.grid_reference import astar_reference, dijkstra_cost


def _path_cost(cost, cells, resolution):
    steps = np.diff(cells, axis=0)
    length = np.hypot(steps[:, 0], steps[:, 1]) * resolution
    return float(np.sum(length * 0.5 * (cost[cells[:-1, 0], cells[:-1, 1]] + cost[cells[1:, 0], cells[1:, 1]])))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10_000), rows=st.integers(2, 24), cols=st.integers(2, 24),
       blocked=st.floats(0.0, 0.4), resolution=st.sampled_from([0.5, 1.0, 2.0]))
def test_optimal_against_mcp_geometric(seed, rows, cols, blocked, resolution):
    rng = np.random.default_rng(seed)
    cost = rng.uniform(1.0, 10.0, (rows, cols))
    cost[rng.random((rows, cols)) < blocked] = np.inf
    start, goal = (0, 0), (rows - 1, cols - 1)
    cost[start] = cost[goal] = 1.0
    ours = plan(cost, start, goal, resolution=resolution)
    reference = dijkstra_cost(cost, start, goal, resolution=resolution)
    if not np.isfinite(reference):
        assert ours.cells is None and math.isinf(ours.cost)
        return
    assert ours.cost == pytest.approx(reference, rel=1e-9)
    cells = ours.cells
    assert tuple(cells[0]) == start and tuple(cells[-1]) == goal
    assert np.all(np.abs(np.diff(cells, axis=0)).max(axis=1) == 1)
    assert np.all(np.isfinite(cost[cells[:, 0], cells[:, 1]]))
    assert _path_cost(cost, cells, resolution) == pytest.approx(ours.cost, rel=1e-9)


def test_four_connected_is_manhattan_on_uniform_grid():
    path = plan(np.ones((5, 7)), (0, 0), (4, 6), diagonal=False)
    assert path.cost == pytest.approx(10.0)


def test_heuristic_prunes_expansions():
    cost = np.ones((60, 60))
    path = plan(cost, (30, 0), (30, 59))
    assert path.cost == pytest.approx(59.0)
    assert path.expansions < cost.size / 4  # a straight corridor of the open grid, not a flood fill


@pytest.mark.parametrize("cell,msg", [((0, 0), "start .* blocked"), ((9, 9), "outside")])
def test_bad_endpoints_name_the_problem(cell, msg):
    cost = np.ones((5, 5))
    cost[0, 0] = np.inf
    with pytest.raises(ValueError, match=msg):
        plan(cost, cell, (4, 4))


@pytest.mark.parametrize("bad", [np.nan, -np.inf])
def test_nan_or_minus_inf_cost_is_an_error(bad):
    cost = np.ones((5, 5))
    cost[2, 2] = bad
    with pytest.raises(ValueError, match=r"NaN or -inf"):
        plan(cost, (0, 0), (4, 4))


def assert_same_search(cost, start, goal, diagonal):
    """The compiled search and the plain-Python heapq A* agree to the bit: cost, expansions and path."""
    ours = plan(cost, start, goal, diagonal=diagonal, resolution=0.7)
    reference = astar_reference(cost, start, goal, diagonal=diagonal, resolution=0.7)
    assert ours.cost == reference.cost and ours.expansions == reference.expansions
    assert (ours.cells is None) == (reference.cells is None)
    if ours.cells is not None:
        np.testing.assert_array_equal(ours.cells, reference.cells)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000), rows=st.integers(2, 20), cols=st.integers(2, 20),
       levels=st.sampled_from([1, 2, 0]), diagonal=st.booleans())
def test_compiled_search_equals_plain_reference(seed, rows, cols, levels, diagonal):
    """Few cost levels make many equal-cost ties: the tie-breaking must match too (datasets depend on it)."""
    rng = np.random.default_rng(seed)
    cost = rng.integers(1, levels + 1, (rows, cols)).astype(float) if levels else rng.uniform(1.0, 3.0, (rows, cols))
    cost[rng.random((rows, cols)) < 0.25] = np.inf
    start, goal = (0, 0), (rows - 1, cols - 1)
    cost[start] = cost[goal] = 1.0
    assert_same_search(cost, start, goal, diagonal)


@pytest.mark.parametrize("resolution", [0.0, -1.0, np.nan, np.inf])
def test_bad_resolution_is_an_error(resolution):
    with pytest.raises(ValueError, match="resolution = .*cell size in metres"):
        plan(np.ones((3, 3)), (0, 0), (2, 2), resolution=resolution)


def test_start_equals_goal_is_a_one_cell_path():
    path = plan(np.ones((3, 3)), (1, 1), (1, 1))
    assert path.cost == 0.0 and path.cells.tolist() == [[1, 1]]


@pytest.mark.parametrize("seed,rows,cols", [(0, 200, 200), (1, 150, 240)])
def test_large_grids_equal_plain_reference(seed, rows, cols):
    """Long searches over big open lists (thousands of decrease-keys in ``heap``'s indexed heap), walls and
    uniform costs (many f ties): path, cost bits and expansions are exactly the plain-Python heapq A*'s."""
    rng = np.random.default_rng(seed)
    cost = np.ones((rows, cols)) if seed % 2 == 0 else rng.choice([1.0, 1.5, 2.0, 3.0], (rows, cols))
    cost[rng.random((rows, cols)) < 0.2] = np.inf
    for _ in range(5):
        r, c = rng.integers(0, rows), rng.integers(0, cols)
        cost[r, max(0, c - 50):c + 50] = np.inf
    free = np.argwhere(np.isfinite(cost))
    for diagonal in (True, False):
        start, goal = (tuple(int(v) for v in free[rng.integers(len(free))]) for _ in range(2))
        assert_same_search(cost, start, goal, diagonal)
