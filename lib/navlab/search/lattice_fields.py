"""Compiled per-state look-ups the lattice search evaluates for every successor: heuristics, pruners, cost.

Why compiled and why here: the paper's Table VII times exactly these calls (35 heuristic states, 140
pruned states per expansion) and its BRT pruner cost 12.5 % of the search time; inside a numba loop a
4D multilinear look-up is a few dozen loads, with no Python call per state. The search layer only knows
*numbers*: a ``GridField`` (values on a regular grid) and a kind code. ``navlab.reach`` builds these from
its stored value functions (``hj.guidance``, ``hj.pruners``), so the dependency points downwards.

Heuristic kinds (``H_*``), all in seconds, evaluated at a successor state (x, y, v, θ):

- ``H_ZERO``: 0 (Dijkstra);
- ``H_DIST``: max(|p − goal| − tol, 0) / v_max (the paper's general Dist, admissible form);
- ``H_RASTER``: a 2D field over (x, y) (map-based Dist: obstacle-aware travel time);
- ``H_GOAL_GRID``: the general TTR grid in the goal frame (goal at the origin, heading relative to the
  goal heading); off the grid the admissible Euclidean bound of ``reach.lookup.TTRLookup``;
- ``H_ROOM_GRID``: a 4D grid in room coordinates (map-based TTR); off the grid ``par[5]``.

Pruner kinds, static (``S_*``) and human (``U_*``), each returns True where a segment must be dropped:

- ``S_OBS``: the conservative collision check (``swept_unsafe``): the path from the parent through the
  segment's samples may come within the robot radius of an obstacle (2D signed-distance field; par:
  [radius + field error, value off the grid, field error]);
- ``S_OBS_POINT``: the conventional instantaneous check the paper's OBS baseline performs: clearance <=
  radius at any of the segment's samples (same field and par as ``S_OBS``); the path between samples is
  not checked, so a plan may graze an obstacle, which the paper's dense feasibility check then catches;
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
S_NONE, S_OBS, S_BRT, S_OBS_POINT = 0, 1, 2, 3
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


# Why the look-ups read a field through ``field_meta`` and the hot ones are ``inline="always"``: profiling
# the search showed most of a look-up's time went to reference counting, not arithmetic: every call of
# a compiled function that takes arrays increments and decrements their counts (atomics), and a 4D
# look-up passed six arrays through five nested calls. Unpacking the field once per kernel into a tuple
# of scalars and inlining the functions that take arrays (values, par) into the loop that uses them
# leaves no array-passing call on the hot path; scalar-only helpers are left to LLVM's inliner (inlining
# everything at numba's level cost minutes of compile time for no measurable gain).


@numba.njit(cache=True, error_model="numpy")
def field_meta(f):
    """A ``GridField`` as (values, meta): meta = (ndim, lo, inv_spacing, shape, periodic, strides, hi),
    each a 4-tuple of scalars (axes beyond ``ndim`` padded), ``hi`` the last node's coordinate."""
    fv, flo, finv, fshape, fper, fstr = f
    d = flo.shape[0]
    lo = (flo[0], flo[1], flo[2] if d > 2 else 0.0, flo[3] if d > 3 else 0.0)
    inv = (finv[0], finv[1], finv[2] if d > 2 else 1.0, finv[3] if d > 3 else 1.0)
    n = (fshape[0], fshape[1], fshape[2] if d > 2 else 2, fshape[3] if d > 3 else 2)
    per = (fper[0], fper[1], fper[2] if d > 2 else False, fper[3] if d > 3 else False)
    st = (fstr[0], fstr[1], fstr[2] if d > 2 else 0, fstr[3] if d > 3 else 0)
    hi = (lo[0] + (n[0] - 1) / inv[0], lo[1] + (n[1] - 1) / inv[1], lo[2] + (n[2] - 1) / inv[2],
          lo[3] + (n[3] - 1) / inv[3])
    return fv, (d, lo, inv, n, per, st, hi)


