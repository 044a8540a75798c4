"""Batched lookups into precomputed value functions: multilinear interpolation and frame transforms.

``interpolate`` (numpy) and ``interpolate_torch`` evaluate a grid's multilinear interpolant at N states
at once, gathering the 2^d corners by flat index (a memory-mapped array is read only where touched).
Periodic axes (θ) wrap. Other axes clamp to the grid; what a state *outside* the grid means is decided
per value function, by the lookups below, with a bound that is safe for the way the value is used:

- ``TTRLookup`` (heuristic, must not overestimate): states are moved into the goal frame (goal at the
  origin, heading relative to the goal heading); outside the domain the value is the admissible
  Euclidean bound ``max(|p| - goal_radius, 0) / v_max``. Inside, unreached states carry the horizon
  (a lower bound, set by the solver).
- ``StaticBRTLookup`` (pruner, must not call an unsafe state safe): a position outside the room is
  inside a wall and gets the grid's minimum value (the most unsafe value anywhere); speed clamps.
- ``HumanBRTLookup``: the human is put in the robot's frame (``to_robot_frame``); outside the relative
  domain the value is the lower bound ``|p| - (r_robot + r_human) - (v_human + v_max) * T`` on the
  clearance over the horizon (|v| <= v_max, a reversing robot's too), which the build guarantees is >= 0
  there (the domain covers every encounter that can close within the horizon).
"""

from __future__ import annotations

import math

import numpy as np
import torch

from navlab.reach.grid import Grid
from navlab.reach.store import StoredGrid

TWO_PI = 2.0 * math.pi


def _cell_coords(coord, lo: float, spacing: float, n: int, periodic: bool, floor, clip):
    """Lower corner index and fraction along one axis (works for numpy arrays and torch tensors)."""
    idx = (coord - lo) / spacing
    if periodic:
        i0 = floor(idx)
        frac = idx - i0
        i0 = i0 % n
        return i0, (i0 + 1) % n, frac
    idx = clip(idx, 0.0, n - 1.0)
    i0 = clip(floor(idx), 0, n - 2)
    return i0, i0 + 1, idx - i0


def interpolate(values: np.ndarray, grid: Grid, points: np.ndarray) -> np.ndarray:
    """Multilinear interpolant of ``values`` (shape ``grid.shape``) at ``points`` (N, d): (N,) float64."""
    points = np.asarray(points, dtype=np.float64)
    _check(values.shape, grid, points.shape)
    _check_finite(bool(np.isfinite(points).all()))
    flat = values.reshape(-1)
    strides = np.cumprod((1,) + grid.shape[::-1])[:-1][::-1]
    axes = [_cell_coords(points[:, d], grid.lo[d], grid.spacing[d], grid.shape[d], grid.periodic[d],
                         np.floor, np.clip) for d in range(grid.ndim)]
    out = np.zeros(len(points))
    for corner in range(1 << grid.ndim):
        index = np.zeros(len(points), dtype=np.int64)
        weight = np.ones(len(points))
        for d, (i0, i1, frac) in enumerate(axes):
            upper = (corner >> d) & 1
            index += (i1 if upper else i0).astype(np.int64) * strides[d]
            weight *= frac if upper else 1.0 - frac
        out += weight * flat[index]
    return out


def interpolate_torch(values: torch.Tensor, grid: Grid, points: torch.Tensor) -> torch.Tensor:
    """Torch twin of ``interpolate`` (same formula, runs on ``values.device``); returns (N,) float64."""
    points = points.to(dtype=torch.float64, device=values.device)
    _check(tuple(values.shape), grid, tuple(points.shape))
    _check_finite(bool(torch.isfinite(points).all()))
    flat = values.reshape(-1)
    strides = np.cumprod((1,) + grid.shape[::-1])[:-1][::-1]
    axes = [_cell_coords(points[:, d], grid.lo[d], grid.spacing[d], grid.shape[d], grid.periodic[d],
                         torch.floor, torch.clamp) for d in range(grid.ndim)]
    out = torch.zeros(len(points), dtype=torch.float64, device=values.device)
    for corner in range(1 << grid.ndim):
        index = torch.zeros(len(points), dtype=torch.int64, device=values.device)
        weight = torch.ones(len(points), dtype=torch.float64, device=values.device)
        for d, (i0, i1, frac) in enumerate(axes):
            upper = (corner >> d) & 1
            index += (i1 if upper else i0).long() * int(strides[d])
            weight *= frac if upper else 1.0 - frac
        out += weight * flat[index].double()
    return out


def _check_finite(all_finite: bool) -> None:
    """A NaN or inf state has no cell: it would index far outside the grid or read as a safe NaN value."""
    if not all_finite:
        raise ValueError("interpolate: a state holds NaN or inf; look up finite states only (check the "
                         "simulator or planner that produced it)")


def _check(values_shape: tuple, grid: Grid, points_shape: tuple) -> None:
    if tuple(values_shape) != grid.shape:
        raise ValueError(f"interpolate: values of shape {tuple(values_shape)} do not match grid {grid.shape}")
    if len(points_shape) != 2 or points_shape[1] != grid.ndim:
        raise ValueError(f"interpolate: points must be (N, {grid.ndim}), got {tuple(points_shape)}")


