"""The three value functions of HJ-search (paper Sec. VI): general TTR, static-map BRT, human-robot BRT.

Pure functions of explicit arguments (dynamics, grid, geometry, settings); params.yaml is read elsewhere.
Every function takes a ``backend`` (solver.Backend): ``device`` (CPU default), ``dtype`` (float32 default),
``progress`` (tqdm) and ``compile`` (torch.compile the numerical Hamiltonian; pays off on CPU and CUDA once a
solve runs for more than the compile, ~25 s on CPU).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import torch

from navlab.reach.dynamics import DubinsCar4D, Dynamics, HumanRobotRelative
from navlab.reach.grid import Grid
from navlab.reach.settings import DEFAULT_SETTINGS, SolverSettings
from navlab.reach.solver import DEFAULT_BACKEND, Backend, obstacle_floor, solve


def disk_signed_distance(grid: Grid, radius: float, device="cpu", dtype=torch.float32,
                         center: tuple[float, float] = (0.0, 0.0)) -> torch.Tensor:
    """|(x_0, x_1) − center| − radius on the whole grid: a disk in the first two coordinates, a cylinder
    in the rest."""
    if not (math.isfinite(radius) and radius >= 0):
        raise ValueError(f"disk radius = {radius!r}: must be a finite number of metres >= 0")
    x, y = grid.mesh(0, device, dtype) - center[0], grid.mesh(1, device, dtype) - center[1]
    return (torch.sqrt(x * x + y * y) - radius).expand(grid.shape).contiguous()


def time_to_reach(
    dynamics: Dynamics,
    grid: Grid,
    target_values,
    horizon: float,
    settings: SolverSettings = DEFAULT_SETTINGS,
    *,
    stall_time: float | None = None,
    obstacle_values=None,
    backend: Backend = DEFAULT_BACKEND,
) -> torch.Tensor:
    """Minimum time to reach {l ≤ 0}, by first entry into the growing reach tube (Mitchell et al. 2005).

    The reach tube (control 'min', V = min(V, l)) is marched in τ; each state's TTR is the τ at which its
    value first drops to ≤ 0, interpolated linearly inside the step. States never reached get
    ``horizon``, a lower bound on their TTR. With ``stall_time``, the march stops once no new state has
    been reached for that long (the reachable part of the grid is exhausted). With ``obstacle_values`` g
    (e.g. the map's signed distance, broadcast over the other axes) the paths may not cross {g < 0}: a
    reach-avoid tube, so the TTR is the time around the obstacles (states inside them are never reached).
    """
    if dynamics.control_mode != "min":
        raise ValueError(
            "time_to_reach: the control must drive the state into the target: "
            "build the dynamics with control_mode='min'"
        )
    settings = dataclasses.replace(
        settings, value_postprocessor="backward_reachable_tube", convergence_band=None
    )
    device, dtype = backend.device, backend.dtype
    target = torch.as_tensor(target_values, dtype=dtype).to(device)
    reached = target <= 0
    if obstacle_values is not None:  # a goal state inside an obstacle is not reached (solve raises V there)
        reached &= obstacle_floor(obstacle_values, grid, dtype, device) <= 0
    ttr = torch.where(reached, torch.zeros_like(target), torch.full_like(target, float("inf")))
    last_growth = 0.0
    first_entry = torch.compile(_first_entry, dynamic=False) if backend.compile else _first_entry

    def record_first_entry(tau, dt, previous, values):
        nonlocal ttr, last_growth
        start, step = (torch.tensor(t, dtype=dtype, device=device) for t in (tau - dt, dt))
        ttr, any_entered = first_entry(ttr, previous, values, start, step)
        if bool(any_entered):
            last_growth = tau
        return stall_time is not None and tau - last_growth > stall_time

    solve(
        dynamics,
        grid,
        target,
        horizon,
        settings,
        backend=backend,
        on_step=record_first_entry,
        obstacle_values=obstacle_values,
    )
    return ttr.clamp_(max=horizon)


def _first_entry(ttr, previous, values, step_start, dt):
    """TTR with the states that crossed V ≤ 0 in this step filled in (crossing time interpolated)."""
    entered = (values <= 0) & torch.isinf(ttr)
    fraction = (previous / (previous - values).clamp(min=1e-12)).clamp(0, 1)
    return torch.where(entered, step_start + fraction * dt, ttr), entered.any()


def general_ttr(
    car: DubinsCar4D,
    grid: Grid,
    goal_radius: float,
    horizon: float,
    settings: SolverSettings = DEFAULT_SETTINGS,
    *,
    stall_time: float | None = 1.0,
    backend: Backend = DEFAULT_BACKEND,
) -> torch.Tensor:
    """Goal-centred TTR of the 4D car in free space (paper Sec. VI-A): goal = disk of ``goal_radius``
    at the origin of the (x, y) axes; grid axes (x, y, v, θ)."""
    _check_car_grid(grid, car, "general_ttr")
    reach_car = dataclasses.replace(car, control_mode="min")
    target = disk_signed_distance(grid, goal_radius, backend.device, backend.dtype)
    return time_to_reach(
        reach_car,
        grid,
        target,
        horizon,
        settings,
        stall_time=stall_time,
        backend=backend,
    )


def map_ttr(
    car: DubinsCar4D,
    grid: Grid,
    obstacle_distance_xy,
    goal_xy: tuple[float, float],
    goal_radius: float,
    robot_radius: float,
    horizon: float,
    settings: SolverSettings = DEFAULT_SETTINGS,
    *,
    stall_time: float | None = 1.0,
    backend: Backend = DEFAULT_BACKEND,
) -> torch.Tensor:
    """Map-based TTR (paper Fig. 2): time to a goal disk in a room when paths may not come closer than
    ``robot_radius`` to an obstacle, a reach-avoid tube on the room's (x, y, v, θ) grid.

    ``obstacle_distance_xy`` is the signed distance to the room's obstacles on the (x, y) nodes,
    indexed [i_x, i_y]. One solve per goal: this is what makes the map-based TTR costly in the paper.
    The goal disk is widened to half a cell diagonal when smaller: a monotone scheme creates no new
    minima, so a goal that holds no grid node would never be reached.
    """
    _check_car_grid(grid, car, "map_ttr")
    radius = max(goal_radius, 0.5 * math.hypot(*grid.spacing[:2]))
    device, dtype = backend.device, backend.dtype
    target = disk_signed_distance(grid, radius, device, dtype, center=goal_xy)
    clearance = torch.as_tensor(np.asarray(obstacle_distance_xy) - robot_radius, dtype=dtype)[:, :, None, None]
    return time_to_reach(
        dataclasses.replace(car, control_mode="min"),
        grid,
        target,
        horizon,
        settings,
        stall_time=stall_time,
        obstacle_values=clearance,
        backend=backend,
    )


def avoid_tube(
    dynamics: Dynamics,
    grid: Grid,
    failure_values,
    horizon: float,
    settings: SolverSettings = DEFAULT_SETTINGS,
    *,
    backend: Backend = DEFAULT_BACKEND,
):
    """Avoid BRT value V(x, horizon) for the failure set {l < 0} (control 'max'); returns the Solution."""
    if dynamics.control_mode != "max":
        raise ValueError(
            "avoid_tube: the control must keep away from the failure set: "
            "build the dynamics with control_mode='max'"
        )
    settings = dataclasses.replace(settings, value_postprocessor="backward_reachable_tube")
    return solve(
        dynamics,
        grid,
        failure_values,
        horizon,
        settings,
        backend=backend,
    )


def static_brt(
    sdf_values,
    car: DubinsCar4D,
    grid: Grid,
    *,
    robot_radius: float,
    max_horizon: float,
    band: float,
    tolerance: float,
    window: float = 0.5,
    settings: SolverSettings = DEFAULT_SETTINGS,
    backend: Backend = DEFAULT_BACKEND,
):
    """Static-map avoid BRT (paper Sec. VI-B), run until the band |V| < ``band`` stops moving: by less
    than ``tolerance`` (metres of value) over ``window`` seconds of horizon.

    ``sdf_values``: signed distance to the obstacles (positive in free space) on the grid's (x, y)
    nodes, indexed [i_x, i_y]; the failure set is {sdf < robot_radius}, broadcast over (v, θ).
    Returns the Solution: ``.values`` the BRT value, ``.converged`` False if ``max_horizon`` came first.
    """
    _check_car_grid(grid, car, "static_brt")
    sdf = torch.as_tensor(sdf_values, dtype=backend.dtype).to(backend.device)
    if tuple(sdf.shape) != tuple(grid.shape[:2]):
        raise ValueError(
            f"static_brt: sdf_values has shape {tuple(sdf.shape)}, the grid's (x, y) nodes "
            f"{grid.shape[:2]}; sample the signed distance on grid.axis(0) × grid.axis(1)"
        )
    failure = (sdf - robot_radius).reshape(*sdf.shape, 1, 1).expand(grid.shape).contiguous()
    settings = dataclasses.replace(
        settings, convergence_band=band, convergence_tolerance=tolerance, convergence_window=window
    )
    avoid_car = dataclasses.replace(car, control_mode="max")
    return avoid_tube(
        avoid_car,
        grid,
        failure,
        max_horizon,
        settings,
        backend=backend,
    )


def human_brt(
    relative: HumanRobotRelative,
    grid: Grid,
    *,
    collision_radius: float,
    horizon: float,
    settings: SolverSettings = DEFAULT_SETTINGS,
    backend: Backend = DEFAULT_BACKEND,
) -> torch.Tensor:
    """Human-robot avoid BRT over a fixed horizon (paper Sec. VI-C) on the (p_x, p_y, v) grid of
    ``HumanRobotRelative``; collision when the human is within ``collision_radius`` of the robot."""
    if grid.ndim != 3 or grid.periodic[:2] != (False, False):
        raise ValueError("human_brt: the grid must be (p_x, p_y, v) with no periodic axis")
    settings = dataclasses.replace(settings, convergence_band=None)
    failure = disk_signed_distance(grid, collision_radius, backend.device, backend.dtype)
    avoid = dataclasses.replace(relative, control_mode="max")
    return avoid_tube(
        avoid,
        grid,
        failure,
        horizon,
        settings,
        backend=backend,
    ).values


def _check_car_grid(grid: Grid, car, who: str):
    if grid.ndim != 4 or grid.periodic != (False, False, False, True):
        raise ValueError(
            f"{who}: the grid must be (x, y, v, θ) with only θ periodic, got periodic={grid.periodic}"
        )
    if grid.lo[2] < car.v_min - 1e-9:
        raise ValueError(f"{who}: the speed axis must start at v >= the car's v_min = {car.v_min}, got lo={grid.lo[2]}")