@numba.njit(cache=True, inline="always", error_model="numpy")
def _axis(lo, inv, n, per, stride, x):
    """Lower corner offset, offset to the upper corner and fraction along one axis (periodic axes wrap,
    others clamp)."""
    x = (x - lo) * inv
    if per:
        i0 = math.floor(x)
        fr = x - i0
        if i0 >= n or i0 < 0:  # off the first period: the modulo (and its zero-division check) only here,
            i0 %= n  # where no loop can run away (a NaN or inf floors to INT64_MIN: a loop ran ~10^18 times)
        i1 = i0 + 1 if i0 + 1 < n else 0
    else:
        x = min(max(x, 0.0), n - 1.0)
        i0 = min(int(x), n - 2)
        fr = x - i0
        i1 = i0 + 1
    return i0 * stride, (i1 - i0) * stride, fr


@numba.njit(cache=True, inline="always", error_model="numpy")
def interp2(fv, m, p0, p1):
    """Bilinear interpolant of a 2D field (values ``fv``, ``m`` from ``field_meta``) at (p0, p1)."""
    _, lo, inv, n, per, st, _ = m
    v = fv
    b0, o0, t0 = _axis(lo[0], inv[0], n[0], per[0], st[0], p0)
    b1, o1, t1 = _axis(lo[1], inv[1], n[1], per[1], st[1], p1)
    i = b0 + b1
    return (1 - t0) * ((1 - t1) * v[i] + t1 * v[i + o1]) + t0 * ((1 - t1) * v[i + o0] + t1 * v[i + o0 + o1])


@numba.njit(cache=True, inline="always", error_model="numpy")
def interp3(fv, m, p0, p1, p2):
    """Trilinear interpolant of a 3D field at (p0, p1, p2)."""
    _, lo, inv, n, per, st, _ = m
    v = fv
    b0, o0, t0 = _axis(lo[0], inv[0], n[0], per[0], st[0], p0)
    b1, o1, t1 = _axis(lo[1], inv[1], n[1], per[1], st[1], p1)
    b2, o2, t2 = _axis(lo[2], inv[2], n[2], per[2], st[2], p2)
    i = b0 + b1 + b2
    a = (1 - t0) * ((1 - t1) * v[i] + t1 * v[i + o1]) + t0 * ((1 - t1) * v[i + o0] + t1 * v[i + o0 + o1])
    i += o2
    b = (1 - t0) * ((1 - t1) * v[i] + t1 * v[i + o1]) + t0 * ((1 - t1) * v[i + o0] + t1 * v[i + o0 + o1])
    return (1 - t2) * a + t2 * b


@numba.njit(cache=True, inline="always", error_model="numpy")
def interp4(fv, m, p0, p1, p2, p3):
    """Quadrilinear interpolant of a 4D field at (p0, ..., p3). Each dimension has its own function
    (the kind of a heuristic or pruner fixes it): no branch on the dimension in the hot loop."""
    _, lo, inv, n, per, st, _ = m
    v = fv
    b0, o0, t0 = _axis(lo[0], inv[0], n[0], per[0], st[0], p0)
    b1, o1, t1 = _axis(lo[1], inv[1], n[1], per[1], st[1], p1)
    b2, o2, t2 = _axis(lo[2], inv[2], n[2], per[2], st[2], p2)
    b3, o3, t3 = _axis(lo[3], inv[3], n[3], per[3], st[3], p3)
    i = b0 + b1 + b2 + b3
    a = (1 - t0) * ((1 - t1) * v[i] + t1 * v[i + o1]) + t0 * ((1 - t1) * v[i + o0] + t1 * v[i + o0 + o1])
    j = i + o2
    b = (1 - t0) * ((1 - t1) * v[j] + t1 * v[j + o1]) + t0 * ((1 - t1) * v[j + o0] + t1 * v[j + o0 + o1])
    lo3 = (1 - t2) * a + t2 * b
    j = i + o3
    a = (1 - t0) * ((1 - t1) * v[j] + t1 * v[j + o1]) + t0 * ((1 - t1) * v[j + o0] + t1 * v[j + o0 + o1])
    j += o2
    b = (1 - t0) * ((1 - t1) * v[j] + t1 * v[j + o1]) + t0 * ((1 - t1) * v[j + o0] + t1 * v[j + o0 + o1])
    return (1 - t3) * lo3 + t3 * ((1 - t2) * a + t2 * b)


