"""Symmetries, monotonicity and soundness by simulation of the three value functions."""

import itertools
import math

import pytest
import torch

from navlab.hj.reachability import disk_signed_distance, general_ttr, human_brt, static_brt
from navlab.reach.dynamics import DubinsCar4D, HumanRobotRelative
from navlab.reach.grid import Grid
from navlab.reach.settings import SolverSettings
from navlab.reach.solver import Backend
from reach_support import interpolate

pytestmark = pytest.mark.usefixtures("single_thread")

QUIET = Backend(progress=False)
CAR = DubinsCar4D(v_max=1.0, a_min=-1.0, a_max=1.0, omega_max=1.5)
ROOM = (4.0, 3.0)  # walls on the grid's border
BOX = ((1.6, 1.0), (2.4, 1.9))  # one obstacle, lower and upper corners
ROBOT_RADIUS = 0.15


def room_signed_distance(x, y):
    """Exact signed distance to the walls and the box (positive in free space)."""
    walls = torch.minimum(torch.minimum(x, ROOM[0] - x), torch.minimum(y, ROOM[1] - y))
    (x0, y0), (x1, y1) = BOX
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    qx, qy = (x - cx).abs() - (x1 - x0) / 2, (y - cy).abs() - (y1 - y0) / 2
    outside = torch.sqrt(qx.clamp(min=0) ** 2 + qy.clamp(min=0) ** 2)
    box = outside + torch.minimum(torch.maximum(qx, qy), torch.zeros_like(qx))
    return torch.minimum(walls, box)


@pytest.fixture(scope="module")
def ttr_grid():
    torch.set_num_threads(1)
    grid = Grid(
        (-2.0, -2.0, 0.0, -math.pi), (2.0, 2.0, 1.0, math.pi), (25, 25, 5, 16), (False, False, False, True)
    )
    return grid, general_ttr(CAR, grid, 0.3, 3.0, SolverSettings(scheme="eno2"), backend=QUIET)


@pytest.fixture(scope="module")
def room_brt():
    torch.set_num_threads(1)
    grid = Grid(
        (0.0, 0.0, 0.0, -math.pi),
        (ROOM[0], ROOM[1], 1.0, math.pi),
        (41, 31, 5, 16),
        (False, False, False, True),
    )
    sdf = room_signed_distance(grid.mesh(0)[:, :, 0, 0], grid.mesh(1)[:, :, 0, 0])
    solution = static_brt(
        sdf,
        CAR,
        grid,
        robot_radius=ROBOT_RADIUS,
        max_horizon=8.0,
        band=0.3,
        tolerance=0.01,
        settings=SolverSettings(scheme="eno2"),
        backend=QUIET,
    )
    return grid, sdf - ROBOT_RADIUS, solution


def test_ttr_mirror_symmetry(ttr_grid):
    """Mirroring y → −y and θ → −θ maps the car's trajectories onto each other."""
    grid, ttr = ttr_grid
    n = grid.shape[3]
    mirrored_theta = [(-k) % n for k in range(n)]  # θ_k = −π + k·dθ  ↦  −θ_k = θ_{n−k}
    mirrored = ttr.flip(1)[..., mirrored_theta]
    assert torch.allclose(ttr, mirrored, atol=1e-4)


def test_ttr_theta_roll_equivariance(ttr_grid):
    """Rotating the plane by 90° and the heading by π/2 leaves the obstacle-free TTR unchanged."""
    grid, ttr = ttr_grid
    quarter = grid.shape[3] // 4
    # (x, y) ↦ (−y, x): new[i, j] = old at (x_i, y_j) rotated back, i.e. old(y_j, −x_i)
    rotated = torch.rot90(ttr, k=1, dims=(0, 1)).roll(quarter, dims=3)
    assert torch.allclose(ttr, rotated, atol=1e-4)


def test_ttr_is_zero_on_the_goal_and_grows_outwards(ttr_grid):
    grid, ttr = ttr_grid
    r = torch.sqrt(grid.mesh(0) ** 2 + grid.mesh(1) ** 2).expand(grid.shape)
    assert torch.all(ttr[r <= 0.3] == 0)
    assert torch.all(ttr[r > 0.3] > 0)
    # admissible against the straight-line bound: no state reaches faster than distance / v_max
    # (away from the outer boundary, where optimal paths that leave the grid are cut short)
    interior = r <= 1.5
    assert torch.all(ttr[interior] >= (r[interior] - 0.3) / CAR.v_max - 0.05)


def test_avoid_tube_grows_with_the_horizon_and_contains_the_failure_set():
    grid = Grid(
        (0.0, 0.0, 0.0, -math.pi),
        (ROOM[0], ROOM[1], 1.0, math.pi),
        (21, 16, 5, 12),
        (False, False, False, True),
    )
    failure = (
        (room_signed_distance(grid.mesh(0), grid.mesh(1)) - ROBOT_RADIUS).expand(grid.shape).contiguous()
    )
    from navlab.reach.solver import solve

    solution = solve(
        CAR, grid, failure, [0.0, 0.5, 1.0, 2.0], SolverSettings(scheme="upwind1"), backend=QUIET
    )
    snapshots = solution.snapshots
    assert torch.equal(snapshots[0], failure)
    for earlier, later in itertools.pairwise(snapshots):
        assert torch.all((earlier <= 0) <= (later <= 0))  # nested tubes
        # V(·, τ) falls with τ where the earlier tube had not yet arrived (up to round-off of the
        # stencils); inside it, near the walls, the scheme may lift the value by a fraction of a cell,
        # which cannot move the set
        outside = earlier > 0
        assert torch.all(later[outside] <= earlier[outside] + 1e-3)
        free = failure > 0
        assert torch.all(later[free] <= earlier[free] + 0.25 * grid.spacing[0])
    assert torch.all(snapshots[-1] <= failure)
    assert int((snapshots[-1] <= 0).sum()) > int((failure <= 0).sum())


