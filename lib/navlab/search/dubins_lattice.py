"""A kinodynamic lattice for the 4D Dubins car of the HJ-search paper (Eq. 19), state (x, y, v, θ).

Why this shape: the paper searches over (acceleration, turn-rate) primitives held for a step ``dt``
(its Table X: 0.5 s between neighbouring nodes) and counts 35 successors and 140 pruned states per
expansion (Table VII): 5 accelerations × 7 turn rates, each checked at 4 points along its segment.
Speeds are kept on ``n`` levels from ``v_min`` to ``v_max`` in steps of ``dv = (v_max − v_min) / (n − 1)``,
0 among them: every ``a · dt`` is a whole number of levels and v is clipped to [v_min, v_max] (the grids'
speed axis), so a primitive's shape depends only on the speed level it starts from and on the control.
With ``v_min < 0`` the car reverses (x moves by v cos θ dt < 0 along its heading): the paper's Sec. VII-A
reports Dist guiding the car into "persistent backward movements" and TTR's "slight reversal followed by
a precise reorientation" (Fig. 6), which a forward-only car (``v_min = 0``, a labelled variant) cannot do.
``primitive_table`` integrates each primitive once per level in the body frame; an expansion then only
rotates and translates a table row (no integration in the hot loop).

Nodes keep their continuous state and are identified by a snapped cell ``(⌊x/c⌋, ⌊y/c⌋, level,
round(θ/bin))`` for duplicate detection, as Nav2's Smac hybrid A* does. With ``snap_states`` the node
state is moved to its cell's centre after its segment was checked as driven: the lattice is then a fixed
graph, which is what an independent Dijkstra can check the search against (its plans jump by up to half
a cell and half a heading bin at every node, so they are not trajectories the car can drive).

``integrate`` (compiled, any number of micro-steps) is the reference integrator; ``densify`` replays a
plan's controls with it for the paper's feasibility check, through the very points the table was
integrated on (``samples_per_step × micro_steps`` per step), which the search's swept collision check
(``lattice_fields.swept_unsafe``) provably covers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit


@dataclass(frozen=True)
class LatticeSpec:
    """Primitives and cells of the lattice. Units: s, m/s², rad/s, m."""

    dt: float
    accelerations: tuple[float, ...]
    turn_rates: tuple[float, ...]
    v_max: float
    speed_levels: int
    samples_per_step: int  # points per primitive handed to a pruner (the last is the successor itself)
    cell_m: float
    heading_bins: int
    snap_states: bool = False
    micro_steps: int = 8  # midpoint-rule sub-steps per sample when building the table (and the dense check's)
    v_min: float = 0.0  # < 0: the car reverses; planning.lattice_spec passes hj.grids.robot.v_min

    def __post_init__(self):
        if self.dt <= 0 or self.v_max <= 0 or self.cell_m <= 0:
            raise ValueError(f"LatticeSpec: dt, v_max and cell_m must be > 0; got {self}")
        if not -self.v_max <= self.v_min <= 0.0:
            raise ValueError(f"LatticeSpec: v_min = {self.v_min} must lie in [-v_max, 0] (hj.grids.robot.v_min)")
        if self.speed_levels < 2 or self.heading_bins < 4 or self.samples_per_step < 1 or self.micro_steps < 1:
            raise ValueError("LatticeSpec: need speed_levels >= 2, heading_bins >= 4, samples_per_step >= 1, "
                             "micro_steps >= 1")
        if not self.accelerations or not self.turn_rates:
            raise ValueError("LatticeSpec: accelerations and turn_rates must not be empty")
        for a in self.accelerations:
            steps = a * self.dt / self.dv
            if abs(steps - round(steps)) > 1e-6:
                raise ValueError(f"LatticeSpec: acceleration {a} × dt {self.dt} = {a * self.dt:g} m/s is not a "
                                 f"whole number of speed levels ({self.dv:g} m/s); change accelerations, dt or "
                                 f"speed_levels in params.yaml (hj.planner.lattice)")
        zero = -self.v_min / self.dv
        if abs(zero - round(zero)) > 1e-6:
            raise ValueError(f"LatticeSpec: 0 m/s is not a speed level ({self.speed_levels} levels from v_min = "
                             f"{self.v_min:g} to v_max = {self.v_max:g}, {self.dv:g} m/s apart): a car at rest would "
                             f"be off the lattice; change speed_levels (hj.planner.lattice) or hj.grids.robot.v_min")

    @property
    def dv(self) -> float:
        return (self.v_max - self.v_min) / (self.speed_levels - 1)

    @property
    def zero_level(self) -> int:
        """The index of the level 0 m/s: level k is the speed (k − zero_level) · dv."""
        return round(-self.v_min / self.dv)

    @property
    def speeds(self) -> np.ndarray:
        """(levels,) the speed of every level, v_min first."""
        return (np.arange(self.speed_levels) - self.zero_level) * self.dv

    @property
    def v_range(self) -> tuple[float, float]:
        return self.v_min, self.v_max

    @property
    def n_primitives(self) -> int:
        return len(self.accelerations) * len(self.turn_rates)

    @property
    def controls(self) -> np.ndarray:
        """(P, 2) (a, ω) of every primitive, accelerations outermost."""
        return np.array([(a, w) for a in self.accelerations for w in self.turn_rates], dtype=np.float64)

    def level(self, v: float) -> int:
        k = v / self.dv
        if abs(k - round(k)) > 1e-6 or not 0 <= round(k) + self.zero_level < self.speed_levels:
            raise ValueError(f"speed {v} m/s is not a lattice speed level (multiples of {self.dv:g} from "
                             f"{self.v_min:g} to {self.v_max:g}); start from one of them (e.g. 0)")
        return round(k) + self.zero_level


@njit(cache=True)
def _integrate_into(out: np.ndarray, state: np.ndarray, a: float, omega: float, h: float, v_min: float,
                    v_max: float) -> None:
    """``integrate``'s loop, compiled: ``out`` (n, 4) filled with the states after each sub-step of length h.
    The same operations in the same order as the plain-Python loop it replaced (no fast-math, so no fused or
    reordered arithmetic; math.cos/sin are libm's), so the states are bit for bit those
    (tests/test_hj_planner.py checks it against that loop)."""
    x, y, v, th = state[0], state[1], state[2], state[3]
    for i in range(out.shape[0]):
        v1 = min(max(v + a * h, v_min), v_max)
        th1 = th + omega * h
        vm = 0.5 * (v + v1)
        tm = th + 0.5 * omega * h
        x += h * vm * math.cos(tm)
        y += h * vm * math.sin(tm)
        v = v1
        th = th1
        out[i, 0] = x
        out[i, 1] = y
        out[i, 2] = v
        out[i, 3] = th


@njit(cache=True)
def _primitive_rows(v: float, controls: np.ndarray, h: float, samples: int, micro: int, v_min: float,
                    v_max: float) -> np.ndarray:
    """(P, samples, 4): each control of ``controls`` (P, 2) held from (0, 0, v, 0) for samples × micro sub-steps
    of length h, every ``micro``-th state kept (``integrate`` per control, in one compiled loop)."""
    rows = np.empty((controls.shape[0], samples, 4))
    dense = np.empty((samples * micro, 4))
    start = np.array([0.0, 0.0, v, 0.0])
    for p in range(controls.shape[0]):
        _integrate_into(dense, start, controls[p, 0], controls[p, 1], h, v_min, v_max)
        for k in range(samples):
            rows[p, k] = dense[(k + 1) * micro - 1]
    return rows


def integrate(state: np.ndarray, a: float, omega: float, duration: float, n: int,
              v_range: tuple[float, float]) -> np.ndarray:
    """States after each of ``n`` equal sub-steps of holding (a, ω) from ``state`` (x, y, v, θ): (n, 4).

    v moves linearly and is clipped to ``v_range`` (v_min, v_max), θ moves linearly; the position uses
    the midpoint of each sub-step (second order), the same rule the table is built with (at v < 0 the car
    moves backwards along its heading). Compiled (``_integrate_into``): every re-plan's first step, the
    closed loop's car and the dense feasibility check run it.
    """
    out = np.empty((n, 4))
    v_min, v_max = v_range
    _integrate_into(out, np.asarray(state, dtype=np.float64)[:4].copy(), float(a), float(omega), duration / n,
                    float(v_min), float(v_max))
    return out


def primitive_table(spec: LatticeSpec) -> np.ndarray:
    """(levels, P, samples, 4): body-frame (dx, dy, v, dθ) at each sample of every primitive per start level
    (``first_step`` from each level, where it adds nothing to the accelerations)."""
    return np.stack([first_step(spec, v)[0] for v in spec.speeds])


def first_step(spec: LatticeSpec, v: float) -> tuple[np.ndarray, np.ndarray]:
    """The primitives of a plan's first step from an off-level speed ``v``: rows (P, S, 4) as in
    ``primitive_table`` and their controls (P, 2).

    Why: a car's measured speed is rarely a level, and a plan made from the nearest level but executed
    from the true speed drifts by up to dv/2 · t (12 cm in 2 s at dv = 0.125 m/s): in a turn the faster car
    swings wide, off the states the pruner checked. Each primitive's acceleration here absorbs the gap
    over the first step (a + (level − v)/dt, at most dv/(2·dt) = 0.125 m/s² more or less than the lattice's),
    so the step ends on the same level as from the level itself and the search checks exactly the
    trajectory the car will drive.
    """
    if not spec.v_min - 1e-9 <= v <= spec.v_max + 1e-9:
        raise ValueError(f"speed {v} m/s is outside the lattice's [{spec.v_min:g}, {spec.v_max:g}] m/s")
    level = spec.speeds[min(max(round(v / spec.dv) + spec.zero_level, 0), spec.speed_levels - 1)]
    s, m = spec.samples_per_step, spec.micro_steps
    controls = spec.controls.copy()
    controls[:, 0] += (level - v) / spec.dt
    rows = _primitive_rows(float(v), controls, spec.dt / (s * m), s, m, *map(float, spec.v_range))
    rows[:, -1, 2] = np.round(rows[:, -1, 2] / spec.dv) * spec.dv  # end speeds exactly on a level
    return rows, controls


def place(rows: np.ndarray, state: np.ndarray) -> np.ndarray:
    """Body-frame primitive rows (..., 4) placed at ``state`` (x, y, v, θ): world-frame samples."""
    x, y, _, th = (float(s) for s in state)
    c, s = math.cos(th), math.sin(th)
    out = np.empty(rows.shape)
    out[..., 0] = x + c * rows[..., 0] - s * rows[..., 1]
    out[..., 1] = y + s * rows[..., 0] + c * rows[..., 1]
    out[..., 2] = rows[..., 2]
    out[..., 3] = th + rows[..., 3]
    return out


def densify(spec: LatticeSpec, start: np.ndarray, controls: np.ndarray) -> np.ndarray:
    """Replay a plan's controls from ``start``: (1 + K·n, 4), n = ``samples_per_step × micro_steps`` sub-steps
    per primitive, the integration the table was built with (every ``micro_steps``-th point is a sample
    the search checked; the swept check bounds the path between them). With ``snap_states`` each step
    starts from its node's cell centre, as the search's do."""
    n = spec.samples_per_step * spec.micro_steps
    points = [np.asarray(start, dtype=np.float64)[None]]
    state = np.asarray(start, dtype=np.float64)
    for a, w in np.asarray(controls, dtype=np.float64).reshape(-1, 2):
        seg = integrate(state, a, w, spec.dt, n, spec.v_range)
        points.append(seg)
        state = snap(spec, seg[-1]) if spec.snap_states else seg[-1]
    return np.concatenate(points)


def snap(spec: LatticeSpec, state: np.ndarray) -> np.ndarray:
    """The centre of ``state``'s cell (speed to the nearest level, heading to its bin)."""
    c, b = spec.cell_m, 2 * math.pi / spec.heading_bins
    x, y, v, th = state
    return np.array([(math.floor(x / c) + 0.5) * c, (math.floor(y / c) + 0.5) * c,
                     spec.speeds[spec.level(round(v / spec.dv) * spec.dv)], round(th / b) * b])


def successor_samples(spec: LatticeSpec, table: np.ndarray, state: np.ndarray) -> np.ndarray:
    """(P, S, 4) world-frame samples of every primitive from ``state``: what one expansion hands a pruner
    (its last sample per primitive is the successor the heuristic sees)."""
    v = float(state[2])
    return place(table[spec.level(round(v / spec.dv) * spec.dv)], state)