@numba.njit(cache=True, inline="always", error_model="numpy")
def cell_index(m, p0, p1, p2, p3):
    """Flat index of the lower corner of the grid cell holding (p0, ..., p_{d-1}), the cell ``interp`` uses."""
    d, lo, inv, n, per, st, _ = m
    i = _axis(lo[0], inv[0], n[0], per[0], st[0], p0)[0] + _axis(lo[1], inv[1], n[1], per[1], st[1], p1)[0]
    if d > 2:
        i += _axis(lo[2], inv[2], n[2], per[2], st[2], p2)[0]
    if d > 3:
        i += _axis(lo[3], inv[3], n[3], per[3], st[3], p3)[0]
    return i


def cell_min(field: GridField) -> np.ndarray:
    """The smallest of the 2^d corner values of every grid cell, at its lower corner's flat index.

    Why: a multilinear interpolant is a convex combination of its cell's corners, so it is at least
    their minimum. A pruner that only asks "is V above the threshold?" answers from one load wherever
    the whole cell is above it (most of free space) and interpolates only in cells that straddle the
    threshold; its decisions are exactly those of the full interpolant.
    """
    shape = tuple(int(n) for n in field.shape)
    low = np.asarray(field.values).reshape(shape)
    for axis, periodic in enumerate(field.periodic):
        upper = np.roll(low, -1, axis=axis)
        if not periodic:  # the last node is never a lower corner (interp clamps to n - 2)
            edge = [slice(None)] * len(shape)
            edge[axis] = -1
            upper[tuple(edge)] = low[tuple(edge)]
        low = np.minimum(low, upper)
    return np.ascontiguousarray(low.reshape(-1))


@numba.njit(cache=True, inline="always", error_model="numpy")
def _outside_xy(m, x, y):
    hi = m[6]
    lo = m[1]
    return x < lo[0] or y < lo[1] or x > hi[0] or y > hi[1]


@numba.njit(cache=True, inline="always", error_model="numpy")
def wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


@numba.njit(cache=True, inline="always", error_model="numpy")
def heuristic(kind, fv, m, par, x, y, v, th):
    """par: [goal_x, goal_y, goal_heading, v_max, tolerance_or_goal_radius, off_grid_value, cos(goal_heading),
    sin(goal_heading)]."""
    out = 0.0
    dx, dy = x - par[0], y - par[1]
    if kind == H_DIST:
        out = max(math.sqrt(dx * dx + dy * dy) - par[4], 0.0) / par[3]
    elif kind == H_RASTER:
        out = interp2(fv, m, x, y)
    elif kind == H_GOAL_GRID:
        c, s = par[6], par[7]  # cos, sin of the goal heading
        lx, ly = c * dx + s * dy, -s * dx + c * dy
        if _outside_xy(m, lx, ly):
            out = max(math.sqrt(lx * lx + ly * ly) - par[4], 0.0) / par[3]
        else:
            out = interp4(fv, m, lx, ly, v, wrap(th - par[2]))
    elif kind == H_ROOM_GRID:
        out = par[5] if _outside_xy(m, x, y) else interp4(fv, m, x, y, v, th)
    return out  # H_ZERO: 0