def outside(grid: Grid, points, dims: tuple[int, ...] | None = None):
    """Boolean (N,) mask of points beyond the grid's [lo, hi] on any of ``dims`` (non-periodic ones)."""
    dims = tuple(d for d in (range(grid.ndim) if dims is None else dims) if not grid.periodic[d])
    mask = points[:, 0] != points[:, 0]  # all False, same array type and device as points
    for d in dims:
        mask = mask | (points[:, d] < grid.lo[d]) | (points[:, d] > grid.hi[d])
    return mask


def wrap_angle(a):
    """Angles into [-π, π)."""
    return (a + math.pi) % TWO_PI - math.pi


def _rotate(x, y, angle):
    c, s = (torch.cos(angle), torch.sin(angle)) if isinstance(angle, torch.Tensor) else (
        np.cos(angle), np.sin(angle))
    return c * x - s * y, s * x + c * y


def _stack(cols):
    return torch.stack(cols, dim=-1) if isinstance(cols[0], torch.Tensor) else np.stack(cols, axis=-1)


def to_goal_frame(states, goal_xy, goal_heading=0.0):
    """World (N, 4) states (x, y, v, θ) -> the TTR frame: goal at the origin, heading along +x."""
    gx, gy = goal_xy[..., 0], goal_xy[..., 1]
    x, y = _rotate(states[:, 0] - gx, states[:, 1] - gy, -goal_heading)
    return _stack([x, y, states[:, 2], wrap_angle(states[:, 3] - goal_heading)])


def to_robot_frame(robot_states, human_xy):
    """Human position relative to the robot, in the robot's frame (x ahead, y to the left): (N, 2)."""
    x, y = _rotate(human_xy[..., 0] - robot_states[:, 0], human_xy[..., 1] - robot_states[:, 1],
                   -robot_states[:, 3])
    return _stack([x, y])


class _Lookup:
    """Shared plumbing: numpy states use the memory map; torch states a cached tensor on their device."""

    def __init__(self, stored: StoredGrid):
        self.stored, self.grid = stored, stored.grid
        self._tensors: dict[torch.device, torch.Tensor] = {}

    def _interp(self, points):
        if isinstance(points, torch.Tensor):
            if points.device not in self._tensors:
                self._tensors[points.device] = torch.from_numpy(np.array(self.stored.values)).to(points.device)
            return interpolate_torch(self._tensors[points.device], self.grid, points)
        return interpolate(self.stored.values, self.grid, points)


def _where(mask, a, b):
    return torch.where(mask, a, b) if isinstance(mask, torch.Tensor) else np.where(mask, a, b)


def _f64(a):
    return a.double() if isinstance(a, torch.Tensor) else np.asarray(a, dtype=np.float64)


def _norm(xy):
    return torch.linalg.vector_norm(xy, dim=-1) if isinstance(xy, torch.Tensor) else np.linalg.norm(xy, axis=-1)


class TTRLookup(_Lookup):
    """General TTR heuristic: ``h(states, goal_xy)`` for world states (N, 4) -> (N,) seconds."""

    def __init__(self, stored: StoredGrid):
        super().__init__(stored)
        inputs = stored.meta["inputs"]
        self.v_max = float(inputs["robot"]["v_max"])
        self.goal_radius = float(inputs["ttr"]["goal_radius_m"])

    def __call__(self, states, goal_xy, goal_heading=0.0):
        local = to_goal_frame(states, goal_xy, goal_heading)
        euclid = (_norm(local[:, :2]) - self.goal_radius).clip(min=0.0) / self.v_max
        return _where(outside(self.grid, local, dims=(0, 1)), _f64(euclid), self._interp(local))


class StaticBRTLookup(_Lookup):
    """Static-map BRT of one room: ``V(states)`` for room-frame states (N, 4); V < threshold is unsafe."""

    def __init__(self, stored: StoredGrid):
        super().__init__(stored)
        self.unsafe_value = float(stored.meta.get("info", {}).get("min_value", np.min(stored.values)))

    def __call__(self, states):
        values = self._interp(states)
        return _where(outside(self.grid, states, dims=(0, 1)), self.unsafe_value, values)


class MapTTRLookup(_Lookup):
    """Map-based TTR to the room goal it was solved for: ``h(states)`` for room-frame states (N, 4).

    Outside the room grid, and inside obstacles, it returns the horizon: the lower bound it stores for
    every state it never reached.
    """

    def __init__(self, stored: StoredGrid):
        super().__init__(stored)
        self.horizon = float(stored.meta["inputs"]["ttr"]["horizon_s"])

    def __call__(self, states):
        return _where(outside(self.grid, states, dims=(0, 1)), self.horizon, self._interp(states))


class HumanBRTLookup(_Lookup):
    """Human-robot BRT: ``V(robot_states (N, 4), human_xy (N, 2))``; relative state is (x_rel, y_rel, v)."""

    def __init__(self, stored: StoredGrid):
        super().__init__(stored)
        inputs = stored.meta["inputs"]
        robot, human = inputs["robot"], inputs["human"]
        self.collision_radius = float(robot["radius_m"]) + float(human["radius_m"])
        self.closing = (float(human["speed"]) + float(robot["v_max"])) * float(inputs["human_brt"]["horizon_s"])

    def relative_states(self, robot_states, human_xy):
        rel = to_robot_frame(robot_states, human_xy)
        return _stack([rel[:, 0], rel[:, 1], robot_states[:, 2]])

    def __call__(self, robot_states, human_xy):
        rel = self.relative_states(robot_states, human_xy)
        bound = _f64(_norm(rel[:, :2]) - self.collision_radius - self.closing)
        return _where(outside(self.grid, rel, dims=(0, 1)), bound, self._interp(rel))
