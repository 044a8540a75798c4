"""Compiled per-state look-ups the lattice search evaluates for every successor: heuristics, pruners, cost.

Why compiled and why here: the paper's Table VII times exactly these calls (35 heuristic states, 140
pruned states per expansion) and its BRT pruner cost 12.5 % of the search time; inside a numba loop a
4D multilinear look-up is a few dozen loads, with no Python call per state. The search layer only knows
*numbers*: a ``GridField`` (values on a regular grid) and a kind code. ``navlab.reach`` builds these from
its stored value functions (``reach.guidance``, ``reach.pruners``), so the dependency points downwards.

Heuristic kinds (``H_*``), all in seconds, evaluated at a successor state (x, y, v, θ):

- ``H_ZERO``: 0 (Dijkstra);
- ``H_DIST``: max(|p − goal| − tol, 0) / v_max (the paper's general Dist, admissible form);
- ``H_RASTER``: a 2D field over (x, y) (map-based Dist: obstacle-aware travel time);
- ``H_GOAL_GRID``: the general TTR grid in the goal frame (goal at the origin, heading relative to the
  goal heading); off the grid the admissible Euclidean bound of ``reach.lookup.TTRLookup``;
- ``H_ROOM_GRID``: a 4D grid in room coordinates (map-based TTR); off the grid ``par[5]``.

Pruner kinds, static (``S_*``) and human (``U_*``), each returns True where a segment must be dropped:

- ``S_OBS``: robot clearance (2D signed-distance field − radius) <= 0 at any segment sample;
- ``S_BRT``: static-map BRT value <= margin at any sample (paper Eq. 12); off the room: pruned;
- ``U_FS``: human-robot BRT value < m at any sample, for any human (feasible-set pruning);
- ``U_FI``: FS, or the forward-invariance condition of Eq. 14 with the finite difference of Eq. 15,
  (V(s') − V(s)) / Δt < −γ (V(s') − m), and the adaptive γ of Eq. 16-18.

Every function has a plain-numpy twin in ``navlab.reach`` that the tests compare against.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

H_ZERO, H_DIST, H_RASTER, H_GOAL_GRID, H_ROOM_GRID = 0, 1, 2, 3, 4
S_NONE, S_OBS, S_BRT = 0, 1, 2
U_NONE, U_FS, U_FI = 0, 1, 2


class GridField(NamedTuple):
    """Values on a regular grid, flattened C-order, with what a compiled look-up needs (ndim <= 4)."""

    values: np.ndarray  # (prod(shape),) float32 or float64
    lo: np.ndarray  # (d,) float64
    inv_spacing: np.ndarray  # (d,) float64
    shape: np.ndarray  # (d,) int64
    periodic: np.ndarray  # (d,) bool
    strides: np.ndarray  # (d,) int64

    @classmethod
    def from_grid(cls, values: np.ndarray, lo, spacing, periodic) -> GridField:
        values = np.ascontiguousarray(values)
        shape = np.asarray(values.shape, dtype=np.int64)
        strides = np.cumprod(np.r_[1, shape[::-1]])[:-1][::-1].astype(np.int64)
        return cls(values.reshape(-1), np.asarray(lo, np.float64), 1.0 / np.asarray(spacing, np.float64), shape,
                   np.asarray(periodic, bool), strides)

    @classmethod
    def empty(cls, ndim: int = 1) -> GridField:
        """A placeholder for an unused slot (numba needs a value of the right type)."""
        one = np.ones(ndim)
        return cls(np.zeros(2 ** ndim, np.float32), np.zeros(ndim), one, np.full(ndim, 2, np.int64),
                   np.zeros(ndim, bool), np.ones(ndim, np.int64))


@numba.njit(cache=True)
def _axis(flo, finv, fshape, fper, fstr, k, x):
    """Lower corner offset, offset to the upper corner and fraction along axis ``k``."""
    n = fshape[k]
    x = (x - flo[k]) * finv[k]
    if fper[k]:
        i0 = math.floor(x)
        fr = x - i0
        i0 = int(i0) % n
        i1 = (i0 + 1) % n
    else:
        x = min(max(x, 0.0), n - 1.0)
        i0 = min(int(x), n - 2)
        fr = x - i0
        i1 = i0 + 1
    return i0 * fstr[k], (i1 - i0) * fstr[k], fr


@numba.njit(cache=True)
def interp(fv, flo, finv, fshape, fper, fstr, p0, p1, p2, p3):
    """Multilinear interpolant of field ``f`` (2, 3 or 4 axes) at (p0, ..., p_{d-1}); periodic axes wrap,
    others clamp. Written out per dimension: no allocation in the hot loop."""
    d = flo.shape[0]
    v = fv
    b0, o0, t0 = _axis(flo, finv, fshape, fper, fstr, 0, p0)
    b1, o1, t1 = _axis(flo, finv, fshape, fper, fstr, 1, p1)
    i = b0 + b1
    if d == 2:
        return ((1 - t0) * ((1 - t1) * v[i] + t1 * v[i + o1])
                + t0 * ((1 - t1) * v[i + o0] + t1 * v[i + o0 + o1]))
    b2, o2, t2 = _axis(flo, finv, fshape, fper, fstr, 2, p2)
    i += b2
    if d == 3:
        lo = (1 - t0) * ((1 - t1) * v[i] + t1 * v[i + o1]) + t0 * ((1 - t1) * v[i + o0] + t1 * v[i + o0 + o1])
        i += o2
        hi = (1 - t0) * ((1 - t1) * v[i] + t1 * v[i + o1]) + t0 * ((1 - t1) * v[i + o0] + t1 * v[i + o0 + o1])
        return (1 - t2) * lo + t2 * hi
    b3, o3, t3 = _axis(flo, finv, fshape, fper, fstr, 3, p3)
    i += b3
    out = 0.0
    for c3 in range(2):
        w3 = t3 if c3 else 1 - t3
        j = i + c3 * o3
        lo = (1 - t0) * ((1 - t1) * v[j] + t1 * v[j + o1]) + t0 * ((1 - t1) * v[j + o0] + t1 * v[j + o0 + o1])
        j += o2
        hi = (1 - t0) * ((1 - t1) * v[j] + t1 * v[j + o1]) + t0 * ((1 - t1) * v[j + o0] + t1 * v[j + o0 + o1])
        out += w3 * ((1 - t2) * lo + t2 * hi)
    return out


@numba.njit(cache=True)
def wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


@numba.njit(cache=True)
def heuristic(kind, fv, flo, finv, fshape, fper, fstr, par, x, y, v, th):
    """par: [goal_x, goal_y, goal_heading, v_max, tolerance_or_goal_radius, off_grid_value]."""
    if kind == H_ZERO:
        return 0.0
    dx, dy = x - par[0], y - par[1]
    if kind == H_DIST:
        return max(math.sqrt(dx * dx + dy * dy) - par[4], 0.0) / par[3]
    if kind == H_RASTER:
        return interp(fv, flo, finv, fshape, fper, fstr, x, y, 0.0, 0.0)
    if kind == H_GOAL_GRID:
        c, s = math.cos(par[2]), math.sin(par[2])
        lx, ly = c * dx + s * dy, -s * dx + c * dy
        if lx < flo[0] or ly < flo[1] or lx > flo[0] + (fshape[0] - 1) / finv[0] \
                or ly > flo[1] + (fshape[1] - 1) / finv[1]:
            return max(math.sqrt(lx * lx + ly * ly) - par[4], 0.0) / par[3]
        return interp(fv, flo, finv, fshape, fper, fstr, lx, ly, v, wrap(th - par[2]))
    # H_ROOM_GRID
    if x < flo[0] or y < flo[1] or x > flo[0] + (fshape[0] - 1) / finv[0] \
            or y > flo[1] + (fshape[1] - 1) / finv[1]:
        return par[5]
    return interp(fv, flo, finv, fshape, fper, fstr, x, y, v, th)


@numba.njit(cache=True)
def static_value(kind, fv, flo, finv, fshape, fper, fstr, par, x, y, v, th):
    """The static pruner's safety value at one state: clearance (S_OBS) or BRT value (S_BRT), minus margin.

    par: [robot_radius (S_OBS) or margin (S_BRT), value off the grid]. Positive is safe.
    """
    if x < flo[0] or y < flo[1] or x > flo[0] + (fshape[0] - 1) / finv[0] \
            or y > flo[1] + (fshape[1] - 1) / finv[1]:
        return par[1] - par[0]
    if kind == S_OBS:
        return interp(fv, flo, finv, fshape, fper, fstr, x, y, 0.0, 0.0) - par[0]
    return interp(fv, flo, finv, fshape, fper, fstr, x, y, v, th) - par[0]


@numba.njit(cache=True)
def human_value(fv, flo, finv, fshape, fper, fstr, par, x, y, v, th, hx, hy):
    """Human-robot BRT value for a robot state and a human position (reach.lookup.HumanBRTLookup).

    par: [collision_radius, closing_distance (speed sum × horizon), m, Δt, γ_min, γ_max, k_θ, w_θ, w_d, d_th].
    """
    c, s = math.cos(th), math.sin(th)
    rx, ry = hx - x, hy - y
    px, py = c * rx + s * ry, -s * rx + c * ry
    if px < flo[0] or py < flo[1] or px > flo[0] + (fshape[0] - 1) / finv[0] \
            or py > flo[1] + (fshape[1] - 1) / finv[1]:
        return math.sqrt(px * px + py * py) - par[0] - par[1]
    return interp(fv, flo, finv, fshape, fper, fstr, px, py, v, 0.0)


@numba.njit(cache=True)
def adaptive_gamma(par, x, y, th, hx, hy):
    """Eq. 16-18: γ from the angular alignment exp(−k_θ |θ − ψ|) and the distance alignment
    max(0, 1 − d / d_th) (d: clearance between the two discs), between γ_min (risky) and γ_max."""
    rx, ry = hx - x, hy - y
    psi = math.atan2(ry, rx)
    a_theta = math.exp(-par[6] * abs(wrap(th - psi)))
    d = math.sqrt(rx * rx + ry * ry) - par[0]
    a_dist = max(0.0, 1.0 - d / par[9])
    risk = min(max(par[7] * a_theta + par[8] * a_dist, 0.0), 1.0)
    return par[5] - (par[5] - par[4]) * risk


@numba.njit(cache=True)
def human_prunes(kind, fv, flo, finv, fshape, fper, fstr, par, humans, parent, samples, n):
    """True when any of the ``n`` segment samples (last = the successor) violates a human pruner."""
    m, dt = par[2], par[3]
    for h in range(humans.shape[0]):
        hx, hy = humans[h, 0], humans[h, 1]
        for i in range(n):
            if human_value(fv, flo, finv, fshape, fper, fstr, par, samples[i, 0], samples[i, 1], samples[i, 2], samples[i, 3], hx, hy) < m:
                return True
        if kind == U_FI:
            s = samples[n - 1]
            v1 = human_value(fv, flo, finv, fshape, fper, fstr, par, s[0], s[1], s[2], s[3], hx, hy)
            v0 = human_value(fv, flo, finv, fshape, fper, fstr, par, parent[0], parent[1], parent[2], parent[3], hx, hy)
            gamma = adaptive_gamma(par, s[0], s[1], s[3], hx, hy)
            if (v1 - v0) / dt < -gamma * (v1 - m):
                return True
    return False


@numba.njit(cache=True)
def heuristic_batch(kind, f, par, states):
    fv, flo, finv, fshape, fper, fstr = f
    out = np.empty(states.shape[0])
    for i in range(states.shape[0]):
        out[i] = heuristic(kind, fv, flo, finv, fshape, fper, fstr, par, states[i, 0], states[i, 1], states[i, 2], states[i, 3])
    return out


@numba.njit(cache=True)
def static_prune_batch(kind, f, par, samples):
    """samples (N, S, 4): True for each of the N segments with any sample at or below the threshold."""
    fv, flo, finv, fshape, fper, fstr = f
    out = np.zeros(samples.shape[0], np.bool_)
    for i in range(samples.shape[0]):
        for j in range(samples.shape[1]):
            s = samples[i, j]
            if static_value(kind, fv, flo, finv, fshape, fper, fstr, par, s[0], s[1], s[2], s[3]) <= 0.0:
                out[i] = True
                break
    return out


@numba.njit(cache=True)
def static_value_batch(kind, f, par, states):
    fv, flo, finv, fshape, fper, fstr = f
    out = np.empty(states.shape[0])
    for i in range(states.shape[0]):
        out[i] = static_value(kind, fv, flo, finv, fshape, fper, fstr, par, states[i, 0], states[i, 1], states[i, 2], states[i, 3])
    return out


@numba.njit(cache=True)
def human_prune_batch(kind, f, par, humans, parents, samples):
    """parents (N, 4), samples (N, S, 4): True for each segment a human pruner drops."""
    fv, flo, finv, fshape, fper, fstr = f
    out = np.zeros(samples.shape[0], np.bool_)
    for i in range(samples.shape[0]):
        out[i] = human_prunes(kind, fv, flo, finv, fshape, fper, fstr, par, humans, parents[i], samples[i], samples.shape[1])
    return out


@numba.njit(cache=True)
def heuristic_loop(kind, f, par, states, calls):
    """``calls`` repeated evaluations of ``states`` inside compiled code (how the search pays for them):
    timed from Python in one call, it gives the per-state cost without the Python call overhead."""
    fv, flo, finv, fshape, fper, fstr = f
    total = 0.0
    for _ in range(calls):
        for i in range(states.shape[0]):
            total += heuristic(kind, fv, flo, finv, fshape, fper, fstr, par, states[i, 0], states[i, 1], states[i, 2], states[i, 3])
    return total


@numba.njit(cache=True)
def static_prune_loop(kind, f, par, samples, calls):
    """As ``heuristic_loop``, for the static pruner over (N, S, 4) segments; returns the pruned count."""
    fv, flo, finv, fshape, fper, fstr = f
    pruned = 0
    for _ in range(calls):
        for i in range(samples.shape[0]):
            for j in range(samples.shape[1]):
                s = samples[i, j]
                if static_value(kind, fv, flo, finv, fshape, fper, fstr, par, s[0], s[1], s[2], s[3]) <= 0.0:
                    pruned += 1
                    break
    return pruned