@numba.njit(cache=True, inline="always", error_model="numpy")
def static_value(kind, fv, m, par, x, y, v, th):
    """The static pruner's safety value at one state: clearance (S_OBS, S_OBS_POINT) or BRT value (S_BRT),
    minus margin.

    par: [robot_radius (S_OBS, S_OBS_POINT) or margin (S_BRT), value off the grid]. Positive is safe.
    """
    if _outside_xy(m, x, y):
        out = par[1]
    elif kind == S_OBS or kind == S_OBS_POINT:
        out = interp2(fv, m, x, y)
    else:
        out = interp4(fv, m, x, y, v, th)
    return out - par[0]


@numba.njit(cache=True, inline="always", error_model="numpy")
def first_unsafe(kind, fv, fmin, m, par, samples, i, n):
    """Index of the first of the ``n`` states of segment ``i`` of ``samples`` (N, S, 4) with
    ``static_value <= 0``, or -1.

    Answered from the cell's corner minimum (``cell_min``) where that suffices and interpolated only in
    cells that straddle the threshold. Why one call per segment, indexed rather than sliced, with the
    per-state test written out here: every array handed to an inlined function (or sliced) costs an
    atomic reference-count pair; checked per state through such a function, the common one-load answer
    took ~60 ns instead of ~11 (measured; ~24 ns with this per-segment call).
    """
    thr, off_grid = par[0], par[1]
    for j in range(n):
        x, y, v, th = samples[i, j, 0], samples[i, j, 1], samples[i, j, 2], samples[i, j, 3]
        if _outside_xy(m, x, y):
            if off_grid - thr <= 0.0:
                return j
        elif fmin[cell_index(m, x, y, v, th)] - thr <= 0.0 and static_value(kind, fv, m, par, x, y, v, th) <= 0.0:
            return j
    return -1


@numba.njit(cache=True, inline="always", error_model="numpy")
def obs_clearance(fv, m, par, x, y):
    """The OBS field's value at (x, y) minus its threshold (off the grid: ``par[1]`` minus it)."""
    return par[1] - par[0] if _outside_xy(m, x, y) else interp2(fv, m, x, y) - par[0]


@numba.njit(cache=True, inline="always", error_model="numpy")
def chord_clearance(da, db, c):
    """A lower bound on the obstacle distance along the straight segment from a to b (length ``c``) when
    only lower bounds ``da``, ``db`` on it at a and b are known.

    No obstacle point lies inside B(a, da) or B(b, db), so the bound is the distance from the segment to
    the outside of their union: where the two circles cross, sqrt(da² − t²) with t the crossing's foot on
    the segment; beyond an end, that end's disc (or the larger disc's rim) decides. It is attained by a
    point obstacle at the crossing, so no bound from da, db and c alone is larger; the 1-Lipschitz bound
    (da + db − c) / 2 is smaller by up to half the chord (6 cm of a 12.5 cm step at 1 m/s).
    """
    if da <= 0.0 or db <= 0.0 or c >= da + db:  # the discs leave the chord open: the 1-Lipschitz bound,
        return 0.5 * (da + db - c)  # which stays a lower bound on a signed distance (0 would not be one)
    if c <= 1e-12:
        return min(da, db)
    t = (da * da - db * db + c * c) / (2.0 * c)
    if t >= c:
        return max(db, da - c)
    if t <= 0.0:
        return max(da, db - c)
    return math.sqrt(da * da - t * t)


@numba.njit(cache=True, inline="always", error_model="numpy")
def _interval_clear(q_prev, q, length, rho, a, b, cusp):
    """One interval between two samples ``a`` and ``b`` (x, y, θ), given the clearance lower bounds ``q``
    (minus the threshold) at its ends: clear by the 1-Lipschitz bound over any path of ``length``, or by
    ``chord_clearance`` less the path's offset from its chord. Within a primitive the turn rate is
    constant, so the path between two samples is convex with total turning ``turn``: it lies in the
    triangle of the chord and the end tangents, at most (c / 2) tan(turn / 2) from the chord (taken only
    for turns < 1 rad). The chord and the turn are computed only where the Lipschitz bound does not decide.
    A ``cusp`` (the speed changes sign: the car stops and drives back) leaves that triangle: the Lipschitz
    bound alone decides."""
    if q_prev + q > length:
        return True
    turn = abs((b[2] - a[2] + math.pi) % (2.0 * math.pi) - math.pi)
    if cusp or turn >= 1.0:
        return False
    c = math.hypot(b[0] - a[0], b[1] - a[1])
    return chord_clearance(q_prev + rho, q + rho, c) - 0.5 * c * math.tan(0.5 * turn) > rho


