r"""A* and ANA* on the Dubins lattice, compiled with numba (HJ-search paper, Sec. VII; Algorithm 2).

- **A\*** (Hart, Nilsson & Raphael 1968) with a node-expansion limit; a cell whose g improves is reopened,
  so an admissible (not necessarily consistent) heuristic still returns the lattice optimum.
- **ANA\*** (van den Berg, Shah, Huang & Goldberg, AAAI 2011): OPEN ordered by the largest
  e(s) = (G − g(s)) / h(s) (a float, not SBPL's integer truncation, which loses the order between 1 and
  2); before the first solution G = ∞ and the order is the smallest h (greedy). Successors are inserted
  only when g + h < G; after each improving solution the states with e <= 1 (g + h >= G) are dropped and
  the rest re-keyed. Every solution is recorded with the expansions and time it took and the bound
  ε = G / min_OPEN(g + h) (1 when OPEN is empty: the last solution is optimal).

The expansion loop, the look-ups (``lattice_fields``) and the open list (``heap``'s deeper-first heap) are
one compiled function: an expansion rotates the precomputed primitive table (``dubins_lattice``), checks the
pruners on the ``samples_per_step`` points of every segment (an OBS pruner sweeps the path between them, provably:
``lattice_fields.swept_unsafe``) and evaluates the heuristic of improved successors.
The cost of a step is ``dt · (1 + w · c(x, y))`` with ``c`` an optional state-cost raster (the paper's
Nav2 costmap term; w = 0 gives time, the paper's "state cost 1.0"), so time heuristics stay admissible.
``lattice_reference.py`` is the plain-Python heapq twin that the tests and benchmarks compare against.
"""

from __future__ import annotations

import copy
import math
import time
from dataclasses import dataclass, field, replace
from typing import NamedTuple

import numba
import numpy as np

from navlab.search.dubins_lattice import LatticeSpec, first_step, primitive_table, snap
from navlab.search.heap import deeper_first_pop, deeper_first_push
from navlab.search.lattice_fields import (
    H_ZERO,
    S_NONE,
    S_OBS,
    S_OBS_POINT,
    U_FI,
    U_NONE,
    GridField,
    cell_min,
    field_meta,
    first_unsafe,
    heuristic,
    heuristic_batch,
    human_prune_batch,
    human_prunes,
    human_values_at,
    interp2,
    obs_clearance,
    static_prune_batch,
    static_value_batch,
    swept_prune_batch,
    swept_unsafe,
    wrap,
)

FOUND, EXPANSION_LIMIT, TIME_LIMIT, NO_PATH = 0, 1, 2, 3
STATUS = {FOUND: "found", EXPANSION_LIMIT: "expansion limit", TIME_LIMIT: "time limit", NO_PATH: "no path"}
MAX_SOLUTIONS = 512


def _read_only(field: GridField) -> GridField:
    """``field`` with its values as a read-only view. Why: numba compiles ``_search`` once per combination of
    argument types, and read-only is part of an array's type; fields arrive writable (built in memory) or
    read-only (memory-mapped stored grids), so each mix of heuristic and pruners cost a compile of its own
    (about 50 s each, four of them on a fresh checkout's HJ stages). One type: one compile."""
    values = field.values.view()
    values.flags.writeable = False
    return field._replace(values=values)


@dataclass(frozen=True)
class Heuristic:
    """What the compiled search evaluates as h: a kind code (``lattice_fields.H_*``), a field and par."""

    kind: int
    field: GridField
    par: np.ndarray  # [goal_x, goal_y, goal_heading, v_max, tolerance, off_grid_value, cos, sin of goal_heading]
    name: str = ""

    def __call__(self, states: np.ndarray) -> np.ndarray:
        """h at (N, 4) states in one compiled call: (N,) seconds."""
        return heuristic_batch(self.kind, self.field, self.par, _states(states))


