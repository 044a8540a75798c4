"""Reach-avoid TTR: paths may not cross obstacles, so the time to reach behind a wall is the detour's."""

import math

import pytest
import torch

from navlab.hj.reachability import time_to_reach
from navlab.reach.grid import Grid
from navlab.reach.settings import SolverSettings
from navlab.reach.solver import Backend
from reach_dynamics_support import SingleIntegrator

pytestmark = pytest.mark.usefixtures("single_thread")

QUIET = Backend(progress=False)
HALF, N, HORIZON = 3.0, 61, 6.0
WALL_HALF_WIDTH, WALL_TOP = 0.15, 1.0  # the wall: |x| ≤ 0.15, y ≤ 1 (down to the grid's edge)
GOAL, GOAL_RADIUS = (-1.5, -1.0), 0.3


def _wall_signed_distance(x, y):
    """Signed distance to the box |x| ≤ w, −∞ < y ≤ top (negative inside)."""
    dx = x.abs() - WALL_HALF_WIDTH
    dy = y - WALL_TOP
    outside = torch.sqrt(dx.clamp(min=0) ** 2 + dy.clamp(min=0) ** 2)
    return outside + torch.maximum(dx, dy).clamp(max=0)


@pytest.fixture(scope="module")
def corridor():
    threads = torch.get_num_threads()
    torch.set_num_threads(1)  # module fixtures run before the single_thread one
    grid = Grid((-HALF, -HALF), (HALF, HALF), (N, N), (False, False))
    x, y = grid.mesh(0), grid.mesh(1)
    target = torch.sqrt((x - GOAL[0]) ** 2 + (y - GOAL[1]) ** 2) - GOAL_RADIUS
    obstacle = _wall_signed_distance(x, y)
    settings = SolverSettings(scheme="eno2", rk_order=2)
    free = time_to_reach(SingleIntegrator(1.0), grid, target, HORIZON, settings, backend=QUIET)
    walled = time_to_reach(
        SingleIntegrator(1.0), grid, target, HORIZON, settings, obstacle_values=obstacle, backend=QUIET
    )
    torch.set_num_threads(threads)
    return grid, x.expand(N, N), y.expand(N, N), obstacle, free, walled


def _node(grid, px, py):
    return tuple(round((p - lo) / h) for p, lo, h in zip((px, py), grid.lo, grid.spacing))


def test_behind_the_wall_the_ttr_is_the_detour_around_its_end(corridor):
    grid, _, _, _, free, walled = corridor
    start = (1.5, -1.0)
    i = _node(grid, *start)
    corner_left, corner_right = (-WALL_HALF_WIDTH, WALL_TOP), (WALL_HALF_WIDTH, WALL_TOP)
    detour = math.dist(start, corner_right) + 2 * WALL_HALF_WIDTH + math.dist(corner_left, GOAL) - GOAL_RADIUS
    straight = math.dist(start, GOAL) - GOAL_RADIUS
    assert abs(float(free[i]) - straight) < 0.05
    # the shortest path hugs the wall's end: no shorter (it may not cross) and not much longer
    assert float(walled[i]) >= float(free[i]) + (detour - straight) - 0.1
    assert float(walled[i]) <= detour + 0.5  # measured 5.11 against 4.83 at h = 0.1 (ENO2 smears the corner)


def test_where_the_straight_path_is_clear_the_ttr_is_unchanged(corridor):
    _, x, y, _, free, walled = corridor
    clear = (x <= -0.6) & (y <= WALL_TOP - 0.2)  # segment to the goal stays left of the wall
    assert float((walled - free)[clear].abs().max()) < 0.05


def test_obstacles_are_never_entered_and_only_slow_the_robot(corridor):
    _, _, _, obstacle, free, walled = corridor
    assert bool((walled[obstacle < 0] == HORIZON).all())
    assert bool((walled >= free - 0.05).all())


def test_obstacle_values_must_broadcast_to_the_grid():
    grid = Grid((-1.0, -1.0), (1.0, 1.0), (11, 11), (False, False))
    target = torch.sqrt(grid.mesh(0) ** 2 + grid.mesh(1) ** 2).expand(11, 11) - 0.2
    with pytest.raises(ValueError, match="obstacle values"):
        time_to_reach(SingleIntegrator(1.0), grid, target, 1.0, obstacle_values=torch.zeros(5, 5),
                      backend=QUIET)
