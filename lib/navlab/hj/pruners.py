"""Pruners of the HJ-search paper as compiled look-ups: OBS, static-map BRT (Eq. 12), human FS- and
FI-BRT (Eq. 14-18, Table X).

All take whole segments: a pruner sees the ``samples_per_step`` points of every primitive of one
expansion (the paper's Table VII: 140 states per call) and drops a successor when any point fails.

- ``obs_pruner``: the collision check: clearance (exact signed distance to the room's walls and
  obstacles, sampled on a fine raster) minus the robot radius and the raster's error bound
  (``field_error``) must be > 0 at a state, and along a segment the swept check of
  ``lattice_fields.swept_unsafe`` (the search's, and the simulator's re-check) bounds it between samples
  (by the two-disc chord bound ``chord_clearance``, else the 1-Lipschitz one): ours, so that no plan a
  search returns can touch an obstacle;
- ``obs_point_pruner``: the paper's OBS baseline, the conventional instantaneous check ("perform
  instantaneous collision checking only", Sec. VII): the same clearance at the segment's samples only. A
  plan it passes may graze an obstacle between samples; the paper's dense feasibility check
  (``hj.planning.plan_clearance``) then counts it as a failure (Sec. VII-B, Fig. 7);
- ``static_brt_pruner``: the static-map BRT value must be > ``margin``, a margin measured against a finer
  solve (``hj.brt_margin``), so that the grid's discretisation error never lets an unsafe state pass;
- ``human_pruner``: the human-robot BRT with the humans fixed at their observed positions (prediction
  free). ``"fs"`` prunes V < m; ``"fi"`` prunes that and, with the finite difference of Eq. 15 over the
  step Δt, (V(s') − V(s)) / Δt < −γ (V(s') − m), γ adapted by Eq. 16-18 between γ_min and γ_max. FS is
  FI's limiting case γ → ∞, so FI prunes a superset of FS (tested).

``*_reference`` are the plain numpy versions (through ``reach.lookup``) the tests compare against.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from navlab.hj.guidance import grid_field
from navlab.maps.rooms import Room
from navlab.reach.lookup import HumanBRTLookup, StaticBRTLookup, wrap_angle
from navlab.search.lattice_fields import S_BRT, S_OBS, S_OBS_POINT, U_FI, U_FS, GridField
from navlab.search.lattice_search import HumanPruner, StaticPruner


@dataclass(frozen=True)
class FIParams:
    """Appendix A, Table X."""

    dt: float = 0.5  # Δt between neighbouring nodes (Eq. 15)
    margin: float = 0.0  # m
    gamma_min: float = 0.8
    gamma_max: float = 1.2
    k_theta: float = 10.0  # Eq. 16
    w_theta: float = 0.5  # Eq. 18
    w_dist: float = 0.5
    d_threshold: float = 0.5  # Eq. 17, m

    def __post_init__(self):
        bad = [f.name for f in dataclasses.fields(self) if not math.isfinite(getattr(self, f.name))]
        if bad or self.dt <= 0:  # a NaN margin or γ compares false: every step would pass as safe
            raise ValueError(f"FIParams {', '.join(bad) or 'dt'}: must be finite numbers (dt > 0); got {self}")


def clearance_field(room: Room, resolution: float = 0.02) -> GridField:
    """Signed distance to walls ∪ obstacles on raster nodes covering the room, [i_x, i_y]."""
    nx, ny = round(room.width / resolution) + 1, round(room.height / resolution) + 1
    x, y = np.meshgrid(np.linspace(0, room.width, nx), np.linspace(0, room.height, ny), indexing="ij")
    return GridField.from_grid(room.obstacle_distance(x, y).astype(np.float32), (0.0, 0.0),
                               (room.width / (nx - 1), room.height / (ny - 1)), (False, False))


FLOAT32_SLACK_M = 1e-5  # the raster's float32 rounding (< 1e-6 m at room scale) and the replay's, with room to spare


def field_error(field: GridField) -> float:
    """How far the bilinear interpolant of a 1-Lipschitz distance raster can exceed the true distance.

    The interpolant at p is Σ w_i d(c_i) over its cell's corners, and d(c_i) <= d(p) + |c_i − p|, so it
    exceeds d(p) by at most Σ w_i |c_i − p| <= sqrt(Σ w_i |c_i − p|²) = sqrt(hx² tx(1−tx) + hy² ty(1−ty))
    <= |(hx, hy)| / 2: half the cell diagonal (1.4 cm on the 2 cm raster), plus float32 rounding.
    """
    return 0.5 * math.hypot(*(1.0 / np.asarray(field.inv_spacing))) + FLOAT32_SLACK_M


def _checked_clearance(room: Room, robot_radius: float, resolution: float) -> tuple[GridField, float]:
    """The clearance raster and its interpolation error, after refusing a radius that would prune nothing."""
    if not (math.isfinite(robot_radius) and robot_radius >= 0):  # NaN: clearance - NaN <= 0 is never true
        raise ValueError(f"OBS robot_radius {robot_radius}: must be a finite number >= 0 (metres)")
    field = clearance_field(room, resolution)
    return field, field_error(field)


def obs_pruner(room: Room, robot_radius: float, resolution: float = 0.02) -> StaticPruner:
    """The OBS pruner: value = interpolated clearance − (radius + ``field_error``), a lower bound on the true
    clearance minus the radius (> 0 is collision-free)."""
    field, error = _checked_clearance(room, robot_radius, resolution)
    return StaticPruner(S_OBS, field, np.array([robot_radius + error, -1.0, error]), "OBS")


def obs_point_pruner(room: Room, robot_radius: float, resolution: float = 0.02) -> StaticPruner:
    """The paper's OBS pruner: the clearance at the segment's sample points must exceed the robot radius, as a
    costmap look-up checks it (no allowance for the raster's interpolation error, which ``obs_pruner`` adds
    so that its bound holds between samples)."""
    field, error = _checked_clearance(room, robot_radius, resolution)
    return StaticPruner(S_OBS_POINT, field, np.array([robot_radius, -1.0, error]), "OBS")


def static_brt_pruner(lookup: StaticBRTLookup, margin: float) -> StaticPruner:
    if not (math.isfinite(margin) and margin >= 0):  # NaN: V <= NaN is never true, nothing would be pruned
        raise ValueError(f"static BRT margin {margin}: a negative or NaN margin lets unsafe states through; "
                         f"use a finite margin >= 0")
    return StaticPruner(S_BRT, grid_field(lookup.stored.values, lookup.grid),
                        np.array([margin, lookup.unsafe_value]), "BRT")


def human_pruner(lookup: HumanBRTLookup, humans, kind: str = "fi", fi: FIParams = FIParams(),
                 velocities=None, prediction_s: float = 0.0) -> HumanPruner:
    """FS or FI human-robot BRT pruner for the observed ``humans`` (H, 2).

    With ``velocities`` (H, 2) and ``prediction_s`` > 0 a node is checked against each human where it
    walks by the node's time at its observed velocity (held after ``prediction_s``): the BRT's worst case
    covers the human's departures from that line. Frozen humans (the default) let a plan cross just
    ahead of a walking human, which the BRT at its *old* position calls safe (Zig-Zag contacts, measured).
    """
    if kind not in ("fs", "fi"):
        raise ValueError(f"human pruner kind {kind!r}: use 'fs' (feasible set) or 'fi' (forward invariant)")
    if not prediction_s >= 0:
        raise ValueError(f"human prediction_s must be >= 0 s, got {prediction_s}")
    humans = np.asarray(humans, np.float64).reshape(-1, 2)
    velocities = np.zeros_like(humans) if velocities is None else np.asarray(velocities, np.float64).reshape(-1, 2)
    if velocities.shape != humans.shape:
        raise ValueError(f"{len(velocities)} human velocities for {len(humans)} humans: give one (vx, vy) per human")
    par = np.array([lookup.collision_radius, lookup.closing, fi.margin, fi.dt, fi.gamma_min, fi.gamma_max,
                    fi.k_theta, fi.w_theta, fi.w_dist, fi.d_threshold, prediction_s])
    return HumanPruner(U_FI if kind == "fi" else U_FS, grid_field(lookup.stored.values, lookup.grid), par,
                       np.hstack([humans, velocities]), f"{kind.upper()}-BRT")


def static_prune_reference(lookup: StaticBRTLookup, margin: float, samples: np.ndarray) -> np.ndarray:
    """numpy twin of the compiled static BRT pruner: (N, S, 4) segments -> (N,) True = pruned."""
    n, s, _ = samples.shape
    return (lookup(samples.reshape(-1, 4)) <= margin).reshape(n, s).any(axis=1)


def adaptive_gamma_reference(fi: FIParams, collision_radius: float, robot: np.ndarray, human_xy) -> np.ndarray:
    """Eq. 16-18 in numpy, for (N, 4) robot states and one human position."""
    rel = np.asarray(human_xy, float)[None] - robot[:, :2]
    a_theta = np.exp(-fi.k_theta * np.abs(wrap_angle(robot[:, 3] - np.arctan2(rel[:, 1], rel[:, 0]))))
    a_dist = np.maximum(0.0, 1.0 - (np.linalg.norm(rel, axis=1) - collision_radius) / fi.d_threshold)
    risk = np.clip(fi.w_theta * a_theta + fi.w_dist * a_dist, 0.0, 1.0)
    return fi.gamma_max - (fi.gamma_max - fi.gamma_min) * risk


def human_prune_reference(lookup: HumanBRTLookup, humans, kind: str, fi: FIParams, parents: np.ndarray,
                          samples: np.ndarray, velocities=None, prediction_s: float = 0.0, t0=None,
                          durations=None) -> np.ndarray:
    """numpy twin of the compiled human pruner: parents (N, 4), samples (N, S, 4) -> (N,) True = pruned."""
    n, s, _ = samples.shape
    humans = np.asarray(humans, float).reshape(-1, 2)
    velocities = np.zeros_like(humans) if velocities is None else np.asarray(velocities, float).reshape(-1, 2)
    t0 = np.zeros(n) if t0 is None else np.asarray(t0, float)
    durations = np.zeros(n) if durations is None else np.asarray(durations, float)
    times = np.minimum(t0[:, None] + np.arange(1, s + 1)[None] * durations[:, None] / s, prediction_s)  # (N, S)
    out = np.zeros(n, bool)
    for hxy, hv in zip(humans, velocities, strict=True):
        at = hxy[None, None] + times[..., None] * hv[None, None]  # (N, S, 2)
        values = lookup(samples.reshape(-1, 4), at.reshape(-1, 2)).reshape(n, s)
        out |= (values < fi.margin).any(axis=1)
        if kind == "fi":
            v1 = values[:, -1]
            v0 = lookup(parents, hxy[None] + np.minimum(t0, prediction_s)[:, None] * hv[None])
            gamma = np.array([adaptive_gamma_reference(fi, lookup.collision_radius, samples[i, -1:], at[i, -1])[0]
                              for i in range(n)])
            out |= (v1 - v0) / fi.dt < -gamma * (v1 - fi.margin)
    return out