@dataclass(frozen=True)
class StaticPruner:
    kind: int
    field: GridField
    par: np.ndarray  # [radius or margin, value off the grid], and for S_OBS the field's error bound
    name: str = ""
    # the corner minimum of every cell of ``field`` (lattice_fields.cell_min), derived here
    lower: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        self._check_obs(self.par)
        object.__setattr__(self, "lower", cell_min(self.field))

    def _check_obs(self, par: np.ndarray) -> None:
        """The compiled swept check reads an OBS pruner's par[2] (the field's error bound) and needs
        par[0] >= it: below, the threshold is a negative radius and segments through obstacles pass."""
        if self.kind not in (S_OBS, S_OBS_POINT):
            return
        if len(par) != 3:
            raise ValueError(f"OBS pruner par {list(par)}: give [radius + field error, value off the grid, "
                             f"field error] (hj.pruners.obs_pruner builds it)")
        if par[0] < par[2]:
            raise ValueError(f"OBS threshold {par[0]}: below the field's error bound {par[2]:.4f} m, it would "
                             f"let paths through obstacles; use >= that (a robot radius >= 0)")

    def __call__(self, samples: np.ndarray) -> np.ndarray:
        """(N, S, 4) segment samples (all successors of one expansion) -> (N,) True where pruned."""
        return static_prune_batch(self.kind, self.field, self.lower, self.par, _segments(samples))

    def swept(self, parents: np.ndarray, samples: np.ndarray, durations: np.ndarray) -> np.ndarray:
        """The conservative collision check of an OBS pruner (``lattice_fields.swept_unsafe``; a point-check
        one's field and par serve it as well): parents (N, 4), their segments' samples (N, S, 4), equally
        spaced over ``durations`` (N,) s -> (N,) True where the path from a parent through its samples may
        touch an obstacle."""
        if self.kind not in (S_OBS, S_OBS_POINT):
            raise ValueError(f"the {self.name or 'static'} pruner has no swept collision check: use an OBS "
                             f"pruner (hj.pruners.obs_pruner)")
        parents, samples = _states(parents, "parents"), _segments(samples)
        if len(parents) != len(samples):
            raise ValueError(f"{len(parents)} parents for {len(samples)} segments: give each segment its parent")
        steps = _times(durations, len(samples), "durations") / samples.shape[1]
        if (steps < 0).any():
            raise ValueError("durations must be >= 0 s")
        return swept_prune_batch(self.field, self.lower, self.par, parents, samples, steps)

    def values(self, states: np.ndarray) -> np.ndarray:
        """The safety value minus the threshold at (N, 4) states (> 0 is kept)."""
        return static_value_batch(self.kind, self.field, self.par, _states(states))

    def goal_clearance(self, goal: Goal) -> float:
        """An upper bound on ``values`` over every state a goal node can hold (any speed and heading, any
        position within the goal tolerance): the largest node value of the field cells that the goal's
        bounding box meets (a multilinear interpolant never exceeds its cell's corners), and the value off
        the grid where the box leaves it. <= 0: every such state is pruned, so no search can reach the goal."""
        f, centre = self.field, np.asarray(goal.xy, np.float64)
        reach = goal.tolerance + 1e-6  # m: the goal test's rounding
        inv, n = f.inv_spacing[:2], f.shape[:2]
        lo, hi = f.lo[:2], f.lo[:2] + (n - 1) / inv
        off_grid = (centre - reach < lo).any() or (centre + reach > hi).any()
        i0 = np.clip(np.floor((centre - reach - lo) * inv), 0, n - 2).astype(np.int64)
        i1 = np.clip(np.ceil((centre + reach - lo) * inv), i0 + 1, n - 1).astype(np.int64)
        block = np.asarray(f.values).reshape(tuple(f.shape))[i0[0]:i1[0] + 1, i0[1]:i1[1] + 1]
        bound = max(float(block.max()), float(self.par[1])) if off_grid else float(block.max())
        return bound - float(self.par[0])

    def with_threshold(self, threshold: float) -> StaticPruner:
        """The same pruner pruning at ``threshold`` instead of ``par[0]``; it shares the cell minima (they do
        not depend on the threshold, and re-deriving them costs a pass over the whole grid per call)."""
        if not math.isfinite(threshold):
            raise ValueError(f"pruner threshold {threshold}: must be a finite number (a NaN prunes nothing)")
        par = np.array([threshold, *self.par[1:]])
        self._check_obs(par)
        twin = copy.copy(self)
        object.__setattr__(twin, "par", par)
        return twin


@dataclass(frozen=True)
class HumanPruner:
    kind: int
    field: GridField
    par: np.ndarray  # see lattice_fields.human_value
    humans: np.ndarray  # (H, 4) observed x, y, vx, vy (lattice_fields.human_prunes predicts with them)
    name: str = ""

    def __post_init__(self):
        # read-only whatever it came as (a stored BRT is a memory map, NO_HUMAN's placeholder and a solved one
        # are not): ``human_prune_batch`` compiles once per array type, as ``search`` does (``_read_only``)
        object.__setattr__(self, "field", _read_only(self.field))
        humans = np.asarray(self.humans, np.float64)
        if humans.ndim != 2 or humans.shape[1] != 4:
            raise ValueError(f"humans must be (H, 4) (x, y, vx, vy), got {humans.shape}")
        require_finite(humans, "humans (x, y, vx, vy)", "drop the humans whose track was lost or fix their estimate")

    def __call__(self, parents: np.ndarray, samples: np.ndarray, t0: np.ndarray | None = None,
                 durations: np.ndarray | None = None) -> np.ndarray:
        """parents (N, 4), segment samples (N, S, 4) -> (N,) True where a human makes the step unsafe.
        ``t0``/``durations`` (N,): each parent's time after the observation and its segment's length (default
        0: the humans where they were seen)."""
        parents, samples = _states(parents, "parents"), _segments(samples)
        n = len(parents)
        if len(samples) != n:  # the compiled loop reads parents[i] for every segment i, unchecked
            raise ValueError(f"{n} parents for {len(samples)} segments: give each segment its parent state")
        t0 = np.zeros(n) if t0 is None else _times(t0, n, "t0")
        durations = np.zeros(n) if durations is None else _times(durations, n, "durations")
        return human_prune_batch(self.kind, self.field, self.par, np.ascontiguousarray(self.humans, np.float64),
                                 parents, samples, t0, durations)


