"""The level-set solver loop: march ∂V/∂τ = H(x, ∇V) from τ = 0 (V = l) to the requested times.

τ is the time to go (the horizon of the backward reachable tube). Each step: one TVD Runge-Kutta step
of the Lax-Friedrichs numerical Hamiltonian, then the value postprocessor (V = min(V, l) for a tube), then
the obstacle floor V = max(V, −g) when states with g < 0 must be avoided (reach-avoid, Fisac et al. 2015),
then the optional convergence test on the band near the zero level set, then the caller's ``on_step``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import torch
from tqdm.auto import tqdm

from navlab.reach.artificial_dissipation import (
    dissipation_coefficients,
    lax_friedrichs_numerical_hamiltonian,
    max_rate,
)
from navlab.reach.grid import Grid
from navlab.reach.settings import DEFAULT_SETTINGS, SolverSettings
from navlab.reach.time_integration import RUNGE_KUTTA

# on_step(tau, dt, previous, values) -> True to stop; ``previous`` are the values before the step.
StepHook = Callable[[float, float, torch.Tensor, torch.Tensor], bool]


class Backend(NamedTuple):
    """Where and how a solve runs (device, float precision, tqdm, torch.compile), bundled because every value
    function only forwards them to ``solve``."""

    device: str | torch.device = "cpu"
    dtype: torch.dtype = torch.float32
    progress: bool = True
    compile: bool = False


DEFAULT_BACKEND = Backend()


@dataclass
class Solution:
    values: torch.Tensor  # V at the last time reached
    snapshots: torch.Tensor | None  # V at each requested time (len(times), *shape) when times were given
    time: float  # the last τ reached
    steps: int
    converged: bool  # stopped by the band test or by on_step before the horizon


def _times(times) -> tuple[np.ndarray, bool]:
    if np.ndim(times) == 0:
        horizon = float(times)
        if not (horizon > 0 and math.isfinite(horizon)):  # inf: no step is ever taken, V stays the failure set
            raise ValueError(f"solve: the horizon must be a finite number of seconds > 0, got {times!r}")
        return np.array([horizon]), False
    ts = np.asarray(times, dtype=float)
    if ts.ndim != 1 or len(ts) == 0 or ts[0] < 0 or np.any(np.diff(ts) <= 0) or not np.isfinite(ts).all():
        raise ValueError(
            f"solve: times must be a non-empty increasing sequence of times to go >= 0, got {times!r}"
        )
    return ts, True


def _band_change(reference: torch.Tensor, values: torch.Tensor, band: float, tube_target) -> float:
    """max |ΔV| since ``reference`` over the states near the zero level set (|V| < band).

    In a tube, states with l ≤ 0 are in it for good (V ≤ l), so their values cannot move the set's
    boundary and are left out: otherwise cells deep in a wall at the grid's border, where the ghost
    cells keep stirring the value, would hold the test open.
    """
    change = (values - reference).abs_()
    change.masked_fill_(values.abs() >= band, 0.0)
    if tube_target is not None:
        change.masked_fill_(tube_target <= 0, 0.0)
    return float(change.max())


def obstacle_floor(obstacle_values, grid: Grid, dtype, device) -> torch.Tensor:
    """−g, checked: the lowest value a state may take when {g < 0} must be avoided."""
    floor = torch.as_tensor(obstacle_values, dtype=dtype).to(device).neg()
    try:
        if torch.broadcast_shapes(floor.shape, grid.shape) != torch.Size(grid.shape):
            raise RuntimeError
    except RuntimeError:
        raise ValueError(f"obstacle values of shape {tuple(floor.shape)} do not broadcast to the grid "
                         f"{grid.shape}; give one value per grid node or per leading axes") from None
    if not torch.isfinite(floor).all():
        raise ValueError("obstacle values contain NaN or inf")
    return floor


def solve(
    dynamics,
    grid: Grid,
    initial_values,
    times: float | Sequence[float],
    settings: SolverSettings = DEFAULT_SETTINGS,
    *,
    backend: Backend = DEFAULT_BACKEND,
    on_step: StepHook | None = None,
    obstacle_values=None,
) -> Solution:
    """Solve the HJ(I) PDE for ``dynamics`` on ``grid`` starting from V(·, 0) = ``initial_values`` (= l).

    ``times``: a horizon (float; only the final values are returned) or an increasing sequence of times
    to go at which to keep snapshots. When the run stops early (convergence), the remaining snapshots
    hold the converged values, which is what V would stay at. ``backend.compile`` fuses the numerical
    Hamiltonian with ``torch.compile``: ~5x per step on CPU (inductor C++; 41×41×11×36 WENO5 + RK3: 37 vs
    166 ms per step on one core) and ~30x on CUDA; the first step pays the compile (CPU: ~25 s for WENO5,
    ~11 s for ENO2, 4 s when inductor's on-disk cache already holds the kernels).
    ``obstacle_values`` (g, broadcastable to the grid, e.g. a signed distance to the obstacles over the first
    axes): trajectories may not pass through {g < 0}, enforced by V = max(V, −g) at τ = 0 and after each step.
    """
    if not isinstance(settings, SolverSettings):
        raise TypeError(f"solve: settings must be a SolverSettings, got {type(settings).__name__}")
    device, dtype, progress, compile = backend.device, backend.dtype, backend.progress, backend.compile
    values = torch.as_tensor(initial_values, dtype=dtype).to(device).clone()
    if tuple(values.shape) != tuple(grid.shape):
        raise ValueError(f"solve: initial values have shape {tuple(values.shape)}, the grid {grid.shape}")
    if not torch.isfinite(values).all():
        raise ValueError("solve: initial values contain NaN or inf")
    floor = None if obstacle_values is None else obstacle_floor(obstacle_values, grid, dtype, device)
    if floor is not None:
        torch.maximum(values, floor, out=values)
    targets, keep_snapshots = _times(times)
    horizon = float(targets[-1])

    state = [grid.mesh(d, device, dtype) for d in range(grid.ndim)]
    alphas = dissipation_coefficients(dynamics, grid, state, settings.dissipation)
    rate_bound = max_rate(alphas, grid)
    max_dt = settings.cfl / rate_bound if rate_bound > 0 else horizon
    rk_step = RUNGE_KUTTA[settings.rk_order]
    tube_target = values.clone() if settings.value_postprocessor == "backward_reachable_tube" else None

    def rate(v):
        return lax_friedrichs_numerical_hamiltonian(dynamics, grid, state, v, alphas, settings.scheme)

    if compile:  # the Hamiltonian is where the time goes; compiling the whole step only compiles longer
        rate = torch.compile(rate, dynamic=False)

    snapshots = (
        torch.empty((len(targets), *grid.shape), dtype=dtype, device=device) if keep_snapshots else None
    )
    tau, steps, next_target, converged = 0.0, 0, 0, False
    band_reference, band_reference_time = None, 0.0
    if settings.convergence_band is not None:
        band_reference = values.clone()
    bar = tqdm(
        total=horizon,
        disable=not progress,
        unit="s",
        desc=f"HJ {type(dynamics).__name__}",
        bar_format="{l_bar}{bar}| τ={n:.2f}/{total:.2f} s [{elapsed}<{remaining}]",
    )
    with torch.no_grad():
        while True:
            while next_target < len(targets) and targets[next_target] <= tau + 1e-9 * max(horizon, 1.0):
                if snapshots is not None:
                    snapshots[next_target] = values
                next_target += 1
            if next_target == len(targets) or converged:
                break
            dt = min(max_dt, float(targets[next_target]) - tau)
            new_values = rk_step(rate, values, dt)
            if tube_target is not None:
                torch.minimum(new_values, tube_target, out=new_values)
            if floor is not None:
                torch.maximum(new_values, floor, out=new_values)
            tau += dt
            steps += 1
            bar.update(dt)
            if band_reference is not None and tau - band_reference_time >= settings.convergence_window:
                change = _band_change(band_reference, new_values, settings.convergence_band, tube_target)
                bar.set_postfix(band_change=f"{change:.1e}", refresh=False)
                converged = change < settings.convergence_tolerance
                band_reference.copy_(new_values)
                band_reference_time = tau
            if on_step is not None and on_step(tau, dt, values, new_values):
                converged = True
            values = new_values
            if converged and snapshots is not None:
                snapshots[next_target:] = values
    bar.close()
    return Solution(values=values, snapshots=snapshots, time=tau, steps=steps, converged=converged)
