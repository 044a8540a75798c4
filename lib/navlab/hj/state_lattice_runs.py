"""HJ-search's A* tasks (Tables I-V) on the true state lattice ``navlab.search.state_lattice`` (issue 26
item 2): Dijkstra, A* with Dist and A* with TTR from the same starts, where both A* costs must equal
Dijkstra's (the search graph is fixed, so A* with an admissible heuristic is exact on it).

Used by ``notebooks/hj/01_heuristics.ipynb`` (Table I's state-lattice rows, ``hj.tables.table1``) and by
``benchmarks/hj_state_lattice.py`` (Tables I-V).

TTR admissibility: the goal-frame TTR grid can exceed the lattice's cost-to-go through its interpolation
error. At the goal states themselves (cost-to-go 0) the search sets every h to 0
(``Lattice.heuristic_table``). Elsewhere, its largest excess δ over the lattice's exact cost-to-go is
measured on the *open* room (the same walls, no obstacles) with the task's lattice anchoring and goal
(``Lattice.cost_to_go``: backward Dijkstra over every lattice state); obstacles only remove primitives, so
cost-to-go in the task's room is >= the open room's and max(TTR − δ, 0) is admissible in any room. The raw
TTR's excess in the task's room is kept beside it (<= 0: admissible as it is).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from navlab.core.params import Params
from navlab.hj.grids import load_ttr
from navlab.hj.guidance import ttr_heuristic
from navlab.hj.planning import heading_tasks
from navlab.hj.pruners import clearance_field, field_error
from navlab.maps.rooms import load_room
from navlab.reach.lookup import TTRLookup
from navlab.search.lattice_fields import wrap
from navlab.search.state_lattice import (
    ANGLES,
    Car,
    Clearance,
    Goal,
    K,
    Lattice,
    LatticeSettings,
    Primitives,
    build_primitives,
    deflated,
    dist_heuristic,
)

TOLERANCE_S = 1e-9  # |A* cost − Dijkstra cost| within which they are the same (path sums round at ~1e-14 s)
DIJKSTRA, DIST, TTR = "Dijkstra (state lattice)", "A* w/ Dist (state lattice)", "A* w/ TTR (state lattice)"
METHODS = (DIJKSTRA, DIST, TTR)


@dataclass(frozen=True)
class LatticeRun:
    """One search of one task. ``start``: the task's (x, y, v, θ); ``heading_deg``: the lattice heading θ
    snapped to; ``delta``: the TTR deflation δ of the task's group; ``room_excess``: the raw TTR's largest
    excess over the cost-to-go in the task's room. The collision test is conservative (the swept disc
    clears the obstacles), so a plan found is a feasible plan: ``success`` = ``feasible`` = ``found``
    (the attributes ``hj.paper.summarise`` reads, as of ``hj.planning.TaskResult``)."""

    start: tuple[float, ...]
    heading_deg: float
    goal: tuple[float, float]
    found: bool
    cost: float
    expansions: int
    seconds: float
    delta: float
    room_excess: float

    @property
    def success(self) -> bool:
        return self.found

    @property
    def feasible(self) -> bool:
        return self.found

    @property
    def clearance(self) -> float:
        """Not measured (``summarise`` reads it only for a found plan that is not feasible: never here)."""
        return math.nan


def same_cost(reference: LatticeRun, run: LatticeRun) -> bool:
    """Does ``run`` return ``reference``'s (Dijkstra's) result: both without a plan, or both with costs
    within ``TOLERANCE_S``?"""
    return run.found == reference.found and (not reference.found or abs(run.cost - reference.cost) <= TOLERANCE_S)


@dataclass(frozen=True)
class Setup:
    """What every task of a table shares: settings, primitives, the room's and the open room's clearances,
    the TTR look-up and the A* goal's tolerance and top speed (hj.planner)."""

    settings: LatticeSettings
    primitives: Primitives
    room: Clearance
    open_room: Clearance
    ttr: TTRLookup
    goal_tolerance: float
    goal_speed: float


@dataclass(frozen=True)
class StateLatticeRuns:
    """One table's runs by method (``METHODS``), each over the same task list, and the lattice they ran on."""

    settings: LatticeSettings
    n_primitives: int
    results: dict[str, list[LatticeRun]]

    @property
    def headings(self) -> int:
        return K


def settings_of(params: Params) -> LatticeSettings:
    """The lattice for the paper's car (hj.grids.robot) at the module's default resolution."""
    return LatticeSettings(Car.from_params(params))


def clearance(name: str, radius: float) -> Clearance:
    """Room ``name``'s clearance raster with its interpolation error bound, for a robot of ``radius``."""
    field = clearance_field(load_room(name))
    return Clearance(field, field_error(field), radius)


def make_setup(params: Params, room: str, ttr: TTRLookup, primitives: Primitives | None = None) -> Setup:
    """The ``Setup`` for tasks in ``room``; ``primitives``: built from ``settings_of(params)`` when None."""
    settings, radius = settings_of(params), params.hj.grids.robot.radius_m
    p = params.hj.planner
    return Setup(settings, build_primitives(settings) if primitives is None else primitives,
                 clearance(room, radius), clearance("open", radius), ttr, p.goal_tolerance_astar_m, p.goal_max_speed)


def run_group(setup: Setup, start_xy, goal_xy, starts) -> dict[str, list[LatticeRun]]:
    """One start position and goal with several start states (at ``start_xy``): δ from the open room, then
    Dijkstra, A* w/ Dist and A* w/ TTR (deflated by δ) from each start; the runs by method."""
    goal = Goal(tuple(map(float, goal_xy)), setup.goal_tolerance, setup.goal_speed)
    ttr = ttr_heuristic(setup.ttr, goal.xy)
    open_lattice = Lattice(setup.settings, setup.open_room, start_xy, setup.primitives)
    delta = max(open_lattice.excess(ttr, goal, open_lattice.cost_to_go(goal)), 0.0)
    lattice = Lattice(setup.settings, setup.room, start_xy, setup.primitives)
    room_excess = lattice.excess(ttr, goal, lattice.cost_to_go(goal))
    heuristics = {DIJKSTRA: None, DIST: dist_heuristic(goal, setup.settings.car.v_max), TTR: deflated(ttr, delta)}
    runs: dict[str, list[LatticeRun]] = {m: [] for m in METHODS}
    for start in starts:
        start = tuple(map(float, start))
        heading = math.degrees(ANGLES[int(np.argmin(np.abs(wrap(ANGLES - start[3]))))])
        for method, h in heuristics.items():
            plan = lattice.search(start, goal, h)
            runs[method].append(LatticeRun(start, heading, goal.xy, plan.found, plan.cost, plan.expansions,
                                           plan.seconds, delta, room_excess))
    return runs


def run_table(params: Params, artifacts_dir, table, ttr: TTRLookup | None = None,
              primitives: Primitives | None = None) -> StateLatticeRuns:
    """One of Tables I-IV's task sets (``params.hj.planner.tableN``: room, start_xy, goal_xy, headings_deg;
    starts at rest, headings snapped to the lattice's 16) on the state lattice; ``ttr``: the TTR look-up
    (loaded from ``artifacts_dir`` when None)."""
    ttr = load_ttr(params, artifacts_dir) if ttr is None else ttr
    setup = make_setup(params, table.room, ttr, primitives)
    results = run_group(setup, table.start_xy, table.goal_xy, heading_tasks(table.start_xy, table.headings_deg))
    return StateLatticeRuns(setup.settings, len(setup.primitives.cost), results)