@numba.njit(cache=True, inline="always", error_model="numpy")
def swept_unsafe(fv, fmin, m, par, q0, parent, step, samples, i, n):
    """Index of the first of the ``n`` samples of segment ``i`` whose path from the previous sample may
    come within the robot's radius of an obstacle, or -1: the conservative collision check of S_OBS.

    ``q0``: the parent's clearance lower bound (``obs_clearance``); ``parent``: its state (x, y, v, θ);
    ``step``: the time between samples. Why it is conservative: the field's threshold ``par[0]`` is the
    required clearance ρ (robot radius, plus any pose allowance) plus ``par[2]``, a bound on the field's
    interpolation error (``hj.pruners.obs_pruner``), so q = value − threshold is a lower bound on the true
    distance minus ρ at each sample. Between two samples the path is kept clear when either (a) q_a + q_b
    > L, L ≤ step · max(|v_a|, |v_b|) its arc length (the speed is linear in time over a primitive, so
    |v| is at most its larger end; a reversing car's v < 0 counts by its magnitude): the true
    distance d is 1-Lipschitz, so d(p) ≥ (d(a) + d(b) − L) / 2 on any path; or (b) the straight chord is
    ``chord_clearance`` from the obstacles and the path within its offset bound of the chord
    (``_interval_clear``). Each q is the cell's corner minimum (``cell_min``) when that already decides
    both of its intervals by (a), else the interpolant, so the decisions are those of the interpolant.
    """
    rho = par[0] - par[2]
    q_prev, v_prev, exact_prev = q0, parent[2], True
    px, py, pth = parent[0], parent[1], parent[3]
    for j in range(n):
        x, y, v, th = samples[i, j, 0], samples[i, j, 1], samples[i, j, 2], samples[i, j, 3]
        v_next = samples[i, j + 1, 2] if j + 1 < n else v
        length = step * max(abs(v_prev), abs(v))
        exact, cusp = True, v_prev * v < 0.0
        if _outside_xy(m, x, y):
            q = par[1] - par[0]
        else:
            q = fmin[cell_index(m, x, y, 0.0, 0.0)] - par[0]
            if q > 0.5 * step * max(abs(v_prev), abs(v), abs(v_next)):
                exact = False  # clears both its intervals: a lower bound is enough
            else:
                q = interp2(fv, m, x, y) - par[0]
        if not _interval_clear(q_prev, q, length, rho, (px, py, pth), (x, y, th), cusp):
            if not exact_prev:  # the bound was not enough after all: the interpolant decides
                q_prev = obs_clearance(fv, m, par, px, py)
            if not exact:
                q, exact = obs_clearance(fv, m, par, x, y), True
            if not _interval_clear(q_prev, q, length, rho, (px, py, pth), (x, y, th), cusp):
                return j
        q_prev, v_prev, exact_prev, px, py, pth = q, v, exact, x, y, th
    return -1


@numba.njit(cache=True, inline="always", error_model="numpy")
def _human_value_cs(fv, m, par, x, y, v, c, s, hx, hy):
    """``human_value`` with the cosine and sine of the robot's heading given: a segment's sample is
    checked against every human, and the trigonometry is the same for all of them."""
    rx, ry = hx - x, hy - y
    px, py = c * rx + s * ry, -s * rx + c * ry
    if _outside_xy(m, px, py):
        return math.sqrt(px * px + py * py) - par[0] - par[1]
    return interp3(fv, m, px, py, v)


