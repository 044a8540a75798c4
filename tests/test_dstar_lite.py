"""D* Lite: the worked examples of Koenig & Likhachev (replayed as gonum's dynamic tests do) and, after
every batch of cost changes while the agent moves, the cost of its path equals a from-scratch Dijkstra."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import dijkstra

from navlab.search.dstar_lite import DStarLite
from navlab.search.grid_astar import plan
from navlab.search.grid_graph import grid_csr

FIG2 = ["..................", "..................", "..................", "..................",
        "..................", "..................", "....*.*...........", "*****.***.........",
        "......*...........", "......***.........", "......*...........", "......*...........",
        "......*...........", "*****.*...........", "......*..........."]


def _walk(rows: list[str], start: int, goal: int, probe: int | None = None):
    """The agent knows nothing at first (unknown cells are assumed free), sees the cells within 1.5 cells
    of itself, moves one step along its plan, and repeats. Node ids are row * cols + col, as in gonum."""
    world = np.array([[np.inf if ch == "*" else 1.0 for ch in row] for row in rows])
    cols = world.shape[1]
    believed = np.ones_like(world)

    def sense(cell):
        window = (slice(max(cell[0] - 1, 0), cell[0] + 2), slice(max(cell[1] - 1, 0), cell[1] + 2))
        new = believed.copy()
        new[window] = world[window]
        changed = np.argwhere(new != believed)
        believed[:] = new
        return changed, new[changed[:, 0], changed[:, 1]]

    here, target = divmod(start, cols), divmod(goal, cols)
    sense(here)
    agent = DStarLite(believed.copy(), here, target)
    walked, probed = [here], None
    while here != target and len(walked) < 4 * world.size:
        path = agent.plan()
        if probe is not None and here == divmod(probe, cols):
            probed = [int(r) * cols + int(c) for r, c in path.cells]
        here = tuple(int(v) for v in path.cells[1])
        agent.move_to(here)
        walked.append(here)
        changed, costs = sense(here)
        agent.update_costs(changed, costs)
    steps = np.diff(np.array(walked), axis=0)
    return [r * cols + c for r, c in walked], float(np.hypot(steps[:, 0], steps[:, 1]).sum()), probed


@pytest.mark.parametrize("rows,start,goal,prefix,weight", [
    # Fig. 2 of Koenig & Likhachev (T-RO 2005) with hypot diagonal weights, as in gonum's test table
    (FIG2, 253, 122, [253, 254, 255, 256, 239, 221, 203, 185, 167, 149, 131, 113, 96], 21.242640687119287),
    (FIG2[:8] + ["." * 18] + FIG2[9:], 253, 122, [253, 254, 255, 256, 239, 221, 203, 185, 167, 150, 151, 152],
     18.656854249492383),  # the exit kept open
    (FIG2[:8] + ["........*........."] + FIG2[9:], 253, 122,
     [253, 254, 255, 256, 239, 221, 203, 185, 167, 150, 151, 150, 131, 113, 96], 24.07106781186548),  # closed late
    (["*..*", "**.*", "**.*", "**.*"], 1, 14, [1, 6, 10, 14], 2 + math.sqrt(2)),
])
def test_worked_examples_walk_the_known_path(rows, start, goal, prefix, weight):
    walked, walked_weight, _ = _walk(rows, start, goal)
    assert walked[:len(prefix)] == prefix and walked[-1] == goal
    assert walked_weight == pytest.approx(weight, rel=1e-12)


def test_tied_corner_is_cut_at_45_degrees():
    """gonum's tie case: from node 16 the rhs values of 12 and 17 tie; the right move is the diagonal."""
    walked, weight, probed = _walk([".....", "...*.", "**.*.", "...*."], 15, 14, probe=12)
    assert walked == [15, 16, 12, 7, 3, 9, 14]
    assert weight == pytest.approx(3 + 3 * math.sqrt(2), rel=1e-12)
    assert probed == [12, 7, 3, 9, 14]


def _dijkstra_cost(cost, source, target, resolution):
    cols = cost.shape[1]
    if not np.isfinite(cost[source]):
        return math.inf
    dist = dijkstra(grid_csr(cost, resolution=resolution), indices=source[0] * cols + source[1])
    return float(dist[target[0] * cols + target[1]])


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 100_000), rows=st.integers(3, 14), cols=st.integers(3, 14),
       resolution=st.sampled_from([0.5, 1.0]), cheapest=st.sampled_from([1.0, 0.5]))