def require_finite(array: np.ndarray, name: str, fix: str) -> np.ndarray:
    """``array`` itself, or a ValueError naming ``name``: a NaN compares false with every threshold, so a
    pruner would call its state safe (and a NaN heading once hung the compiled look-up)."""
    if not np.isfinite(array).all():
        first = tuple(int(i) for i in np.argwhere(~np.isfinite(array))[0])
        raise ValueError(f"{name} holds NaN or inf (first at index {first}); {fix}")
    return array


def _states(states, name: str = "states") -> np.ndarray:
    states = np.ascontiguousarray(states, dtype=np.float64)
    if states.ndim != 2 or states.shape[1] != 4:
        raise ValueError(f"{name} must be (N, 4) (x, y, v, θ), got {states.shape}")
    return require_finite(states, name, "pass finite states (check the simulator or planner that made them)")


def _segments(samples) -> np.ndarray:
    samples = np.ascontiguousarray(samples, dtype=np.float64)
    if samples.ndim != 3 or samples.shape[2] != 4:
        raise ValueError(f"segment samples must be (N, S, 4) (x, y, v, θ), got {samples.shape}")
    return require_finite(samples, "segment samples", "pass finite states (check the planner that made them)")


def _times(times, n: int, name: str) -> np.ndarray:
    times = np.asarray(times, np.float64)
    if times.shape != (n,):
        raise ValueError(f"{name} must hold one time per parent ({n},), got {times.shape}")
    return require_finite(times, name, "pass finite times in seconds")


NO_STATIC = StaticPruner(S_NONE, GridField.empty(2), np.zeros(2), "none")
NO_HUMAN = HumanPruner(U_NONE, GridField.empty(3), np.zeros(11), np.zeros((0, 4)), "none")


class Pruners(NamedTuple):
    """What a search prunes with. ``static``: the paper's pruner (OBS or BRT); ``collision``: an OBS pruner whose
    conservative swept check (``lattice_fields.swept_unsafe``) every segment must pass as well, so that a
    BRT-pruned plan, checked by the BRT only at its samples, never touches an obstacle between them (an OBS
    ``static`` already sweeps); ``human``: the FS/FI human-robot BRT pruner."""

    static: StaticPruner = NO_STATIC
    collision: StaticPruner = NO_STATIC
    human: HumanPruner = NO_HUMAN


class Budget(NamedTuple):
    """When a search stops. ``anytime=False``: A* until the goal is popped or ``max_expansions``;
    ``anytime=True``: ANA* until OPEN is empty (the last solution is optimal), ``max_expansions`` or
    ``time_limit_s``."""

    anytime: bool = False
    max_expansions: int = 10**6
    time_limit_s: float = math.inf


NO_PRUNERS = Pruners()
A_STAR = Budget()  # A* until the goal, at most 10^6 expansions


@dataclass(frozen=True)
class Goal:
    xy: tuple[float, float]
    tolerance: float  # m: reached when |p - goal| <= tolerance ...
    max_speed: float  # ... and |v| <= max_speed (the paper's speed limit at the goal; reversing too)

    def __post_init__(self):
        if len(self.xy) != 2 or not all(math.isfinite(c) for c in self.xy):
            raise ValueError(f"goal xy {self.xy}: must be two finite numbers (x, y) in metres")
        for name in ("tolerance", "max_speed"):  # the search squares the tolerance: -0.3 acted as 0.3
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"goal {name} {value}: must be a finite number >= 0; fix the goal's {name}")


@dataclass(frozen=True)
class Costmap:
    """Step cost dt · (1 + weight · c(x, y)); ``field`` a 2D raster of c >= 0 (None: pure time).

    Both are checked: a negative or NaN step cost breaks A* (one search returned a plan of cost −46)."""

    field: GridField | None = None
    weight: float = 0.0

    def __post_init__(self):
        if not (math.isfinite(self.weight) and self.weight >= 0):
            raise ValueError(f"costmap weight {self.weight}: must be a finite number >= 0 (0: pure time)")
        values = None if self.field is None else np.asarray(self.field.values)
        if values is not None and not (np.isfinite(values).all() and values.min() >= 0):
            raise ValueError(f"costmap field: every cell cost must be finite and >= 0, found min {values.min()}, "
                             f"max {values.max()}; rebuild the cost raster (hj.planning.costmap_field)")