@numba.njit(cache=True, error_model="numpy")
def human_value(fv, m, par, x, y, v, th, hx, hy):
    """Human-robot BRT value for a robot state and a human position (reach.lookup.HumanBRTLookup).

    par: [collision_radius, closing_distance (speed sum × horizon), m, Δt, γ_min, γ_max, k_θ, w_θ, w_d, d_th,
    prediction horizon (human_prunes)].
    """
    return _human_value_cs(fv, m, par, x, y, v, math.cos(th), math.sin(th), hx, hy)


@numba.njit(cache=True, error_model="numpy")
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


@numba.njit(cache=True, error_model="numpy")
def human_values_at(fv, m, par, humans, x, y, v, th, t0, out):
    """``out[h]``: the human BRT value of the state (x, y, v, θ), ``t0`` s after the observation, against
    human h where it walks by then (held after ``par[10]`` s). The FI rule's V at a parent, which is the
    same for all its successors: the search computes it once per expansion."""
    t = min(t0, par[10])
    c, s = math.cos(th), math.sin(th)
    for h in range(humans.shape[0]):
        out[h] = _human_value_cs(fv, m, par, x, y, v, c, s, humans[h, 0] + humans[h, 2] * t,
                                 humans[h, 1] + humans[h, 3] * t)
    return out


@numba.njit(cache=True, error_model="numpy")
def human_prunes(kind, fv, m, par, humans, parent_values, t0, duration, samples, n):
    """True when any of the ``n`` segment samples (last = the successor) of a parent violates a human pruner.

    humans: (H, 4) observed x, y, vx, vy. The parent is ``t0`` s after the observation and sample i at
    t0 + (i + 1)·duration/n; each is checked against the human where it walks by then at its observed
    velocity, the prediction held after ``par[10]`` s (0: the humans frozen where they were seen).
    ``parent_values``: the parent's values against each human (``human_values_at``), which the FI rule
    (Eq. 15) compares with the successor's. The answer is an OR of independent tests, so they are taken
    sample by sample (each sample's trigonometry once for all humans), then the FI rule per human."""
    margin, dt, horizon = par[2], par[3], par[10]
    c, s = 1.0, 0.0
    for i in range(n):
        x, y, v, th = samples[i, 0], samples[i, 1], samples[i, 2], samples[i, 3]
        c, s = math.cos(th), math.sin(th)
        t = min(t0 + (i + 1) * duration / n, horizon)
        for h in range(humans.shape[0]):
            hx, hy = humans[h, 0] + humans[h, 2] * t, humans[h, 1] + humans[h, 3] * t
            if _human_value_cs(fv, m, par, x, y, v, c, s, hx, hy) < margin:
                return True
    if kind == U_FI:
        x, y, v, th = samples[n - 1, 0], samples[n - 1, 1], samples[n - 1, 2], samples[n - 1, 3]
        t = min(t0 + duration, horizon)
        # γ >= 0 for every risk in [0, 1] (rounding included) when 0 <= γ_min <= γ_max; then a step that does
        # not lower V from above the margin satisfies Eq. 15 whatever γ is, and γ's atan2 and exp are skipped
        gamma_free = dt > 0.0 and par[4] >= 0.0 and par[5] >= par[4]
        for h in range(humans.shape[0]):
            hx, hy = humans[h, 0] + humans[h, 2] * t, humans[h, 1] + humans[h, 3] * t
            val1 = _human_value_cs(fv, m, par, x, y, v, c, s, hx, hy)  # c, s: the last sample's
            if gamma_free and val1 >= parent_values[h] and val1 >= margin:
                continue
            gamma = adaptive_gamma(par, x, y, th, hx, hy)
            if (val1 - parent_values[h]) / dt < -gamma * (val1 - margin):
                return True
    return False


