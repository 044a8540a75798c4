r"""A true state lattice for the HJ-search paper's 4D car, where A* is exact (issue 26, item 2).

Why: the paper's search (``lattice_search``, ``dubins_lattice``) integrates controls from continuous
states and keeps one representative per (x, y, v, θ) cell (Nav2 Smac's hybrid-A* duplicate detection),
so its optimum depends on which representative the expansion order kept: A* with the Dist and the TTR
heuristic can return different "optimal" costs (Table I). Here every state lies *on* the lattice and
every motion primitive ends *exactly* on a lattice state, as in SBPL's ``xytheta`` lattice (Likhachev &
Ferguson, IJRR 2009) and Nav2 Smac's state-lattice planner: the search graph is fixed, so A* with any
admissible heuristic returns Dijkstra's cost on it (up to floating-point rounding of path sums, ~1e-14 s).

- **States**: (i, j, k, s): position (x0 + i·cell, y0 + j·cell) (the lattice is anchored at the start),
  heading index k of the 16 grid-aligned directions atan2 of (1,0), (2,1), (1,1), (1,2), ... (SBPL's and
  Smac's lattice generator's choice: a straight move along them lands on a cell), speed level s.
- **Primitives** (``build_primitives``): for a start heading k0, start speed v0, end heading k0 + Δ
  (|Δ| <= ``turn_steps``) and end speed v1, the shortest path to a lattice cell that is a straight line
  (Δ = 0) or an arc tangent to the start line joined to a straight line (Smac's generator: the two
  heading lines meet at I; the arc's tangent length is min(|I|, |P − I|), the rest is straight), with
  the constant acceleration (v1² − v0²) / 2L within [accel_min, accel_max] and curvature κ·v <= ω_max at
  the fastest speed on the arc (v² is linear in arc length, so that is one of the arc's ends); cost = its
  duration 2L / (v0 + v1). At rest (v0 = v1 = 0) a turn in place by one heading step at ω_max (θ̇ = ω
  needs no speed in the paper's model; the continuous lattice uses it too). They
  are solved for the start headings 0, 1, 2 (0°, 26.6°, 45°) and mapped to the other 13 by the grid's
  symmetries (rotations by 90°, reflections), which map the heading set onto itself. A car that reverses
  (``Car.v_min < 0``; the paper's Sec. VII-A and Fig. 6 show reversals) also drives every forward
  primitive backwards: speeds −v0 → −v1, both headings turned by 180° (the path is the one a car facing
  the other way drives forwards), kept where its acceleration, the forward one's negated, is in bounds.
- **Collision** (the paper's OBS test, conservative): a primitive's points, equally spaced in arc length
  (spacing <= ``sample_m``, start and end included), must each have interpolated clearance > robot
  radius + the raster's interpolation error bound + half the spacing. Every point of the path is within
  half a spacing (of arc, hence of distance) of a sample and the distance is 1-Lipschitz, so the whole
  swept disc path clears the obstacles by more than the robot radius.
- **Search** (``Lattice.search``): compiled A* (re-opening states whose g improves, so an admissible but
  inconsistent heuristic, such as an interpolated TTR grid, still returns the optimum) over lattice
  states with h given as a function of (N, 4) continuous states (x, y, v, θ) in seconds, evaluated once
  for every lattice state (and set to 0 on goal states); h = 0 is Dijkstra. The goal: a state within ``tolerance`` of the goal xy at a
  |speed| <= ``max_speed`` (reversing too), tested when popped. ``Lattice.cost_to_go`` runs Dijkstra backwards from the
  goal set over the whole lattice: the exact cost-to-go, against which a heuristic's admissibility is
  measured (``excess``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numba
import numpy as np

from navlab.search.heap import insert_or_decrease, new_indexed, pop_top
from navlab.search.lattice_fields import GridField, _outside_xy, field_meta, interp2, wrap
from navlab.search.lattice_search import Goal

# the 16 grid-aligned headings: (1,0), (2,1), (1,1), (1,2) and their rotations by 90°, counter-clockwise
_QUARTER = np.array([[1, 0], [2, 1], [1, 1], [1, 2]])
HEADINGS = np.concatenate([_QUARTER @ np.linalg.matrix_power(np.array([[0, 1], [-1, 0]]), r) for r in range(4)])
ANGLES = np.arctan2(HEADINGS[:, 1], HEADINGS[:, 0])
K = len(HEADINGS)
BASE = (0, 1, 2)  # the start headings primitives are solved for; the others are their images
# the grid's symmetry group D4 as integer matrices acting on column vectors (x, y)
D4 = tuple(np.array(m) for m in ([[1, 0], [0, 1]], [[0, -1], [1, 0]], [[-1, 0], [0, -1]], [[0, 1], [-1, 0]],
                                  [[1, 0], [0, -1]], [[0, 1], [1, 0]], [[-1, 0], [0, 1]], [[0, -1], [-1, 0]]))
MIRROR = {0: D4[4], 2: D4[5]}  # the reflection fixing base heading 0 (x axis) and 2 (the diagonal)


def heading_index(vector) -> int:
    """Index of the heading whose integer direction is ``vector`` (a D4 image of one of them)."""
    hit = np.flatnonzero((HEADINGS == np.asarray(vector)).all(axis=1))
    if len(hit) != 1:
        raise ValueError(f"{tuple(vector)} is not one of the lattice's heading directions")
    return int(hit[0])


@dataclass(frozen=True)
class Car:
    """The paper's 4D car (hj.grids.robot): ẋ = v cos θ, ẏ = v sin θ, θ̇ = ω, v̇ = a, v ∈ [v_min, v_max]
    (v_min < 0: it reverses; 0: forward only)."""

    v_max: float
    accel_min: float
    accel_max: float
    omega_max: float
    v_min: float = 0.0

    @classmethod
    def from_params(cls, params) -> Car:
        r = params.hj.grids.robot
        return cls(r.v_max, r.accel_min, r.accel_max, r.omega_max, r.v_min)


@dataclass(frozen=True)
class LatticeSettings:
    """The lattice's resolution: cell size, speed levels (increasing, 0 among them; default every
    0.25 m/s from the car's v_min to its v_max), how far a primitive may turn (heading steps of 22.5° or
    26.6°/18.4°) and reach (cells), and the collision sample spacing. A negative level's magnitude must be
    a level too: reverse primitives are the forward ones driven backwards."""

    car: Car
    cell_m: float = 0.1
    speeds: tuple[float, ...] | None = None
    turn_steps: int = 2
    reach_cells: int = 16
    sample_m: float = 0.05

    def __post_init__(self):
        if self.speeds is None:
            levels = range(math.ceil(self.car.v_min / 0.25 - 1e-9), math.floor(self.car.v_max / 0.25 + 1e-9) + 1)
            object.__setattr__(self, "speeds", tuple(0.25 * k for k in levels))
        v = np.asarray(self.speeds, float)
        if (0.0 not in v or (np.diff(v) <= 0).any() or v[0] < self.car.v_min or v[-1] > self.car.v_max
                or not np.isin(-v[v < 0], v).all()):
            raise ValueError(f"speeds {self.speeds}: increasing, 0 among them, within [v_min, v_max] = "
                             f"[{self.car.v_min}, {self.car.v_max}], each negative one's magnitude a level too")


class Primitives(NamedTuple):
    """All primitives, sorted by start class k0 · S + s0 (``start_off``: CSR offsets), with their geometry
    (``theta0``, a first straight ``straight1``, an arc of ``radius`` turning ``turn`` rad, a last straight
    ``straight2``), speeds, lattice displacement (di, dj) and end class, duration ``cost`` and collision
    samples ``samples`` (rows ``sample_off[p]:sample_off[p + 1]``: x, y relative to the start point, v, θ, t)."""

    k0: np.ndarray
    s0: np.ndarray
    k1: np.ndarray
    s1: np.ndarray
    di: np.ndarray
    dj: np.ndarray
    geometry: np.ndarray  # (P, 5): theta0 (the direction of motion: reversing, k0's opposite), straight1, radius, turn, straight2
    speeds: np.ndarray  # (P, 2): v0, v1 (both <= 0 reversing)
    cost: np.ndarray
    gap: np.ndarray  # half the arc length between consecutive samples
    start_off: np.ndarray
    sample_off: np.ndarray
    samples: np.ndarray

    @property
    def length(self) -> np.ndarray:
        g = self.geometry
        return g[:, 1] + g[:, 2] * np.abs(g[:, 3]) + g[:, 4]


def sample_paths(geometry: np.ndarray, speeds: np.ndarray, counts: np.ndarray, omega_max: float) -> np.ndarray:
    """``counts[p]`` + 1 points equally spaced in arc length along each primitive p (start and end
    included), in one vectorised pass: (Σ (counts + 1), 5) rows x, y (from the start point), v, θ, t.

    Along the arc the position is C + Rσ(sin θ(u), −cos θ(u)) about the centre C, σ the turn's sign;
    the speed follows v(s)² = v0² + 2as (constant acceleration a = (v1² − v0²) / 2L), so
    t(s) = (v(s) − v0) / a (s / v0 at a = 0). A turn in place (L = 0) turns at ``omega_max``."""
    th0, st1, rad, turn, st2 = geometry.T
    arc = rad * np.abs(turn)
    length = st1 + arc + st2
    p = np.repeat(np.arange(len(geometry)), counts + 1)
    k = np.arange(len(p)) - np.repeat(np.cumsum(counts + 1) - (counts + 1), counts + 1)
    frac = k / counts[p]
    s = length[p] * frac
    u1 = np.minimum(s, st1[p])
    u2 = np.clip(s - st1[p], 0.0, arc[p])
    u3 = np.clip(s - st1[p] - arc[p], 0.0, st2[p])
    sign, r, a0 = np.sign(turn[p]), rad[p], th0[p]
    spin = length[p] == 0.0  # a turn in place at rest, at the largest turn rate
    theta = a0 + np.where(spin, turn[p] * frac, np.divide(sign * u2, r, out=np.zeros_like(u2), where=r > 0))
    end = th0[p] + turn[p]
    x = u1 * np.cos(a0) + sign * r * (np.sin(theta) - np.sin(a0)) + u3 * np.cos(end)
    y = u1 * np.sin(a0) - sign * r * (np.cos(theta) - np.cos(a0)) + u3 * np.sin(end)
    v0, v1 = speeds[p, 0], speeds[p, 1]
    acc = np.divide(v1 ** 2 - v0 ** 2, 2.0 * length[p], out=np.zeros_like(s), where=~spin)
    v = np.sqrt(v0 ** 2 * (1.0 - frac) + v1 ** 2 * frac)  # = v0² + 2as, exactly v1 at the end
    moving = np.abs(acc) > 1e-12
    t = np.where(moving, (v - v0) / np.where(moving, acc, 1.0), s / np.where(moving | spin, 1.0, v0))
    t = np.where(spin, frac * np.abs(turn[p]) / omega_max, t)
    return np.stack([x, y, v, wrap(theta), t], axis=1)


def _tangent_paths(k0: int, delta: int, cells: np.ndarray, cell_m: float):
    """Straight-arc-straight paths from heading k0 at the origin to each of ``cells`` (N, 2) with heading
    k0 + Δ (Smac's construction): (geometry (N, 5), valid (N,)). Δ = 0: straight along the heading only."""
    th0 = ANGLES[k0]
    turn = float(wrap(ANGLES[(k0 + delta) % K] - th0))
    p = cells * cell_m
    d0 = np.array([math.cos(th0), math.sin(th0)])
    geometry = np.zeros((len(cells), 5))
    geometry[:, 0] = th0
    if delta == 0:
        along = p @ d0
        valid = (np.abs(p @ np.array([-d0[1], d0[0]])) < 1e-9) & (along > 0)
        geometry[:, 1] = along
        return geometry, valid
    d1 = np.array([math.cos(th0 + turn), math.sin(th0 + turn)])
    det = d0[0] * d1[1] - d0[1] * d1[0]
    a = (p[:, 0] * d1[1] - p[:, 1] * d1[0]) / det  # P = a·d0 + b·d1: start to I, I to P
    b = (d0[0] * p[:, 1] - d0[1] * p[:, 0]) / det
    tangent = np.minimum(a, b)
    geometry[:, 1] = np.maximum(a - b, 0.0)
    geometry[:, 2] = tangent / math.tan(abs(turn) / 2)
    geometry[:, 3] = turn
    geometry[:, 4] = np.maximum(b - a, 0.0)
    return geometry, tangent > 1e-9


def _base_primitives(settings: LatticeSettings, k0: int, deltas) -> list[tuple]:
    """For start heading k0 and each Δ, v0, v1: the shortest feasible path (a lattice cell, see the
    module docstring) as (k1, s0, s1, di, dj, geometry row)."""
    car, v = settings.car, np.asarray(settings.speeds, float)
    forward = np.flatnonzero(v >= 0.0)
    r = settings.reach_cells
    grid = np.stack(np.meshgrid(np.arange(-r, r + 1), np.arange(-r, r + 1), indexing="ij"), -1).reshape(-1, 2)
    out = []
    for delta in deltas:
        geometry, valid = _tangent_paths(k0, delta, grid, settings.cell_m)
        arc = geometry[:, 2] * np.abs(geometry[:, 3])
        length = np.where(valid, geometry[:, 1] + arc + geometry[:, 4], np.inf)
        for s0, v0 in zip(forward, v[forward], strict=True):
            for s1, v1 in zip(forward, v[forward], strict=True):
                if v0 + v1 == 0.0:  # at rest: a turn in place by one heading step (θ̇ = ω needs no speed)
                    if abs(delta) == 1:
                        out.append(((k0 + delta) % K, s0, s1, 0, 0, np.array([ANGLES[k0], 0, 0, geometry[0, 3], 0])))
                    continue
                need = max((v1 ** 2 - v0 ** 2) / (2 * car.accel_max), (v0 ** 2 - v1 ** 2) / (2 * -car.accel_min))
                # the fastest speed on the arc (v² is linear in arc length): κ · v <= ω_max there
                acc = (v1 ** 2 - v0 ** 2) / (2 * length)
                v_arc = np.sqrt(np.maximum(v0 ** 2 + 2 * acc * geometry[:, 1], v0 ** 2 + 2 * acc * (geometry[:, 1] + arc)))
                ok = valid & (length >= need - 1e-12) & ((geometry[:, 2] * car.omega_max >= v_arc - 1e-12) | (delta == 0))
                if not ok.any():
                    continue
                best = np.flatnonzero(ok)[np.lexsort((grid[ok, 1], grid[ok, 0], np.round(length[ok], 9)))[0]]
                out.append(((k0 + delta) % K, s0, s1, *grid[best], geometry[best]))
    return out


def _transform(prim: tuple, m: np.ndarray) -> tuple:
    """A base primitive (k0, k1, s0, s1, di, dj, geometry) under the grid symmetry ``m``: headings and
    displacement mapped, the arc's turn reversed by a reflection (det m = −1)."""
    k0, k1, s0, s1, di, dj, geometry = prim
    k0m, k1m = heading_index(m @ HEADINGS[k0]), heading_index(m @ HEADINGS[k1])
    g = geometry.copy()
    g[0] = ANGLES[k0m]
    g[3] *= round(np.linalg.det(m))
    return (k0m, k1m, s0, s1, *(m @ np.array([di, dj])), g)


def _reversed(prims: list[tuple], settings: LatticeSettings) -> list[tuple]:
    """The forward primitives (k0, k1, s0, s1, di, dj, geometry) driven backwards (see the module docstring):
    headings turned by 180°, speeds negated, where both negated speeds are levels and the acceleration
    (the forward one's, negated) lies within the car's bounds. The geometry stays the path's own (theta0:
    the direction of motion); ``build_primitives`` turns the samples' headings."""
    speeds, car = np.asarray(settings.speeds, float), settings.car
    out = []
    for k0, k1, s0, s1, di, dj, g in prims:
        v0, v1 = speeds[s0], speeds[s1]
        r0, r1 = np.flatnonzero(speeds == -v0), np.flatnonzero(speeds == -v1)
        if v0 + v1 == 0.0 or not (len(r0) and len(r1)):
            continue  # a turn in place is its own reverse
        accel = (v1 ** 2 - v0 ** 2) / (2.0 * (g[1] + g[2] * abs(g[3]) + g[4]))
        if car.accel_min - 1e-12 <= -accel <= car.accel_max + 1e-12:
            out.append(((k0 + K // 2) % K, (k1 + K // 2) % K, r0[0], r1[0], di, dj, g))
    return out


def build_primitives(settings: LatticeSettings) -> Primitives:
    """The primitive table (see the module docstring): solved for ``BASE`` headings, the mirror image of
    a turn taken for headings 0 and 2 (so each of their sets is exactly symmetric), then mapped by D4 to
    every heading, and with a reversing car each driven backwards too (``_reversed``); each is sampled for
    the collision check."""
    turns = settings.turn_steps
    base = {}
    for k0 in BASE:
        deltas = range(-turns, turns + 1) if k0 not in MIRROR else range(turns + 1)
        prims = [(k0, *p) for p in _base_primitives(settings, k0, deltas)]
        if k0 in MIRROR:
            prims += [_transform(p, MIRROR[k0]) for p in prims if p[1] != k0]
        base[k0] = prims
    table = []
    for k in range(K):
        m, b = next((m, b) for m in D4 for b in BASE if (m @ HEADINGS[b] == HEADINGS[k]).all())
        table += [_transform(p, m) for p in base[b]]
    table += _reversed(table, settings)
    n_speeds = len(settings.speeds)
    table.sort(key=lambda p: (p[0] * n_speeds + p[2], p[1], p[3], p[4], p[5]))
    k0, k1, s0, s1, di, dj = (np.array([p[c] for p in table], np.int64) for c in range(6))
    geometry = np.array([p[6] for p in table])
    speeds = np.asarray(settings.speeds, float)[np.stack([s0, s1], axis=1)]
    length = geometry[:, 1] + geometry[:, 2] * np.abs(geometry[:, 3]) + geometry[:, 4]
    counts = np.where(length > 0, np.ceil(length / settings.sample_m - 1e-9), 4).astype(np.int64)
    spin = np.abs(geometry[:, 3]) / settings.car.omega_max
    cost = np.where(length > 0, 2.0 * length / np.maximum(np.abs(speeds).sum(axis=1), 1e-300), spin)
    start_off = np.searchsorted(k0 * n_speeds + s0, np.arange(K * n_speeds + 1))
    samples = sample_paths(geometry, np.abs(speeds), counts, settings.car.omega_max)
    backwards = np.repeat(speeds.sum(axis=1) < 0.0, counts + 1)  # driven backwards: v < 0, facing the other way
    samples[backwards, 2] *= -1.0
    samples[backwards, 3] = wrap(samples[backwards, 3] + math.pi)
    return Primitives(k0, s0, k1, s1, di, dj, geometry, speeds, cost, 0.5 * length / counts,
                      start_off.astype(np.int64), np.r_[0, np.cumsum(counts + 1)], samples)


@dataclass(frozen=True)
class Clearance:
    """The room's obstacle clearance raster (``hj.pruners.clearance_field``), ``error_m`` a bound on how
    far its interpolant can exceed the true distance (``hj.pruners.field_error``), and the robot radius."""

    field: GridField
    error_m: float
    radius_m: float


@dataclass(frozen=True)
class LatticePlan:
    found: bool
    cost: float  # s (inf without a plan)
    expansions: int
    seconds: float
    states: np.ndarray  # (n, 4) the plan's lattice states x, y, v, θ, start first
    primitives: np.ndarray  # (n − 1,) the primitive ids taken


def dist_heuristic(goal: Goal, v_max: float) -> Callable[[np.ndarray], np.ndarray]:
    """The paper's Dist, admissible form: max(|p − goal| − tolerance, 0) / v_max (no primitive is faster)."""
    xy = np.asarray(goal.xy, float)
    return lambda states: np.maximum(np.hypot(*(states[:, :2] - xy).T) - goal.tolerance, 0.0) / v_max


def deflated(h: Callable[[np.ndarray], np.ndarray], delta: float) -> Callable[[np.ndarray], np.ndarray]:
    """max(h − δ, 0): a heuristic whose overestimate is bounded by δ made admissible."""
    return lambda states: np.maximum(h(states) - delta, 0.0)


@numba.njit(cache=True, inline="always")
def _clear(fv, m, samples, a, b, x0, y0, threshold):
    """True when every sample row a..b-1 (offsets from (x0, y0)) has interpolated clearance > threshold
    and lies on the raster (off it is outside the room)."""
    for q in range(a, b):
        x, y = x0 + samples[q, 0], y0 + samples[q, 1]
        if _outside_xy(m, x, y) or interp2(fv, m, x, y) <= threshold:
            return False
    return True


@numba.njit(cache=True)
def _clear_batch(prims, field, frame, cells, ids):
    """``_clear`` of primitive ids[n] from lattice cell cells[n] (the search's own test), as a mask."""
    fv, m = field_meta(field)
    x0, y0, cell, threshold = frame[0], frame[1], frame[2], frame[7]
    gap, off, samples = prims[0], prims[1], prims[2]
    out = np.zeros(len(ids), np.bool_)
    for n in range(len(ids)):
        p = ids[n]
        out[n] = _clear(fv, m, samples, off[p], off[p + 1], x0 + cells[n, 0] * cell, y0 + cells[n, 1] * cell,
                        threshold + gap[p])
    return out


@numba.njit(cache=True)
def _search(prims, adjacency, field, frame, h, sources, target, reverse, max_expansions):
    """A* from ``sources`` (g = 0) until a ``target`` state is popped (none: every reachable state), over
    the primitives forwards or, with ``reverse``, backwards (predecessors: the cost-to-go of the sources).
    States whose g improves re-enter OPEN (reopening). prims: (gap, sample_off, samples, k0, s0, k1, s1,
    di, dj, cost); adjacency: CSR (offsets by class k·S + s, primitive ids); frame: (x0, y0, cell, nx, ny,
    K, S, clearance threshold). Returns g, parent, via (primitive), the target popped (−1) and expansions."""
    gap, soff, samples, k0, s0, k1, s1, di, dj, cost = prims
    off, ids = adjacency
    x0, y0, cell, nx, ny, nk, ns, threshold = frame
    fv, m = field_meta(field)
    n = nx * ny * nk * ns
    g = np.full(n, np.inf)
    parent = np.full(n, -1, np.int64)
    via = np.full(n, -1, np.int64)
    queue = new_indexed(n, 2)
    key = queue[3]
    for s in sources:
        g[s] = 0.0
        key[s, 0], key[s, 1] = h[s], h[s]
        insert_or_decrease(queue, s)
    expansions, found = 0, -1
    while queue[2][0] > 0 and expansions < max_expansions:
        u = pop_top(queue)
        if target[u]:
            found = u
            break
        expansions += 1
        sp = u % ns
        k = (u // ns) % nk
        j = (u // (ns * nk)) % ny
        i = u // (ns * nk * ny)
        cls = k * ns + sp
        for e in range(off[cls], off[cls + 1]):
            p = ids[e]
            if reverse:
                ci, cj, vi, vj, vk, vs = i - di[p], j - dj[p], i - di[p], j - dj[p], k0[p], s0[p]
            else:
                ci, cj, vi, vj, vk, vs = i, j, i + di[p], j + dj[p], k1[p], s1[p]
            if vi < 0 or vj < 0 or vi >= nx or vj >= ny:
                continue
            v = ((vi * ny + vj) * nk + vk) * ns + vs
            ng = g[u] + cost[p]
            if ng >= g[v] or not _clear(fv, m, samples, soff[p], soff[p + 1], x0 + ci * cell, y0 + cj * cell,
                                        threshold + gap[p]):
                continue
            g[v], parent[v], via[v] = ng, u, p
            key[v, 0], key[v, 1] = ng + h[v], h[v]
            insert_or_decrease(queue, v)
    return g, parent, via, found, expansions


class Lattice:
    """The state lattice over one room, anchored so that ``anchor_xy`` (the start) is a lattice point."""

    def __init__(self, settings: LatticeSettings, clearance: Clearance, anchor_xy,
                 primitives: Primitives | None = None):
        self.settings, self.clearance = settings, clearance
        self.prims = build_primitives(settings) if primitives is None else primitives
        f, cell = clearance.field, settings.cell_m
        lo = np.asarray(f.lo)
        hi = lo + (np.asarray(f.shape) - 1) / np.asarray(f.inv_spacing)
        anchor = np.asarray(anchor_xy, float)
        self.origin = anchor - np.floor((anchor - lo) / cell + 1e-9) * cell
        self.nx, self.ny = (np.floor((hi - self.origin) / cell + 1e-9).astype(int) + 1).tolist()
        self.shape = (self.nx, self.ny, K, len(settings.speeds))
        threshold = clearance.radius_m + clearance.error_m
        self._frame = (float(self.origin[0]), float(self.origin[1]), float(cell), self.nx, self.ny, K,
                       len(settings.speeds), float(threshold))
        p = self.prims
        self._prims = (p.gap, p.sample_off, p.samples, p.k0, p.s0, p.k1, p.s1, p.di, p.dj, p.cost)
        n_classes = K * len(settings.speeds)
        ends = np.argsort(p.k1 * len(settings.speeds) + p.s1, kind="stable")
        self._forward = (p.start_off, np.arange(len(p.cost), dtype=np.int64))
        self._reverse = (np.searchsorted((p.k1 * len(settings.speeds) + p.s1)[ends], np.arange(n_classes + 1)),
                         ends.astype(np.int64))
        self._states = None

    @property
    def states(self) -> np.ndarray:
        """(N, 4) x, y, v, θ of every lattice state, in state-id order."""
        if self._states is None:
            i, j, k, s = np.unravel_index(np.arange(int(np.prod(self.shape))), self.shape)
            cell = self.settings.cell_m
            self._states = np.stack([self.origin[0] + i * cell, self.origin[1] + j * cell,
                                     np.asarray(self.settings.speeds)[s], ANGLES[k]], axis=1)
        return self._states

    def index(self, state) -> int:
        """The lattice state of (x, y, v, θ): position and speed must lie on the lattice; the heading is
        snapped to the nearest lattice heading (the tables' 30° steps are not all lattice headings)."""
        x, y, v, th = map(float, state)
        ij = (np.array([x, y]) - self.origin) / self.settings.cell_m
        s = np.flatnonzero(np.isclose(self.settings.speeds, v))
        if not np.allclose(ij, np.round(ij), atol=1e-6) or len(s) != 1:
            raise ValueError(f"state {tuple(state)} is not on the lattice (cell {self.settings.cell_m} m from "
                             f"{tuple(self.origin)}, speeds {self.settings.speeds})")
        i, j = np.round(ij).astype(int)
        k = int(np.argmin(np.abs(wrap(ANGLES - th))))
        return int(np.ravel_multi_index((i, j, k, s[0]), self.shape))

    def goal_mask(self, goal: Goal) -> np.ndarray:
        st = self.states
        return (np.hypot(st[:, 0] - goal.xy[0], st[:, 1] - goal.xy[1]) <= goal.tolerance) & (
            np.abs(st[:, 2]) <= goal.max_speed)

    def clear(self, cells: np.ndarray, ids: np.ndarray) -> np.ndarray:
        """The search's collision test of primitive ids[n] from lattice cell cells[n] (i, j): True = kept."""
        return _clear_batch((self.prims.gap, self.prims.sample_off, self.prims.samples), self.clearance.field,
                            self._frame, np.asarray(cells, np.int64).reshape(-1, 2), np.asarray(ids, np.int64))

    def heuristic_table(self, heuristic: Callable[[np.ndarray], np.ndarray] | None, goal: Goal) -> np.ndarray:
        """h at every lattice state, 0 on the goal states (their cost-to-go is 0). Why: a grid heuristic
        interpolated across the goal disc's rim mixes in nodes outside it; the default TTR grid gives up to
        ~2 s at lattice goal states 0.18 m from the goal (measured, benchmarks/hj_state_lattice.py), which
        A* would pop late, returning a worse goal."""
        if heuristic is None:
            return np.zeros(len(self.states))
        return np.where(self.goal_mask(goal), 0.0, np.asarray(heuristic(self.states), np.float64))

    def search(self, start, goal: Goal, heuristic: Callable[[np.ndarray], np.ndarray] | None = None,
               max_expansions: int = 10 ** 9) -> LatticePlan:
        """A* from ``start`` (see ``index``) to ``goal`` with ``heuristic`` (None: Dijkstra), evaluated for
        every lattice state first (``heuristic_table``); ``seconds`` counts only the search."""
        h = self.heuristic_table(heuristic, goal)
        source = np.array([self.index(start)], np.int64)
        t0 = time.perf_counter()
        g, parent, via, found, expansions = _search(self._prims, self._forward, self.clearance.field, self._frame,
                                                    h, source, self.goal_mask(goal), False, max_expansions)
        seconds = time.perf_counter() - t0
        if found < 0:
            return LatticePlan(False, math.inf, int(expansions), seconds, self.states[source], np.zeros(0, np.int64))
        path = [found]
        while parent[path[-1]] >= 0:
            path.append(parent[path[-1]])
        path = np.array(path[::-1])
        return LatticePlan(True, float(g[found]), int(expansions), seconds, self.states[path], via[path[1:]])

    def cost_to_go(self, goal: Goal) -> np.ndarray:
        """The exact cost-to-go of every lattice state (inf: cannot reach the goal): Dijkstra backwards
        from every goal state over the primitives' predecessors, with the same collision test."""
        mask = self.goal_mask(goal)
        g = _search(self._prims, self._reverse, self.clearance.field, self._frame, np.zeros(len(mask)),
                    np.flatnonzero(mask).astype(np.int64), np.zeros(len(mask), np.bool_), True, 10 ** 12)[0]
        return g

    def excess(self, heuristic: Callable[[np.ndarray], np.ndarray], goal: Goal, cost_to_go: np.ndarray) -> float:
        """The largest amount by which ``heuristic`` (as ``search`` uses it: ``heuristic_table``) exceeds the
        exact cost-to-go over the states that can reach the goal (<= 0: admissible on this lattice)."""
        finite = np.isfinite(cost_to_go)
        return float((self.heuristic_table(heuristic, goal)[finite] - cost_to_go[finite]).max())
