"""The solver against closed-form value functions, at two resolutions (the error must fall)."""

import math

import pytest
import torch

from navlab.hj.reachability import avoid_tube, disk_signed_distance, general_ttr, time_to_reach
from navlab.reach.dynamics import DubinsCar4D
from navlab.reach.grid import Grid
from navlab.reach.settings import SolverSettings
from navlab.reach.solver import Backend, solve
from reach_dynamics_support import DoubleIntegrator, SingleIntegrator, SingleIntegratorPursuitEvasion

pytestmark = pytest.mark.usefixtures("single_thread")

QUIET, QUIET64 = Backend(progress=False), Backend(dtype=torch.float64, progress=False)


def _square(n, half_width):
    return Grid((-half_width, -half_width), (half_width, half_width), (n, n), (False, False))


@pytest.mark.parametrize("name, margin", [("upwind1", 0.12), ("eno2", 0.04), ("weno5", 0.03)])
def test_single_integrator_ttr_is_distance_over_speed(name, margin):
    """TTR to a disk of radius r at speed s is (|x| − r)/s; the error falls with h and stays within a margin."""
    speed, radius, errors = 2.0, 0.5, []
    for n in (41, 81):
        grid = _square(n, 2.0)
        r = torch.sqrt(grid.mesh(0) ** 2 + grid.mesh(1) ** 2)
        ttr = time_to_reach(
            SingleIntegrator(speed), grid, r - radius, 1.0, SolverSettings(scheme=name), backend=QUIET
        )
        exact = ((r - radius) / speed).clamp(min=0)
        inside = r <= 2.0  # every state within reach of the target before the horizon
        errors.append(float((ttr - exact)[inside].abs().max()))
    assert errors[1] < errors[0]
    assert errors[1] < margin