@dataclass
class SearchResult:
    status: str
    cost: float  # of the returned plan (inf when none)
    expansions: int  # in total
    controls: np.ndarray  # (K, 2) (a, ω) per step of the returned plan
    states: np.ndarray  # (K + 1, 4) lattice states along it
    seconds: float  # since the search began (over resumes)
    heuristic_evals: int = 0
    pruner_evals: int = 0  # segment samples checked (each pruner call checks samples_per_step of them)
    # ANA*: every improving solution, in order
    solution_expansions: list[int] = field(default_factory=list)
    solution_seconds: list[float] = field(default_factory=list)
    solution_costs: list[float] = field(default_factory=list)
    solution_bounds: list[float] = field(default_factory=list)
    frontier: Frontier | None = None  # a search stopped at its limit, with ``keep_frontier``: ``resume`` goes on

    @property
    def found(self) -> bool:
        return math.isfinite(self.cost)

    @property
    def first_solution_expansions(self) -> int | None:
        return self.solution_expansions[0] if self.solution_expansions else None


@numba.njit(cache=True)
def _now():
    with numba.objmode(t="f8"):
        t = time.perf_counter()
    return t


@numba.njit(cache=True)
def _ana_key(G, g, h):
    """Min-heap key of ANA*: −e(s) once a solution exists, h before (G = ∞: greedy on h)."""
    if G == np.inf:
        return h
    if h <= 0.0:
        return -np.inf if g < G else 0.0
    return -(G - g) / h