@numba.njit(cache=True, error_model="numpy")
def heuristic_batch(kind, f, par, states):
    fv, m = field_meta(f)
    out = np.empty(states.shape[0])
    for i in range(states.shape[0]):
        out[i] = heuristic(kind, fv, m, par, states[i, 0], states[i, 1], states[i, 2], states[i, 3])
    return out


@numba.njit(cache=True, error_model="numpy")
def static_prune_batch(kind, f, fmin, par, samples):
    """samples (N, S, 4): True for each of the N segments with any sample at or below the threshold."""
    fv, m = field_meta(f)
    out = np.zeros(samples.shape[0], np.bool_)
    for i in range(samples.shape[0]):
        out[i] = first_unsafe(kind, fv, fmin, m, par, samples, i, samples.shape[1]) >= 0
    return out


@numba.njit(cache=True, error_model="numpy")
def swept_prune_batch(f, fmin, par, parents, samples, steps):
    """parents (N, 4), samples (N, S, 4), steps (N,) (time between samples): True for each segment whose
    path from its parent through its samples fails ``swept_unsafe``."""
    fv, m = field_meta(f)
    out = np.zeros(samples.shape[0], np.bool_)
    for i in range(samples.shape[0]):
        q0 = obs_clearance(fv, m, par, parents[i, 0], parents[i, 1])
        out[i] = q0 <= 0.0 or swept_unsafe(fv, fmin, m, par, q0, parents[i], steps[i], samples, i,
                                            samples.shape[1]) >= 0
    return out


@numba.njit(cache=True, error_model="numpy")
def static_value_batch(kind, f, par, states):
    fv, m = field_meta(f)
    out = np.empty(states.shape[0])
    for i in range(states.shape[0]):
        out[i] = static_value(kind, fv, m, par, states[i, 0], states[i, 1], states[i, 2], states[i, 3])
    return out


@numba.njit(cache=True, error_model="numpy")
def human_prune_batch(kind, f, par, humans, parents, samples, t0, durations):
    """parents (N, 4), samples (N, S, 4), their times t0 (N,) and durations (N,): True for each segment a
    human pruner drops."""
    fv, m = field_meta(f)
    out = np.zeros(samples.shape[0], np.bool_)
    at_parent = np.empty(humans.shape[0])
    for i in range(samples.shape[0]):
        if kind == U_FI:  # only the FI rule reads the parent's values
            p = parents[i]
            human_values_at(fv, m, par, humans, p[0], p[1], p[2], p[3], t0[i], at_parent)
        out[i] = human_prunes(kind, fv, m, par, humans, at_parent, t0[i], durations[i], samples[i],
                              samples.shape[1])
    return out


@numba.njit(cache=True, error_model="numpy")
def heuristic_loop(kind, f, par, states, calls):
    """``calls`` repeated evaluations of ``states`` inside compiled code (how the search pays for them):
    timed from Python in one call, it gives the per-state cost without the Python call overhead.
    Returns the sum of h (kept so the work cannot be optimised away)."""
    fv, m = field_meta(f)
    total = 0.0
    for _ in range(calls):
        for i in range(states.shape[0]):
            total += heuristic(kind, fv, m, par, states[i, 0], states[i, 1], states[i, 2], states[i, 3])
    return total


@numba.njit(cache=True, error_model="numpy")
def static_prune_loop(kind, f, fmin, par, samples, calls):
    """As ``heuristic_loop``, for the static pruner over (N, S, 4) segments, stopping per segment at the
    first failing sample as the search does: (segments pruned, samples evaluated) over all calls."""
    fv, m = field_meta(f)
    pruned = 0
    evaluated = 0
    for _ in range(calls):
        for i in range(samples.shape[0]):
            j = first_unsafe(kind, fv, fmin, m, par, samples, i, samples.shape[1])
            pruned += j >= 0
            evaluated += j + 1 if j >= 0 else samples.shape[1]
    return pruned, evaluated
