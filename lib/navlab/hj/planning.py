"""HJ-guided planning runs of the paper's static experiments (Sec. VII-A..C): one task, one heuristic, one
pruner, A* or ANA*, then the paper's feasibility check.

``Planner`` binds params.yaml (``hj.planner``, ``hj.grids``), the room and the stored value functions;
``run`` plans one task and returns a ``TaskResult`` with what the tables report: success (a plan within
the budget that passes the densified check), expansions (to the first solution for ANA*, as the paper
records them), cost, and time. The feasibility check replays the plan's controls through every sub-step
of the integration the lattice was built with (``search.dubins_lattice.densify``: 8 points per search
sample) and requires positive exact clearance at each.

The pruners are the paper's: "OBS" checks the clearance at the states the search samples (the
conventional instantaneous check) and "BRT" the static BRT there (Eq. 12); neither looks between samples,
so a plan may fail the dense check, and the paper counts such a plan as a failure (Sec. VII-B, Table IV:
"densified trajectories intersected static obstacles"), as ``TaskResult.success`` does. Ours, as labelled
variant rows: "swept OBS" (the conservative swept check, ``search.lattice_fields.swept_unsafe``) and "BRT
+ swept OBS" (the BRT with that check as ``collision``); the swept check provably keeps the dense replay
clear, so a plan of theirs that fails it is a bug: ``run`` raises.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from navlab.core.params import Params
from navlab.hj.brt_margin import measure_static_brt_margin
from navlab.hj.grids import load_map_ttr, load_static_brt, load_ttr
from navlab.hj.guidance import dist_heuristic, map_dist_heuristic, map_ttr_heuristic, ttr_heuristic
from navlab.hj.pruners import clearance_field, obs_point_pruner, obs_pruner, static_brt_pruner
from navlab.maps.rooms import Room, load_room
from navlab.search.dubins_lattice import LatticeSpec, densify, primitive_table
from navlab.search.lattice_fields import GridField
from navlab.search.lattice_search import (
    NO_STATIC,
    Budget,
    Costmap,
    Goal,
    Pruners,
    SearchResult,
    search,
    zero_heuristic,
)

HEURISTICS = ("Dist", "map Dist", "TTR", "map TTR")
PRUNERS = ("none", "OBS", "BRT", "swept OBS", "BRT + swept OBS")  # the paper's, then ours (module docstring)
SWEPT = ("swept OBS", "BRT + swept OBS")


def lattice_spec(params: Params) -> LatticeSpec:
    lat, robot = params.hj.planner.lattice, params.hj.grids.robot
    for a in lat.accelerations:
        if not robot.accel_min <= a <= robot.accel_max:
            raise ValueError(f"hj.planner.lattice.accelerations: {a} is outside the robot's "
                             f"[{robot.accel_min}, {robot.accel_max}] (hj.grids.robot)")
    if max(abs(w) for w in lat.turn_rates) > robot.omega_max:
        raise ValueError(f"hj.planner.lattice.turn_rates exceed hj.grids.robot.omega_max = {robot.omega_max}")
    return LatticeSpec(lat.dt_s, lat.accelerations, lat.turn_rates, robot.v_max, lat.speed_levels,
                       lat.samples_per_step, lat.cell_m, lat.heading_bins, v_min=robot.v_min)


def costmap_field(room: Room, robot_radius: float, decay: float, resolution: float = 0.02) -> GridField:
    """Nav2-like inflation cost exp(−decay · clearance) (1 at contact) on the room raster."""
    sdf = clearance_field(room, resolution)
    values = np.exp(-decay * np.maximum(sdf.values.astype(np.float64) - robot_radius, 0.0)).astype(np.float32)
    return sdf._replace(values=values)


def plan_clearance(room: Room, robot_radius: float, spec: LatticeSpec, result: SearchResult) -> float:
    """The paper's feasibility check as a number: the smallest exact clearance (m) of the plan replayed
    densely under the dynamics (feasible where positive); -inf without a plan."""
    if not result.found:
        return -math.inf
    dense = densify(spec, result.states[0], result.controls)
    return float(room.signed_distance(dense[:, 0], dense[:, 1], robot_radius).min())


@dataclass
class TaskResult:
    heuristic: str
    pruner: str
    algorithm: str
    start: tuple[float, ...]
    goal: tuple[float, float]
    status: str
    found: bool
    clearance: float  # plan_clearance: the densified plan's smallest clearance (m)
    expansions: int  # A*: all; ANA*: to the first solution (the paper's measure), all when none
    total_expansions: int
    cost: float
    first_cost: float
    seconds: float
    bound: float
    min_speed: float = math.nan  # the plan's lowest speed (m/s; < 0: it reverses), NaN without a plan

    @property
    def feasible(self) -> bool:
        return self.clearance > 0.0

    @property
    def success(self) -> bool:
        return self.found and self.feasible


class Planner:
    """Everything one room's experiments share: lattice, value functions, costmap, BRT margin."""

    def __init__(self, params: Params, artifacts_dir: str | Path, room: str, *, costs: bool,
                 log=print, margin: float | None = None):
        self.params, self.room = params, load_room(room)
        self.p = params.hj.planner
        self.robot = params.hj.grids.robot
        self.spec = lattice_spec(params)
        self.table = primitive_table(self.spec)
        self.artifacts_dir = artifacts_dir
        self._ttr = load_ttr(params, artifacts_dir)
        self._log, self._margin, self._margin_report = log, None if margin is None else float(margin), None
        self._obs = obs_pruner(self.room, self.robot.radius_m)  # swept
        self._obs_point = obs_point_pruner(self.room, self.robot.radius_m)
        self.costmap = Costmap(costmap_field(self.room, self.robot.radius_m, self.p.cost_decay_per_m),
                               self.p.cost_weight) if costs else Costmap()

    @functools.cached_property
    def _brt(self):
        """The room's static BRT, read on first use: the forward-only car's rows (Tables I-II) prune with OBS
        and have no BRT of their own (``navlab.hj.grids.forward_only``)."""
        return load_static_brt(self.params, self.artifacts_dir, self.room.name)

    @property
    def margin(self) -> float:
        """Eq. 12's margin m of the BRT pruner, measured on first use (``hj.brt_margin``, cached by the
        ``hj_margins`` stage) unless the constructor was given one."""
        if self._margin is None:
            self._margin_report = measure_static_brt_margin(self.params, self.artifacts_dir, self.room.name,
                                                            self.p.brt_margin_refine, log=self._log)
            self._margin = float(self._margin_report["margin"])
        return self._margin

    @property
    def margin_report(self) -> dict | None:
        """How ``margin`` was measured (``hj.brt_margin``'s statistics); None when the constructor gave it."""
        _ = self.margin
        return self._margin_report

    def heuristic(self, name: str, goal_xy, tolerance: float):
        if name == "Dist":
            return dist_heuristic(goal_xy, self.robot.v_max, tolerance)
        if name == "map Dist":
            return map_dist_heuristic(self.room, goal_xy, self.robot.v_max, self.robot.radius_m, tolerance)
        if name == "TTR":
            return ttr_heuristic(self._ttr, goal_xy)
        if name == "map TTR":
            return map_ttr_heuristic(load_map_ttr(self.params, self.artifacts_dir), goal_xy)
        raise ValueError(f"heuristic {name!r}: choose one of {', '.join(HEURISTICS)}")

    def pruner(self, name: str):
        if name == "none":
            return NO_STATIC
        if name == "OBS":
            return self._obs_point
        if name == "swept OBS":
            return self._obs
        if name in ("BRT", "BRT + swept OBS"):
            return static_brt_pruner(self._brt, self.margin)
        raise ValueError(f"pruner {name!r}: choose one of {', '.join(PRUNERS)}")

    def collision(self, pruner: str):
        """The swept collision check a search with ``pruner`` adds: OBS's swept one for "BRT + swept OBS", none
        otherwise ("swept OBS" sweeps already; the paper's pruners check the sampled states only)."""
        return self._obs if pruner == "BRT + swept OBS" else NO_STATIC

    def run(self, start, goal_xy, heuristic: str, pruner: str, algorithm: str) -> tuple[TaskResult, SearchResult]:
        if algorithm not in ("A*", "ANA*"):
            raise ValueError(f"algorithm {algorithm!r}: use 'A*' or 'ANA*'")
        anytime = algorithm == "ANA*"
        tol = self.p.goal_tolerance_anastar_m if anytime else self.p.goal_tolerance_astar_m
        goal = Goal(tuple(map(float, goal_xy)), tol, self.p.goal_max_speed)
        res = search(self.spec, self.room.bounds, start, goal, self.heuristic(heuristic, goal_xy, tol),
                     pruners=Pruners(static=self.pruner(pruner), collision=self.collision(pruner)),
                     costmap=self.costmap, table=self.table,
                     budget=Budget(anytime=anytime, max_expansions=self.p.anastar_max_expansions if anytime else self.p.astar_max_expansions))
        clearance = plan_clearance(self.room, self.robot.radius_m, self.spec, res)
        if res.found and clearance <= 0.0 and pruner in SWEPT:
            raise AssertionError(f"{algorithm} with {heuristic} + {pruner} from {tuple(np.round(start, 3))} returned a "
                                 f"plan {-1000 * clearance:.2f} mm inside an obstacle by the dense check, which the "
                                 f"swept collision check rules out: a bug in the check or the replay")
        first = res.first_solution_expansions if anytime else None
        out = TaskResult(
            heuristic, pruner, algorithm, tuple(map(float, start)), goal.xy, res.status, res.found, clearance,
            int(first if first is not None else res.expansions), res.expansions, res.cost,
            res.solution_costs[0] if res.solution_costs else res.cost, res.seconds,
            res.solution_bounds[-1] if res.solution_bounds else (1.0 if res.found else math.inf),
            float(res.states[:, 2].min()) if res.found else math.nan)
        return out, res


    def heuristic_excess(self, name: str, tasks: list[tuple], pruner: str = "OBS") -> dict:
        """By how much heuristic ``name`` exceeds the lattice's true cost-to-go at each task's start
        (Dijkstra: h = 0, the same pruner, costmap and A* goal). The TTR is the continuous optimum, so it
        can exceed the lattice's cost only through its grid's interpolation error (issue 11 asks that it be
        measured): {starts Dijkstra solved, starts where h is above the cost, the largest excess in s}."""
        tol = self.p.goal_tolerance_astar_m
        over, worst, solved = 0, 0.0, 0
        for start, goal_xy in tasks:
            goal = Goal(tuple(map(float, goal_xy)), tol, self.p.goal_max_speed)
            res = search(self.spec, self.room.bounds, start, goal, zero_heuristic(),
                         pruners=Pruners(static=self.pruner(pruner), collision=self.collision(pruner)),
                         costmap=self.costmap, table=self.table,
                         budget=Budget(max_expansions=self.p.astar_max_expansions))
            if not res.found:
                continue
            solved += 1
            excess = float(self.heuristic(name, goal_xy, tol)(np.asarray(start, float)[None])[0]) - res.cost
            over += excess > 1e-9
            worst = max(worst, excess)
        return {"starts": solved, "over": over, "max_excess_s": worst}