@pytest.mark.parametrize("name, margin", [("upwind1", 0.15), ("weno5", 0.04)])
def test_pursuit_evasion_capture_radius_grows_at_the_speed_difference(name, margin):
    evader, pursuer, radius, tau = 0.5, 1.0, 0.4, 1.5
    errors = []
    for n in (41, 81):
        grid = _square(n, 2.0)
        failure = disk_signed_distance(grid, radius)
        game = SingleIntegratorPursuitEvasion(evader, pursuer)
        values = avoid_tube(game, grid, failure, tau, SolverSettings(scheme=name), backend=QUIET).values
        # the exact tube value: the distance shrinks at v_p − v_e until capture, so the disk's radius
        # grows by (v_p − v_e) τ
        exact = ((failure + radius) - (pursuer - evader) * tau).clamp(min=0) - radius
        errors.append(float((values - exact).abs().max()))
        row = values[n // 2 :, n // 2]  # along +x from the centre
        i = int((row <= 0).nonzero().max())
        crossing = grid.axis(0)[n // 2 + i] + grid.spacing[0] * float(-row[i] / (row[i + 1] - row[i]))
        assert abs(crossing - (radius + (pursuer - evader) * tau)) <= grid.spacing[0]
    assert errors[1] < errors[0]
    assert errors[1] < margin


def test_faster_evader_is_only_caught_inside_the_capture_set():
    grid = _square(41, 2.0)
    failure = disk_signed_distance(grid, 0.4)
    values = avoid_tube(SingleIntegratorPursuitEvasion(1.0, 0.5), grid, failure, 1.0, backend=QUIET).values
    assert torch.equal(values <= 0, failure <= 0)
    assert torch.allclose(values, failure, atol=1e-6)


def _double_integrator_min_time(x, v):
    """Minimum time to the origin of ẍ = u, |u| ≤ 1 (bang-bang with one switch)."""
    above = x + v * v.abs() / 2 > 0
    t_above = v + 2 * torch.sqrt((x + v * v / 2).clamp(min=0))
    t_below = -v + 2 * torch.sqrt((-x + v * v / 2).clamp(min=0))
    return torch.where(above, t_above, t_below)


def test_double_integrator_minimum_time_function():
    """TTR to the set {T* ≤ T0} is T* − T0 (dynamic programming along the optimal bang-bang path)."""
    t0, errors = 1.0, []
    for n in (61, 121):
        grid = _square(n, 2.5)
        x, v = grid.mesh(0, dtype=torch.float64), grid.mesh(1, dtype=torch.float64)
        t_star = _double_integrator_min_time(x, v)
        ttr = time_to_reach(
            DoubleIntegrator(1.0),
            grid,
            t_star - t0,
            2.0,
            SolverSettings(scheme="weno5"),
            backend=QUIET64,
        )
        exact = (t_star - t0).clamp(min=0)
        # states whose optimal path stays inside the grid and is reached before the horizon, away from
        # the switching curve x = −v|v|/2 where T* has a kink (there the error is first order)
        region = (x.abs() <= 1.0) & (v.abs() <= 1.0) & (exact < 1.8)
        smooth = region & ((x + v * v.abs() / 2).abs() > 3 * grid.spacing[0])
        errors.append((float((ttr - exact)[smooth].abs().max()), float((ttr - exact)[region].abs().mean())))
    assert errors[1][0] < errors[0][0] and errors[1][1] < errors[0][1]
    assert errors[1][0] < 0.05 and errors[1][1] < 0.005


def test_dubins_car_ttr_on_the_heading_aligned_slice():
    """Facing the goal, the fastest way in is to accelerate to v_max and cruise: a closed form in (d, v0)."""
    car = DubinsCar4D(v_max=1.0, a_min=-1.0, a_max=1.0, omega_max=1.5)
    grid = Grid(
        (-2.4, -2.4, 0.0, -math.pi), (2.4, 2.4, 1.0, math.pi), (33, 33, 5, 16), (False, False, False, True)
    )
    radius = 0.3
    ttr = general_ttr(car, grid, radius, 3.0, SolverSettings(scheme="eno2"), stall_time=None, backend=QUIET)
    xs, vs = grid.axis(0), grid.axis(2)
    centre, facing_origin = 16, 0  # y = 0 row; θ = −π points from x > 0 towards the goal
    worst = 0.0
    for i in range(centre + 4, 32):
        for k, v0 in enumerate(vs):
            d = xs[i] - radius
            d_acc = (car.v_max**2 - v0**2) / (2 * car.a_max)
            if d <= d_acc:
                exact = (-v0 + math.sqrt(v0**2 + 2 * car.a_max * d)) / car.a_max
            else:
                exact = (car.v_max - v0) / car.a_max + (d - d_acc) / car.v_max
            error = float(ttr[i, centre, k, facing_origin]) - exact
            assert -0.05 <= error  # never optimistic by more than the margin: usable as a heuristic - 0.05
            worst = max(worst, abs(error))
    assert worst < 0.25


def test_bad_inputs_stop_with_a_message_naming_the_fix():
    grid = _square(11, 1.0)
    with pytest.raises(ValueError, match="shape"):
        solve(SingleIntegrator(1.0), grid, torch.zeros(10, 11), 1.0, backend=QUIET)
    with pytest.raises(ValueError, match="NaN"):
        solve(SingleIntegrator(1.0), grid, torch.full((11, 11), float("nan")), 1.0, backend=QUIET)
    with pytest.raises(ValueError, match="increasing"):
        solve(SingleIntegrator(1.0), grid, torch.zeros(11, 11), [1.0, 0.5], backend=QUIET)
    with pytest.raises(ValueError, match="rk_order"):
        SolverSettings(rk_order=4)
    with pytest.raises(ValueError, match="control_mode='min'"):
        time_to_reach(
            SingleIntegrator(1.0, control_mode="max"), grid, torch.zeros(11, 11), 1.0, backend=QUIET
        )


def test_float64_and_snapshots_at_requested_times():
    grid = _square(41, 2.0)
    r = torch.sqrt(grid.mesh(0, dtype=torch.float64) ** 2 + grid.mesh(1, dtype=torch.float64) ** 2)
    solution = solve(
        SingleIntegrator(1.0), grid, r - 0.5, [0.0, 0.25, 0.5], backend=QUIET64
    )
    assert solution.snapshots.dtype == torch.float64 and solution.snapshots.shape == (3, 41, 41)
    assert solution.time == pytest.approx(0.5)
    far = r > 1.2
    for tau, values in zip([0.0, 0.25, 0.5], solution.snapshots):
        assert torch.allclose(values[far], (r - 0.5 - tau)[far], atol=0.02)


def test_global_dissipation_smears_more_than_local_but_stays_within_the_margin():
    grid = _square(61, 2.5)
    x, v = grid.mesh(0, dtype=torch.float64), grid.mesh(1, dtype=torch.float64)
    t_star = _double_integrator_min_time(x, v)
    exact = (t_star - 1.0).clamp(min=0)
    region = (x.abs() <= 1.0) & (v.abs() <= 1.0) & (exact < 1.8)
    mean_error = {}
    for kind in ("local", "global"):
        settings = SolverSettings(scheme="eno2", dissipation=kind)
        ttr = time_to_reach(
            DoubleIntegrator(1.0), grid, t_star - 1.0, 2.0, settings, backend=QUIET64
        )
        mean_error[kind] = float((ttr - exact)[region].abs().mean())
    assert mean_error["local"] < mean_error["global"] < 0.05, mean_error