@numba.njit(cache=True, error_model="numpy")  # no zero-division checks (and their error paths) in the loop
def _search(start, goal, table, root, lattice, heur, prune, cost, limits, state):
    """The compiled A*/ANA* loop. Bundles (``search`` builds them): lattice (dt, cell_m, dims, snap); heur (kind,
    field, par); prune: static and collision (kind, field, cell minima, par) of two static pruners, then human
    (kind, field, par, humans); cost (use_cost, field, weight); limits (anytime, max_expansions, time_limit);
    state (``_fresh_state``: g and best node per cell, the node pool, OPEN, the solutions, the counters), which
    it goes on from and returns, so that a search stopped at its limit can be resumed (``resume``)."""
    dt, cell_m, dims, snap = lattice
    hk, hf, hp = heur
    static, collision, human = prune
    sk, sf, sb, sp = static
    ck, cf_, cb, cp = collision
    uk, uf, up, humans = human
    use_cost, cf, cost_w = cost
    anytime, max_expansions, time_limit = limits
    g, best, st, parent, prim, cell, hval, tn, heap_k, heap_g, heap_c, sol_i, sol_f, counts, reals = state
    nx, ny, nlev, nbins = dims[0], dims[1], dims[2], dims[3]
    n_prim, n_samp = table.shape[1], table.shape[2]
    segment = np.empty((1, n_samp, 4))  # one segment, indexed as first_unsafe reads it
    at_parent = np.empty(humans.shape[0])  # the expanded node's human values (the FI rule's V before the step)
    samples = segment[0]
    bin_w = 2.0 * math.pi / nbins
    dv, zero = goal[4], round(goal[5])  # the lattice's speed step and the index of its level 0 m/s
    step_t = dt / n_samp  # time between a segment's samples (the swept check's interval)
    t0 = _now() - reals[1]  # the time already spent counts: solution times are from the search's start
    hv, hm = field_meta(hf)
    sv, sm = field_meta(sf)
    cv_, cm_ = field_meta(cf_)
    uv, um = field_meta(uf)
    cv, cm = field_meta(cf)
    x_goal, y_goal, tol2, v_goal = goal[0], goal[1], goal[2] * goal[2], goal[3] + 1e-9

    def cell_of(x, y, v, th):
        ix = math.floor(x / cell_m)
        iy = math.floor(y / cell_m)
        if ix < 0 or iy < 0 or ix >= nx or iy >= ny:
            return -1
        lev = round(v / dv) + zero
        b = round(th / bin_w) % nbins
        return ((ix * ny + iy) * nlev + lev) * nbins + b

    n_nodes, n_heap, n_sol, expansions, h_evals, p_evals, goal_node = counts[:7]
    G = reals[0]
    if n_nodes == 0:  # a fresh search: the start is node 0
        c0 = cell_of(start[0], start[1], start[2], start[3])
        g[c0] = 0.0
        best[c0] = 0
        st[0] = start
        parent[0], prim[0], cell[0] = -1, -1, c0
        h0 = heuristic(hk, hv, hm, hp, start[0], start[1], start[2], start[3])
        hval[0] = h0
        tn[0] = 0.0
        n_nodes = 1
        h_evals = 1
        start_key = _ana_key(G, 0.0, h0) if anytime else h0
        heap_k, heap_g, heap_c, n_heap = deeper_first_push(heap_k, heap_g, heap_c, n_heap, start_key, 0.0, 0)
    status = NO_PATH if goal_node < 0 else FOUND
    stopped = False  # at a limit, with OPEN kept as it is: ``resume`` goes on from exactly here
    last = n_samp - 1
    while n_heap > 0:
        # the limits are checked before the pop, only when the top would be expanded, so that a stopped search
        # leaves OPEN untouched (stale, dominated and goal entries are popped, as always, at no expansion)
        top = heap_c[0]
        if best[cell[top]] == top and not (anytime and heap_g[0] + hval[top] >= G):
            dx, dy = st[top, 0] - x_goal, st[top, 1] - y_goal
            if not (dx * dx + dy * dy <= tol2 and abs(st[top, 2]) <= v_goal):
                if expansions >= max_expansions:
                    status, stopped = (EXPANSION_LIMIT if goal_node < 0 else FOUND), True
                    break
                if (expansions & 255) == 0 and _now() - t0 > time_limit:
                    status, stopped = (TIME_LIMIT if goal_node < 0 else FOUND), True
                    break
        g_cur, cur, n_heap = deeper_first_pop(heap_k, heap_g, heap_c, n_heap)
        if best[cell[cur]] != cur:
            continue  # stale entry: its cell got a better node since
        if anytime and g_cur + hval[cur] >= G:
            continue  # e <= 1: cannot improve on G
        sx, sy, sv_, sth = st[cur, 0], st[cur, 1], st[cur, 2], st[cur, 3]
        dx, dy = sx - x_goal, sy - y_goal
        if dx * dx + dy * dy <= tol2 and abs(sv_) <= v_goal:
            goal_node = cur
            if not anytime:
                status = FOUND
                break
            G = g_cur
            # drop e <= 1, re-key the rest, and the bound: G / min(g + h) over what stays open
            m = 0
            lo = np.inf
            for i in range(n_heap):
                c = heap_c[i]
                if best[cell[c]] == c and heap_g[i] + hval[c] < G:
                    heap_k[m], heap_g[m], heap_c[m] = _ana_key(G, heap_g[i], hval[c]), heap_g[i], c
                    lo = min(lo, heap_g[i] + hval[c])
                    m += 1
            n_heap = 0
            kk, gg, cc = heap_k[:m].copy(), heap_g[:m].copy(), heap_c[:m].copy()
            for i in range(m):
                heap_k, heap_g, heap_c, n_heap = deeper_first_push(heap_k, heap_g, heap_c, n_heap, kk[i], gg[i], cc[i])
            if n_sol < MAX_SOLUTIONS:
                sol_i[n_sol] = expansions
                sol_f[n_sol, 0], sol_f[n_sol, 1] = _now() - t0, G
                sol_f[n_sol, 2] = G / lo if m > 0 and lo > 0 else 1.0
                n_sol += 1
            status = FOUND
            continue
        expansions += 1
        # the start's own first-step primitives (its exact speed, ``first_step``), the level's table after
        rows = root if cur == 0 else table[round(sv_ / dv) + zero]
        cth, sth_ = math.cos(sth), math.sin(sth)
        # the parent's clearance lower bounds, where an OBS check sweeps the path from it
        here = st[cur]  # the parent's state, from which the swept checks start
        sq0 = obs_clearance(sv, sm, sp, sx, sy) if sk == S_OBS else 0.0
        cq0 = obs_clearance(cv_, cm_, cp, sx, sy) if ck == S_OBS else 0.0
        if uk == U_FI:
            human_values_at(uv, um, up, humans, sx, sy, sv_, sth, tn[cur], at_parent)
        for p in range(n_prim):
            # the successor first (most are no improvement on their cell: no segment, no look-up for them)
            r0, r1 = rows[p, last, 0], rows[p, last, 1]
            ex = sx + cth * r0 - sth_ * r1
            ey = sy + sth_ * r0 + cth * r1
            ev = rows[p, last, 2]
            eth = sth + rows[p, last, 3]
            eth = (eth + math.pi) % (2.0 * math.pi) - math.pi
            nc = cell_of(ex, ey, ev, eth)
            if nc < 0:
                continue
            kx, ky, kth = ex, ey, eth  # the node's state: the segment's end, or its cell's centre
            if snap:  # (the segment itself is checked as driven)
                kx = (math.floor(ex / cell_m) + 0.5) * cell_m
                ky = (math.floor(ey / cell_m) + 0.5) * cell_m
                kth = wrap(round(eth / bin_w) * bin_w)
            step = dt
            if use_cost:
                step = dt * (1.0 + cost_w * interp2(cv, cm, kx, ky))
            ng = g_cur + step
            if ng >= g[nc]:
                continue
            for j in range(last):
                r0, r1 = rows[p, j, 0], rows[p, j, 1]
                samples[j, 0] = sx + cth * r0 - sth_ * r1
                samples[j, 1] = sy + sth_ * r0 + cth * r1
                samples[j, 2] = rows[p, j, 2]
                samples[j, 3] = sth + rows[p, j, 3]
            samples[last, 0], samples[last, 1], samples[last, 2], samples[last, 3] = ex, ey, ev, eth
            if sk != S_NONE:
                if sk == S_OBS:
                    bad = swept_unsafe(sv, sb, sm, sp, sq0, here, step_t, segment, 0, n_samp)
                else:
                    bad = first_unsafe(sk, sv, sb, sm, sp, segment, 0, n_samp)
                p_evals += bad + 1 if bad >= 0 else n_samp
                if bad >= 0:
                    continue
            if ck != S_NONE:
                bad = swept_unsafe(cv_, cb, cm_, cp, cq0, here, step_t, segment, 0, n_samp)
                p_evals += bad + 1 if bad >= 0 else n_samp
                if bad >= 0:
                    continue
            if uk != U_NONE and human_prunes(uk, uv, um, up, humans, at_parent, tn[cur], dt, samples, n_samp):
                continue
            h = heuristic(hk, hv, hm, hp, kx, ky, ev, kth)
            h_evals += 1
            if anytime and ng + h >= G:
                continue
            if n_nodes == st.shape[0]:
                st = np.concatenate((st, np.empty_like(st)))
                parent = np.concatenate((parent, np.empty_like(parent)))
                prim = np.concatenate((prim, np.empty_like(prim)))
                cell = np.concatenate((cell, np.empty_like(cell)))
                hval = np.concatenate((hval, np.empty_like(hval)))
                tn = np.concatenate((tn, np.empty_like(tn)))
            node = n_nodes
            n_nodes += 1
            st[node, 0], st[node, 1], st[node, 2], st[node, 3] = kx, ky, ev, kth
            parent[node], prim[node], cell[node], hval[node] = cur, p, nc, h
            tn[node] = tn[cur] + dt
            g[nc] = ng
            best[nc] = node
            key = _ana_key(G, ng, h) if anytime else ng + h
            heap_k, heap_g, heap_c, n_heap = deeper_first_push(heap_k, heap_g, heap_c, n_heap, key, ng, node)
    # the returned plan: the parent chain of the (last) goal node, as primitive indices from the start
    n_path = 0
    c = goal_node
    while c > 0:
        n_path += 1
        c = parent[c]
    prims = np.empty(n_path, np.int32)
    c = goal_node
    for i in range(n_path - 1, -1, -1):
        prims[i] = prim[c]
        c = parent[c]
    counts[0], counts[1], counts[2], counts[3] = n_nodes, n_heap, n_sol, expansions
    counts[4], counts[5], counts[6] = h_evals, p_evals, goal_node
    reals[0], reals[1] = G, _now() - t0
    return (status, stopped, prims,
            (g, best, st, parent, prim, cell, hval, tn, heap_k, heap_g, heap_c, sol_i, sol_f, counts, reals))