def heading_tasks(start_xy, headings_deg) -> list[np.ndarray]:
    """Start states at rest with each initial heading."""
    return [np.array([start_xy[0], start_xy[1], 0.0, math.radians(h)]) for h in headings_deg]


def random_pairs(room: Room, robot_radius: float, n: int, min_distance: float, seed: int) -> list[tuple]:
    """Table V: start (at rest, random heading) and goal in free space, at least 0.3 m clear of obstacles,
    either ``min_distance`` apart or with the straight line between them blocked."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        xy = rng.uniform((0.0, 0.0), (room.width, room.height), size=(2, 2))
        if (room.signed_distance(xy[:, 0], xy[:, 1], robot_radius) < 0.3).any():
            continue
        line = xy[0] + np.linspace(0, 1, 50)[:, None] * (xy[1] - xy[0])
        blocked = (room.signed_distance(line[:, 0], line[:, 1], robot_radius) < 0).any()
        if blocked or np.linalg.norm(xy[1] - xy[0]) >= min_distance:
            out.append((np.array([xy[0, 0], xy[0, 1], 0.0, rng.uniform(-math.pi, math.pi)]), tuple(xy[1])))
    return out


def run_tasks(planner: Planner, tasks: list[tuple], heuristic: str, pruner: str, algorithm: str) -> list[TaskResult]:
    """Plan every (start, goal_xy) task with one heuristic, pruner and algorithm."""
    return [planner.run(start, goal, heuristic, pruner, algorithm)[0] for start, goal in tasks]