def test_static_brt_converges_on_the_band_and_is_ordered_by_speed(room_brt):
    grid, failure, solution = room_brt
    assert solution.converged and solution.time < 8.0
    unsafe = solution.values <= 0
    assert torch.all(unsafe >= (failure <= 0)[:, :, None, None])  # BRT ⊇ failure set
    # a stopped car stays put, so at v = 0 the BRT is the failure set (up to a cell of smearing)
    stopped = unsafe[:, :, 0, :]
    assert torch.all(stopped <= (failure <= grid.spacing[0])[:, :, None])
    volume = unsafe.sum(dim=(0, 1, 3))
    assert torch.all(volume[1:] >= volume[:-1]) and volume[-1] > volume[0]  # Fig. 3: grows with speed


def _rollout(grid, values, starts, seconds, dt=0.01):
    """Greedy safe control (the maximising input for ∇V) from each start; returns min clearance on the way."""
    gradients = torch.gradient(values, spacing=grid.spacing[:3], dim=(0, 1, 2))
    theta_gradient = (values.roll(-1, 3) - values.roll(1, 3)) / (2 * grid.spacing[3])
    gradients = [*gradients, theta_gradient]
    state = [s.clone() for s in starts]
    clearance = room_signed_distance(state[0], state[1]) - ROBOT_RADIUS
    for _ in range(int(seconds / dt)):
        grad = [interpolate(grid, g, state) for g in gradients]
        control = CAR.optimal_control(state, grad)
        velocity = CAR.velocity(state, control)
        state = [s + dt * f for s, f in zip(state, velocity)]
        state[2] = state[2].clamp(0.0, CAR.v_max)
        clearance = torch.minimum(clearance, room_signed_distance(state[0], state[1]) - ROBOT_RADIUS)
    return clearance


def test_greedy_safe_control_from_outside_the_brt_never_collides(room_brt):
    grid, _, solution = room_brt
    generator = torch.Generator().manual_seed(0)
    candidates = [
        lo + (hi - lo) * torch.rand(4000, generator=generator)
        for lo, hi in zip(grid.lo, (grid.hi[0], grid.hi[1], grid.hi[2], grid.hi[3]))
    ]
    value = interpolate(grid, solution.values, candidates)
    margin = 0.1
    safe = value > margin
    starts = [c[safe][:300] for c in candidates]
    assert len(starts[0]) == 300
    clearance = _rollout(grid, solution.values, starts, seconds=3.0)
    assert torch.all(clearance > 0), f"{int((clearance <= 0).sum())} of 300 safe starts collided"
    # and the tube is not vacuous: starts well inside it (but not yet in collision) do collide
    doomed = (value < -margin) & (room_signed_distance(candidates[0], candidates[1]) - ROBOT_RADIUS > 0.05)
    starts = [c[doomed][:100] for c in candidates]
    assert len(starts[0]) >= 20
    assert torch.all(_rollout(grid, solution.values, starts, seconds=3.0) <= 0)


def test_human_brt_for_a_stopped_robot_grows_at_the_human_speed():
    """With (almost) no acceleration, a stopped robot is a sitting target: capture radius R + s·τ."""
    sluggish = HumanRobotRelative(v_max=1.0, a_min=-1e-6, a_max=1e-6, omega_max=1.0, human_speed=0.8)
    grid = Grid((-2.0, -2.0, 0.0), (2.0, 2.0, 1.0), (41, 41, 5), (False, False, False))
    values = human_brt(
        sluggish,
        grid,
        collision_radius=0.4,
        horizon=1.0,
        settings=SolverSettings(scheme="weno5"),
        backend=QUIET,
    )
    distance = disk_signed_distance(grid, 0.0)[:, :, 0]
    exact = (distance - 0.8 * 1.0).clamp(min=0) - 0.4  # the human closes in at 0.8 m/s until contact
    assert float((values[:, :, 0] - exact).abs().max()) < 0.05


def test_human_brt_is_mirror_symmetric_and_contains_the_collision_set():
    relative = HumanRobotRelative(v_max=1.0, a_min=-1.0, a_max=1.0, omega_max=1.5, human_speed=0.8)
    grid = Grid((-2.0, -2.0, 0.0), (2.0, 2.0, 1.0), (33, 33, 5), (False, False, False))
    values = human_brt(
        relative,
        grid,
        collision_radius=0.4,
        horizon=1.0,
        settings=SolverSettings(scheme="eno2"),
        backend=QUIET,
    )
    failure = disk_signed_distance(grid, 0.4)
    assert torch.all(values <= failure)
    assert torch.allclose(values, values.flip(1), atol=1e-4)  # p_y ↦ −p_y (turning left ↔ right)
    # a human ahead of a moving robot is more dangerous than one behind it
    ahead, behind = values[24, 16, -1], values[8, 16, -1]
    assert ahead < behind