class SearchState(NamedTuple):
    """The compiled search's arrays, as it leaves them (``_search`` unpacks them in this order and returns them
    grown and updated): what a stopped search needs to go on (``resume``)."""

    g: np.ndarray  # the best cost found per lattice cell
    best: np.ndarray  # the node holding it (-1: none)
    st: np.ndarray  # nodes: (x index, y index, speed level, heading bin) as floats
    parent: np.ndarray
    prim: np.ndarray  # the primitive that reached the node
    cell: np.ndarray
    hval: np.ndarray  # the node's heuristic value
    tn: np.ndarray  # the node's time after the start
    heap_k: np.ndarray  # OPEN: keys, g, nodes
    heap_g: np.ndarray
    heap_c: np.ndarray
    sol_i: np.ndarray  # per solution: the expansions at which it was found
    sol_f: np.ndarray  # per solution: seconds, cost, proven bound
    counts: np.ndarray  # nodes, OPEN, solutions, expansions, heuristic evals, pruner evals, goal node
    reals: np.ndarray  # G (ANA*'s incumbent cost), seconds spent


def _fresh_state(n_cells: int, incumbent: float = math.inf) -> SearchState:
    """An empty search: no g per cell, room for 2^14 nodes and OPEN entries (both grow), no solutions, and
    ANA*'s incumbent cost G (``search``'s ``upper_bound``)."""
    cap = 1 << 14
    return SearchState(np.full(n_cells, np.inf), np.full(n_cells, -1, np.int64),
                       np.empty((cap, 4)), np.empty(cap, np.int64), np.empty(cap, np.int32), np.empty(cap, np.int64),
                       np.empty(cap), np.empty(cap), np.empty(cap), np.empty(cap), np.empty(cap, np.int64),
                       np.zeros(MAX_SOLUTIONS, np.int64), np.zeros((MAX_SOLUTIONS, 3)),
                       np.array([0, 0, 0, 0, 0, 0, -1], np.int64), np.array([incumbent, 0.0]))