def test_cost_after_every_change_equals_dijkstra_from_scratch(seed, rows, cols, resolution, cheapest):
    """``cheapest`` < 1 lets changes undercut the heuristic's scale too (the restart branch)."""
    rng = np.random.default_rng(seed)
    cost = rng.uniform(1.0, 3.0, (rows, cols))
    cost[rng.random((rows, cols)) < 0.2] = np.inf
    here, goal = (0, 0), (rows - 1, cols - 1)
    cost[here] = cost[goal] = 1.0
    agent = DStarLite(cost, here, goal, resolution=resolution)
    for _ in range(12):
        path = agent.plan()
        reference = _dijkstra_cost(cost, here, goal, resolution)
        if math.isinf(reference):
            assert path.cells is None and math.isinf(path.cost)
        else:
            cells = path.cells
            assert path.cost == pytest.approx(reference, rel=1e-9)
            assert tuple(cells[0]) == here and tuple(cells[-1]) == goal
            assert np.all(np.abs(np.diff(cells, axis=0)).max(axis=1) == 1)
            assert np.all(np.isfinite(cost[cells[:, 0], cells[:, 1]]))
            if len(cells) > 1:
                here = tuple(int(v) for v in cells[1])
                agent.move_to(here)
        m = int(rng.integers(1, 8))
        changed = np.stack([rng.integers(0, rows, m), rng.integers(0, cols, m)], axis=1)
        changed = changed[(changed != np.array(here)).any(axis=1)]  # the agent's own cell stays free
        new = rng.uniform(cheapest, 4.0, len(changed))
        new[rng.random(len(changed)) < 0.3] = np.inf
        cost[changed[:, 0], changed[:, 1]] = new
        agent.update_costs(changed, new)


def test_repair_expands_fewer_cells_than_planning_again():
    """The paper's point: a change near the agent is repaired locally, not re-planned from scratch."""
    cost = np.random.default_rng(0).uniform(1.0, 2.0, (60, 60))
    agent = DStarLite(cost, (30, 0), (30, 59))
    first = agent.plan()
    agent.move_to(first.cells[1])
    blocked = first.cells[4:6]
    agent.update_costs(blocked, np.full(len(blocked), np.inf))
    cost[blocked[:, 0], blocked[:, 1]] = np.inf
    repaired = agent.plan()
    scratch = plan(cost, tuple(first.cells[1]), (30, 59))
    assert repaired.cost == pytest.approx(scratch.cost, rel=1e-12)
    assert repaired.expansions < scratch.expansions / 5


def test_wall_closes_then_opens_again():
    """No false "no path": the goal is reported unreachable behind a wall and reachable once it opens."""
    cost = np.ones((6, 6))
    agent = DStarLite(cost, (0, 0), (5, 5))
    wall = np.array([[3, c] for c in range(6)])
    agent.update_costs(wall, np.full(6, np.inf))
    closed = agent.plan()
    assert closed.cells is None and math.isinf(closed.cost)
    agent.update_costs(wall[2:3], [2.0])
    opened = agent.plan()
    cost[3] = np.inf
    cost[3, 2] = 2.0
    assert opened.cost == pytest.approx(_dijkstra_cost(cost, (0, 0), (5, 5), 1.0), rel=1e-12)


@pytest.mark.parametrize("call,msg", [
    (lambda c: DStarLite(c, (0, 0), (4, 4)), "start .* blocked"),
    (lambda c: DStarLite(c, (1, 1), (9, 4)), "goal .* outside"),
    (lambda c: DStarLite(np.where(np.isinf(c), np.nan, c), (1, 1), (4, 4)), "NaN"),
    (lambda c: DStarLite(c, (1, 1), (4, 4), resolution=0.0), "resolution"),
    (lambda c: DStarLite(c, (1, 1), (4, 4)).update_costs([[2, 2]], [-1.0]), "positive"),
    (lambda c: DStarLite(c, (1, 1), (4, 4)).update_costs([[2, 2]], [np.nan]), "positive"),
    (lambda c: DStarLite(c, (1, 1), (4, 4)).update_costs([[2, 7]], [1.0]), "outside"),
    (lambda c: DStarLite(c, (1, 1), (4, 4)).update_costs([[2, 2]], [1.0, 2.0]), "shape"),
    (lambda c: DStarLite(c, (1, 1), (4, 4)).move_to((0, 0)), "blocked"),
])
def test_bad_input_names_the_problem(call, msg):
    cost = np.ones((5, 5))
    cost[0, 0] = np.inf
    with pytest.raises(ValueError, match=msg):
        call(cost)


@pytest.mark.parametrize("seed", [0, 1])
def test_uniform_costs_with_many_ties_stay_optimal(seed):
    """On equal costs almost every key ties in k1 (f is constant along optimal paths), so an ulp of
    rounding in k1 decides the order: the walk blocks squares ahead of the agent and checks each repair."""
    rng = np.random.default_rng(seed)
    cost = np.ones((60, 60))
    cost[rng.random(cost.shape) < 0.1] = np.inf
    here, goal = (2, 2), (57, 57)
    cost[here] = cost[goal] = 1.0
    agent = DStarLite(cost, here, goal, resolution=0.3)
    for step in range(80):
        path = agent.plan()
        reference = _dijkstra_cost(cost, here, goal, 0.3)
        assert path.cost == pytest.approx(reference, rel=1e-9)
        if path.cells is None or len(path.cells) < 8:  # walled in, or nearly there
            break
        here = tuple(int(v) for v in path.cells[1])
        agent.move_to(here)
        if step % 3 == 0:
            r, c = path.cells[int(rng.integers(3, len(path.cells) - 2))]
            square = np.array([[r + dr, c + dc] for dr in (-1, 0, 1) for dc in (-1, 0, 1)
                               if 0 <= r + dr < 60 and 0 <= c + dc < 60 and (r + dr, c + dc) not in (here, goal)])
            cost[square[:, 0], square[:, 1]] = np.inf
            agent.update_costs(square, np.full(len(square), np.inf))