def _dims(spec: LatticeSpec, bounds) -> np.ndarray:
    (x0, x1), (y0, y1) = bounds
    if x0 != 0.0 or y0 != 0.0:
        raise ValueError(f"lattice bounds must start at the origin (rooms do); got {bounds}")
    if not (math.isfinite(x1) and math.isfinite(y1) and x1 > 0 and y1 > 0):
        raise ValueError(f"lattice bounds must end at a finite width and height > 0 (the room's); got {bounds}")
    return np.array([math.ceil(x1 / spec.cell_m), math.ceil(y1 / spec.cell_m), spec.speed_levels,
                     spec.heading_bins], np.int64)


def replay(spec: LatticeSpec, table: np.ndarray, start: np.ndarray, prims: np.ndarray,
           costmap: Costmap = Costmap(), root: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """States and cost of following primitive indices from ``start`` (the same arithmetic as the search;
    ``root``: the first step's rows from an off-level start speed, ``dubins_lattice.first_step``)."""
    states = [np.asarray(start, np.float64)]
    cost = 0.0
    for i, p in enumerate(prims):
        x, y, v, th = states[-1]
        row = root[p, -1] if i == 0 and root is not None else table[spec.level(round(v / spec.dv) * spec.dv), p, -1]
        c, s = math.cos(th), math.sin(th)
        end = np.array([x + c * row[0] - s * row[1], y + s * row[0] + c * row[1], row[2], th + row[3]])
        end[3] = (end[3] + math.pi) % (2 * math.pi) - math.pi
        if spec.snap_states:
            end = snap(spec, end)
            end[3] = (end[3] + math.pi) % (2 * math.pi) - math.pi
        states.append(end)
        w = 0.0 if costmap.field is None else costmap.weight * float(interp2(*field_meta(costmap.field), end[0], end[1]))
        cost += spec.dt * (1.0 + w)
    return np.array(states), cost


def _check_ends(pruner: StaticPruner, start: np.ndarray, goal: Goal) -> None:
    """A clear error for a start the pruner drops or a goal it drops wholly (no search could reach it)."""
    name = pruner.name or "static"
    clearance = float(pruner.values(start[None])[0])
    if clearance <= 0.0:
        raise ValueError(f"start {tuple(start.round(3))} is already pruned by the {name} pruner (value "
                         f"{clearance:.3f} <= 0: in collision or inside the BRT); move the start")
    clearance = pruner.goal_clearance(goal)
    if clearance + 1e-9 <= 0.0:  # 1e-9: an interpolant may round above its corners' maximum
        raise ValueError(f"goal {goal.xy} (tolerance {goal.tolerance} m) is wholly pruned by the {name} pruner "
                         f"(value <= {clearance:.3f} at every state within it: in collision or inside the BRT), "
                         f"so no search can reach it; move the goal")


def search(spec: LatticeSpec, bounds, start, goal: Goal, heuristic_: Heuristic, *, pruners: Pruners = NO_PRUNERS,
           costmap: Costmap = Costmap(), budget: Budget = A_STAR, table: np.ndarray | None = None,
           keep_frontier: bool = False, upper_bound: float = math.inf) -> SearchResult:
    """Plan from ``start`` (x, y, v, θ) to ``goal`` over the lattice inside ``bounds`` ((0, W), (0, H)),
    pruning with ``pruners`` and stopping by ``budget`` (A* or ANA*).

    The start's speed need not be a level: its first step then uses ``first_step``'s primitives (the
    returned first control carries their adjusted acceleration), every later step the level table.
    ``keep_frontier``: a search stopped at its expansion or time limit keeps its OPEN list and nodes in the
    result's ``frontier``, for ``resume``.
    ``upper_bound`` (ANA* only): the cost of a plan already in hand, ANA*'s incumbent G from the start: only
    strictly cheaper plans are searched for (nodes with g + h >= G are pruned, the rest ordered by
    e = (G - g) / h, as after a solution), so the budget goes to improving on it; "no path" then means
    none cheaper exists (with an admissible heuristic).
    """
    if not (upper_bound > 0.0):
        raise ValueError(f"upper_bound must be a positive cost (inf: none), got {upper_bound!r}")
    if math.isfinite(upper_bound) and not budget.anytime:
        raise ValueError("upper_bound prunes ANA*'s search only; pass budget=Budget(anytime=True, ...)")
    static, collision, human = pruners
    start = np.asarray(start, np.float64)
    if start.shape != (4,) or not np.isfinite(start).all():
        raise ValueError(f"start must be a finite (x, y, v, θ), got {start!r}")
    dims = _dims(spec, bounds)
    (_, x1), (_, y1) = bounds
    for name, (x, y) in (("start", start[:2]), ("goal", goal.xy)):
        if not (0.0 <= x < x1 and 0.0 <= y < y1):
            raise ValueError(f"{name} {(float(x), float(y))} is outside the map [0, {x1}) × [0, {y1}); "
                             f"choose a position inside it")
    if collision.kind not in (S_NONE, S_OBS):
        raise ValueError(f"collision must be an OBS pruner (hj.pruners.obs_pruner), got {collision.name!r}")
    for pruner in (static, collision):
        if pruner.kind != S_NONE:
            _check_ends(pruner, start, goal)
    if spec.snap_states:
        start = snap(spec, start)
    table = primitive_table(spec) if table is None else table
    root, root_controls = first_step(spec, float(start[2]))
    goal_arr = np.array([goal.xy[0], goal.xy[1], goal.tolerance, goal.max_speed, spec.dv, spec.zero_level])
    cf = costmap.field if costmap.field is not None else GridField.empty(2)
    inputs = (start, goal_arr, table, root, (spec.dt, spec.cell_m, dims, spec.snap_states),
              (heuristic_.kind, _read_only(heuristic_.field), heuristic_.par),
              ((static.kind, _read_only(static.field), static.lower, static.par),
               (collision.kind, _read_only(collision.field), collision.lower, collision.par),
               (human.kind, _read_only(human.field), human.par, np.ascontiguousarray(human.humans, np.float64))),
              (costmap.field is not None, _read_only(cf), float(costmap.weight)))
    frontier = Frontier(spec, costmap, root_controls, budget, inputs, _fresh_state(int(np.prod(dims)), upper_bound))
    return _go_on(frontier, int(budget.max_expansions), keep_frontier)


@dataclass
class Frontier:
    """A search stopped at its limit, as it stands (every node, g per cell, OPEN, the solutions so far), with
    what it searches: ``resume`` goes on from here. Its arrays are the search's own: it goes on once."""

    spec: LatticeSpec
    costmap: Costmap
    root_controls: np.ndarray
    budget: Budget
    inputs: tuple  # the compiled search's start, goal, tables and bundles (``search`` builds them)
    state: SearchState | None  # the search's arrays as it left them; None once resumed (they go on once)
    expansions: int = 0  # spent when it stopped


def resume(frontier: Frontier, max_expansions: int) -> SearchResult:
    """Go on with a stopped search until ``max_expansions`` in all (or its time limit, counted from its
    start): the result, the counts and every solution are those of one search given that budget at once
    (tested), at the cost of the new expansions only. Why: a robot at rest in a static world waits for its
    plan, and its search should not start over each re-plan period (``hj.lattice_policy``)."""
    if frontier.state is None:
        raise ValueError("this frontier was resumed already (a search's arrays go on once); resume the frontier "
                         "of the newest result")
    if max_expansions < frontier.expansions:
        raise ValueError(f"max_expansions {max_expansions} is below the {frontier.expansions} expansions the "
                         "search has spent; give the total budget, not the increment")
    return _go_on(frontier, int(max_expansions), True)


def _go_on(frontier: Frontier, max_expansions: int, keep: bool) -> SearchResult:
    """Run the compiled search from ``frontier``'s state up to ``max_expansions`` in all; its SearchResult."""
    state, frontier.state = frontier.state, None
    budget = frontier.budget
    status, stopped, prims, arrays = _search(*frontier.inputs, (bool(budget.anytime), max_expansions,
                                                                  float(budget.time_limit_s)), state)
    state = SearchState(*arrays)
    counts, sol_i, sol_f = state.counts, state.sol_i, state.sol_f
    n_sol = int(counts[2])
    spec, costmap = frontier.spec, frontier.costmap
    start, _, table, root = frontier.inputs[:4]
    found = status == FOUND
    states, cost = replay(spec, table, start, prims, costmap, root) if found else (start[None], math.inf)
    controls = spec.controls[prims] if found else np.zeros((0, 2))
    if len(controls):
        controls[0] = frontier.root_controls[prims[0]]
    return SearchResult(
        status=STATUS[status], cost=cost, expansions=int(counts[3]),
        controls=controls, states=states, seconds=float(state.reals[1]),
        heuristic_evals=int(counts[4]), pruner_evals=int(counts[5]),
        solution_expansions=[int(e) for e in sol_i[:n_sol]], solution_seconds=[float(t) for t in sol_f[:n_sol, 0]],
        solution_costs=[float(c) for c in sol_f[:n_sol, 1]], solution_bounds=[float(b) for b in sol_f[:n_sol, 2]],
        frontier=replace(frontier, state=state, expansions=int(counts[3])) if keep and stopped else None)


def zero_heuristic() -> Heuristic:
    return Heuristic(H_ZERO, GridField.empty(2), np.zeros(8), "zero")
