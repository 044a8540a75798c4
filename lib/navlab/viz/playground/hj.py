"""The HJ-search playground (issue 28, item 3): "what does the HJ-guided planner do if I start *here*?"

A person picks one of the rooms and set-ups of Tables I-IX, clicks the robot's start and goal on the room
(and places humans: position by click, heading by a slider) and sees, at the robot's heading and a chosen
speed, the TTR heuristic to the goal, the static BRT and the human-robot BRT slices, the lattice plan
(status, expansions, search time) and which successors each pruner removes; a button runs the closed loop
for a few simulated seconds and plays it back. Everything is computed by the library the HJ notebooks use:
``hj.scenarios.ClosedLoop`` (heuristics, pruners with the measured BRT margin, the receding-horizon
policy), ``search.lattice_search.search``, ``hj.pruners.human_pruner``, ``hj.receding_horizon.run_patrol``
and ``viz.hj_closed_loop.patrol_gif``. This module keeps the choices, checks them and caches what they give.

Why a census of removed successors and not the search's own: the compiled search counts expansions but
does not report which nodes its pruners dropped. The census asks each pruner, exactly as the search asks it,
about every lattice successor of the drawn slice (every cell at the robot's heading and the slice speed)
and of the plan's own states, so it shows where and how much each one prunes.
"""

from __future__ import annotations

import contextlib
import dataclasses
import html
import math
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import ipywidgets as widgets
import matplotlib
import numpy as np
from matplotlib import pyplot as plt
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from navlab.core.io import DataError
from navlab.core.params import Params, load_params
from navlab.hj.brt_margin import MARGINS_SUBDIR
from navlab.hj.grids import grid_path, load_human_brt, load_static_brt, specs
from navlab.hj.humans import StraightWalker
from navlab.hj.planning import plan_clearance, random_pairs
from navlab.hj.pruners import human_pruner
from navlab.hj.receding_horizon import Run, Trip, run_patrol
from navlab.hj.scenarios import ClosedLoop
from navlab.maps.rooms import Room, load_room
from navlab.search.dubins_lattice import place, primitive_table
from navlab.search.lattice_search import (
    NO_HUMAN,
    Budget,
    Goal,
    Pruners,
    SearchResult,
    StaticPruner,
    search,
)
from navlab.viz.hj_closed_loop import patrol_gif
from navlab.viz.hj_scenes import brt_scene_html
from navlab.viz.playground.common import (
    Memo,
    PlaygroundView,
    UserError,
    figure_bytes,
    one_line,
    require_built,
)

MODES = ("start", "goal", "human")
HEURISTICS = ("TTR", "Dist")
STATIC = ("OBS", "BRT")
HUMAN_MODES = {"FI-BRT": "fi", "FS-BRT": "fs", "OBS": "obs"}  # as Tables VI and IX (hj.scenarios.HUMAN_ROWS)
ALGORITHMS = ("A*", "ANA*")
MAX_HUMANS = 3
FIELD_M = 0.05  # resolution of the drawn fields (m)
AXES = ((0.03, 0.1, 0.44, 0.8), (0.53, 0.1, 0.44, 0.8))  # the two panels' boxes, figure fractions (browser test)
COLORBAR = (0.475, 0.1, 0.008, 0.8)
FIGSIZE = (11.0, 3.4)  # inches: each panel's box has the rooms' 9.6 × 5.4 aspect, so a click maps linearly
MARKS = {"OBS": ("k", "."), "BRT": ("tab:red", "x"), "humans": ("tab:orange", "+")}


@dataclass(frozen=True)
class Human:
    x: float
    y: float
    heading_deg: float


@dataclass(frozen=True)
class Setup:
    """Everything a plan depends on (hashable: the memo's key)."""

    room: str
    start: tuple[float, float, float]  # x, y, heading (deg); the robot starts at rest, as in the tables
    goal: tuple[float, float]
    humans: tuple[Human, ...] = ()
    heuristic: str = "TTR"
    static: str = "OBS"
    human_mode: str = "FI-BRT"
    algorithm: str = "A*"


@dataclass(frozen=True, eq=False)
class PlanOutcome:
    """One search: its result, the densified plan's clearance (m; > 0 feasible)."""

    result: SearchResult
    clearance: float


@dataclass(frozen=True, eq=False)
class Census:
    """Per pruner: the cells (K, 2) of the slice whose successors it removes (some), how many successors it
    removes of ``total`` on the slice, and how many of the plan states' successors (of ``plan_total``)."""

    cells: dict[str, np.ndarray]
    removed: dict[str, int]
    total: int
    on_plan: dict[str, int]
    plan_total: int


@dataclass(frozen=True, eq=False)
class Fields:
    """The drawn slices at (θ, v) on a FIELD_M raster, [row = y, col = x]: TTR to the goal (s), the static
    BRT's value minus its margin (NaN where the room has none), the human-robot BRT's least value over
    the humans (NaN without humans), and the obstacle mask."""

    ttr: np.ndarray
    static: np.ndarray
    human: np.ndarray
    blocked: np.ndarray


@dataclass(frozen=True, eq=False)
class Replay:
    """A closed-loop run (stopped or not) and how it ended, with its playback as GIF bytes."""

    run: Run
    outcome: str
    gif: bytes


class StopLoop(Exception):
    """Raised inside the closed loop when the person pressed Stop."""


def scenarios(params: Params) -> dict[str, tuple[str, Setup]]:
    """The set-ups of the HJ notebooks' tables, by key: (label, setup). Table VII times calls (no set-up)."""
    p, d = params.hj.planner, params.hj.dynamic
    f, z, t8, t9 = d.table6.face_to_face, d.table6.zig_zag, d.table8, d.table9
    hallway, dense = load_room("long_hallway"), load_room("dense_room")
    pair = random_pairs(load_room(p.table5.room), params.hj.grids.robot.radius_m, 1, p.table5.min_distance_m,
                        params.hj.seed)[0]

    def towards(a, b) -> float:
        return math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))

    def human(a, b) -> Human:
        return Human(float(a[0]), float(a[1]), round(towards(a, b)))

    def xy(point) -> tuple[float, float]:
        return float(point[0]), float(point[1])

    return {
        "table1": ("Tables I-II: heuristics (simulation room)",
                   Setup(p.table2.room, (*xy(p.table2.start_xy), 0.0), xy(p.table2.goal_xy), heuristic="TTR")),
        "table3": ("Tables III-IV: OBS vs BRT pruning (simulation room)",
                   Setup(p.table4.room, (*xy(p.table4.start_xy), 30.0), xy(p.table4.goal_xy), static="BRT")),
        "table5": ("Table V: a random start-goal pair (simulation room)",
                   Setup(p.table5.room, (*xy(pair[0]), round(math.degrees(pair[0][3]))), xy(pair[1]))),
        "table6_face": ("Table VI: Face-to-Face (open room)",
                        Setup(d.table6.room, (*xy(f.robot_start), float(f.robot_start[2])), xy(f.robot_goal),
                              (human(f.human_start, f.human_goal),))),
        "table6_zigzag": ("Table VI: Zig-Zag (open room)",
                          Setup(d.table6.room, (*xy(z.robot_start), float(z.robot_start[2])), xy(z.robot_goals[0]),
                                (human(z.human_start, z.human_goal),))),
        "table8_hallway": ("Table VIII: Long Hallway A → B",
                           Setup("long_hallway", (*hallway.goals["A"], t8.start_heading_deg), hallway.goals["B"],
                                 static="BRT")),
        "table8_dense": ("Table VIII: Dense Room A → B",
                         Setup("dense_room", (*dense.goals["A"], t8.start_heading_deg), dense.goals["B"],
                               static="BRT")),
        "table9": ("Table IX: patrolling humans (open room)",
                   Setup(t9.room, (*xy(t9.robot_goals[0]), t9.robot_start_heading_deg), xy(t9.robot_goals[1]),
                         tuple(human(pois[0], pois[1]) for pois in t9.human_pois))),
    }


def walk_goal(room: Room, human: Human, radius: float) -> tuple[float, float]:
    """Where a human walking straight along its heading meets the walls (a StraightWalker's goal)."""
    c, s = math.cos(math.radians(human.heading_deg)), math.sin(math.radians(human.heading_deg))
    lo, hi = np.array([radius, radius]), np.array([room.width - radius, room.height - radius])
    reach = [((hi[k] if d > 0 else lo[k]) - (human.x, human.y)[k]) / d for k, d in enumerate((c, s)) if abs(d) > 1e-9]
    t = max(0.0, min(reach))
    return human.x + t * c, human.y + t * s


class HJPlayground:
    """The playground's state and rules, without widgets: the set-up (room, start, goal, humans, heuristic,
    pruners, algorithm), the slice speed, and outcomes cached per set-up. Every mutator checks its input
    first (a plan is searched before the change is kept) and raises :class:`UserError` (one line) without
    changing anything when it is refused."""

    def __init__(self, params: Params, artifacts_dir: str | Path):
        self.params, self.artifacts_dir = params, Path(artifacts_dir)
        self.robot, self.human = params.hj.grids.robot, params.hj.grids.human
        self.loop = ClosedLoop(params, artifacts_dir, log=lambda message: None)
        self.human_brt = load_human_brt(params, artifacts_dir)  # missing: DataError naming `hj_grids`
        self.brt_rooms = tuple(params.hj.grids.rooms)
        for room in self.brt_rooms:
            load_static_brt(params, artifacts_dir, room)
            margin = self.artifacts_dir / MARGINS_SUBDIR / f"brt_margin_{room}.json"
            if not margin.is_file():
                raise DataError(f"{margin} is missing; build it with `python -m navlab artifacts build --only "
                                f"hj_margins` (or `dvc repro hj_margins`)")
        self.scenarios = scenarios(params)
        self.table = primitive_table(self.loop.spec)
        self.setup: Setup | None = None
        self.scenario: str | None = None
        self.speed = 0.5  # m/s: the slice's speed (the robot itself starts at rest)
        self.rooms = Memo(load_room)
        self.plans = Memo(self._plan)
        self.fields = Memo(self._fields, size=16)
        self.censuses = Memo(self._census, size=16)
        self.scenes = Memo(self._scene, size=4)

    @classmethod
    def load(cls, profile: str, artifacts_dir: str | Path, data_dir: str | Path = "data") -> HJPlayground:
        """The playground on ``profile``'s value functions and BRT margins; missing ones stop with one line
        naming them all and the command that builds them (``data_dir``: only for that command)."""
        params = load_params(profile)
        require_built([*(("hj_grids", grid_path(artifacts_dir, spec.name)) for spec in specs(params)),
                       *(("hj_margins", Path(artifacts_dir, MARGINS_SUBDIR, f"brt_margin_{room}.json"))
                         for room in params.hj.grids.rooms)], params.profile, data_dir, artifacts_dir)
        return cls(params, artifacts_dir)

    # --- choices ------------------------------------------------------------------------------------
    def choose_scenario(self, key: str | None) -> None:
        if key not in self.scenarios:
            raise UserError(f"choose a set-up: one of {', '.join(self.scenarios)} (got {key!r})")
        self._commit(self.scenarios[key][1])
        self.scenario = key

    def click(self, mode: str, x: float, y: float) -> None:
        """A click on the room in ``mode``: the start (keeps its heading), the goal, or a new human."""
        if mode not in MODES:
            raise UserError(f"click mode {mode!r}: one of {', '.join(MODES)}")
        setup = self._chosen()
        where = self._on_floor(mode, x, y)
        if mode == "start":
            self._commit(dataclasses.replace(setup, start=(*where, setup.start[2])))
        elif mode == "goal":
            self._commit(dataclasses.replace(setup, goal=where))
        else:
            self.add_human(*where)

    def add_human(self, x: float, y: float, heading_deg: float = 180.0) -> None:
        setup = self._chosen()
        if len(setup.humans) >= MAX_HUMANS:
            raise UserError(f"at most {MAX_HUMANS} humans: clear them before placing another")
        x, y = self._on_floor("human", x, y)
        gap = math.hypot(x - setup.start[0], y - setup.start[1]) - self.robot.radius_m - self.human.radius_m
        if gap <= 0:
            raise UserError(f"a human at ({x:.2f}, {y:.2f}) stands on the robot ({-gap:.2f} m overlap): "
                            "place it clear of the start")
        self._commit(dataclasses.replace(setup, humans=(*setup.humans, Human(x, y, self._angle(heading_deg)))))

    def set_heading(self, heading_deg: float) -> None:
        """The robot's start heading; the drawn slices follow it."""
        setup = self._chosen()
        self._commit(dataclasses.replace(setup, start=(*setup.start[:2], self._angle(heading_deg))))

    def set_human_heading(self, heading_deg: float) -> None:
        """The heading of the human placed last (it walks that way in the closed loop, and FI/FS-BRT predict it)."""
        setup = self._chosen()
        if not setup.humans:
            raise UserError("no human to turn: place one first (mode 'human', then click the room)")
        last = dataclasses.replace(setup.humans[-1], heading_deg=self._angle(heading_deg))
        self._commit(dataclasses.replace(setup, humans=(*setup.humans[:-1], last)))

    def clear_humans(self) -> None:
        self._commit(dataclasses.replace(self._chosen(), humans=()))

    def set_speed(self, speed: float) -> None:
        """The slices' speed (m/s; the BRTs grow with it): a lattice speed level, negative reversing."""
        dv = self.loop.spec.dv
        if not (math.isfinite(speed) and self.robot.v_min <= speed <= self.robot.v_max):
            raise UserError(f"slice speed {speed}: choose {self.robot.v_min:g} to {self.robot.v_max:g} m/s")
        self.speed = round(speed / dv) * dv

    def set_option(self, name: str, value: str) -> None:
        """``heuristic``, ``static``, ``human_mode`` or ``algorithm``."""
        choices = {"heuristic": HEURISTICS, "static": STATIC, "human_mode": tuple(HUMAN_MODES),
                   "algorithm": ALGORITHMS}
        if name not in choices or value not in choices[name]:
            raise UserError(f"{name} {value!r}: choose one of {', '.join(choices.get(name, ()))}")
        self._commit(dataclasses.replace(self._chosen(), **{name: value}))

    # --- what they give -----------------------------------------------------------------------------
    @property
    def room(self) -> Room:
        return self.rooms(self._chosen().room)

    def plan(self) -> PlanOutcome:
        return self.plans(self._chosen())

    def slice_fields(self) -> Fields:
        s = self._chosen()
        return self.fields(s.room, s.goal, s.start[2], self.speed, s.humans, s.heuristic)

    def census(self) -> Census:
        s = self._chosen()
        return self.censuses(s, self.speed)

    def brt_scene(self) -> str:
        """Static meshcat HTML of the room's static BRT at the slice speed, in 3D: the zero level set over
        (x, y, θ) with θ as height (the scene notebook 00 writes, for the room and speed chosen here)."""
        return self.scenes(self._chosen().room, self.speed)

    def describe(self) -> str:
        s, out = self._chosen(), self.plan()
        r = out.result
        humans = f", {len(s.humans)} human(s) by {s.human_mode}" if s.humans else ""
        cost = f", {r.cost:.1f} s to the goal" if r.found else ""
        if r.found and out.clearance <= 0:
            cost += (f", but it fails the dense check ({-1000 * out.clearance:.0f} mm into an obstacle between the "
                     f"sampled states): the paper counts it a failure, the closed loop does not drive it")
        return (f"{s.algorithm} with {s.heuristic} + {s.static}{humans}: {r.status}{cost}, "
                f"{r.expansions:,} expansions in {1000 * r.seconds:.0f} ms")

    def closed_loop(self, seconds: float, progress: Callable[[float], None] | None = None,
                    stop: threading.Event | None = None) -> Replay:
        """The set-up driven by the receding-horizon loop of Tables VI-IX (``ClosedLoop.policy``, re-plans at
        its rate and budget, no pose noise) for at most ``seconds`` simulated; ``progress(t)`` about every
        half simulated second; ``stop`` set: the run ends there (a Stop press) and what was driven is kept."""
        if not (math.isfinite(seconds) and 0 < seconds <= 120):
            raise UserError(f"closed loop for {seconds} s: choose 1 to 120 simulated seconds")
        s, room = self._chosen(), self.room
        mode = HUMAN_MODES[s.human_mode] if s.humans else "none"
        self._check_pairing(s)
        policy = self.loop.policy(room, s.heuristic, s.static, mode)
        settings = dataclasses.replace(self.loop.settings(0.0), trip_timeout_s=float(seconds))
        walkers = [StraightWalker((h.x, h.y), walk_goal(room, h, self.human.radius_m), self.human.speed)
                   for h in s.humans]
        tick = 1.0 / settings.control_hz
        driven: list[np.ndarray] = []  # (t, x, y) at each check; the first is run_patrol's start check

        def probe(x, y):  # the simulator's collision check, called once a tick: progress, Stop, the path so far
            driven.append(np.array([len(driven) * tick, float(x), float(y)]))
            seen.append(np.array([w.position for w in walkers], float).reshape(-1, 2))
            if stop is not None and stop.is_set():
                raise StopLoop
            if progress is not None and len(driven) % max(1, round(0.5 / tick)) == 0:
                progress(len(driven) * tick)
            return room.obstacle_distance(x, y)

        start = np.array([s.start[0], s.start[1], 0.0, math.radians(s.start[2])])
        rng = np.random.default_rng(self.params.hj.dynamic.seed)
        seen: list[np.ndarray] = []  # the humans' positions at each check
        try:
            run = run_patrol(policy, probe, start, [s.goal], walkers, settings, rng)
            trip = run.trips[0]
            left = math.hypot(*(np.asarray(s.goal) - run.trajectory[-1][1:3]))
            ended = f"still {left:.1f} m from the goal at the {seconds:g} s bound" if trip.outcome == "timeout" \
                else f"{trip.outcome} after {trip.time_s:.1f} s"
            outcome = f"{ended}, {trip.human_contacts} human contact(s)"
        except StopLoop:
            run = stopped_run(np.asarray(driven[1:]).reshape(-1, 3), seen[1:], start, s.goal)
            outcome = f"stopped at {run.trajectory[-1][0]:.1f} s"
        return Replay(run, outcome, self._gif(room, run))

    # --- internals ----------------------------------------------------------------------------------
    def _gif(self, room: Room, run: Run) -> bytes:
        c = self.params.hj.dynamic.closed_loop
        with tempfile.TemporaryDirectory() as tmp, plt.ioff():
            path = patrol_gif(Path(tmp) / "replay.gif", room, run, self.human_brt, self.robot.radius_m,
                              self.human.radius_m, c.control_hz, sample_hz=4.0, fps=8.0,
                              title="closed loop (2x real time): orange = human BRT under the car")
            return path.read_bytes()

    def _chosen(self) -> Setup:
        if self.setup is None:
            raise UserError("choose a set-up first (the menu)")
        return self.setup

    def _commit(self, setup: Setup) -> None:
        """Keep ``setup`` if a plan can be searched on it; a search that refuses it says why in one line."""
        self._check_pairing(setup)
        try:
            self.plans(setup)
        except ValueError as err:  # the search's own refusals: a start or goal its pruners drop
            raise UserError(one_line(err).removeprefix("ValueError: ")) from None
        self.setup = setup

    def _check_pairing(self, setup: Setup) -> None:
        if setup.static == "BRT" and setup.room not in self.brt_rooms:
            raise UserError(f"the {setup.room} room has no static BRT (hj.grids.rooms: {', '.join(self.brt_rooms)}); "
                            "its walls are pruned by OBS")
        if setup.humans and setup.human_mode == "OBS" and setup.static != "OBS":
            raise UserError("the OBS human pruner adds the humans to the OBS field: choose the OBS static pruner")

    def _on_floor(self, what: str, x, y) -> tuple[float, float]:
        """(x, y) if a robot (or human) of its radius fits there, else a UserError saying why."""
        try:
            x, y = float(x), float(y)
        except (TypeError, ValueError):
            raise UserError(f"the {what} needs numbers, got ({x!r}, {y!r})") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise UserError(f"the {what} ({x}, {y}) is not a position: click inside the room")
        room = self.room
        if not (0 <= x < room.width and 0 <= y < room.height):
            raise UserError(f"the {what} ({x:.2f}, {y:.2f}) is off the map [0, {room.width}) × [0, {room.height})")
        radius = self.human.radius_m if what == "human" else self.robot.radius_m
        clearance = float(room.signed_distance(x, y, radius))
        if clearance <= 0:
            raise UserError(f"the {what} ({x:.2f}, {y:.2f}) is inside an obstacle or within its radius "
                            f"{radius} m of one: click free floor")
        return round(x, 3), round(y, 3)

    @staticmethod
    def _angle(heading_deg) -> float:
        try:
            heading = float(heading_deg)
        except (TypeError, ValueError):
            raise UserError(f"heading {heading_deg!r} is not a number of degrees") from None
        if not math.isfinite(heading):
            raise UserError(f"heading {heading_deg} is not a number of degrees")
        return (heading + 180.0) % 360.0 - 180.0

    def _pruners(self, setup: Setup) -> Pruners:
        """The search's pruners as the closed loop's policy builds them: the paper's static and human pruners
        alone, no swept collision check (humans frozen at their placed positions, predicted along their headings
        for ``human_prediction_s``)."""
        room = self.rooms(setup.room)
        static = self.loop.static_pruner(room, setup.static)
        human = NO_HUMAN
        if setup.humans and setup.human_mode == "OBS":
            static = with_human_discs(static, setup.humans, self.human.radius_m)
        elif setup.humans:
            xy, velocities = self._human_arrays(setup.humans)
            human = human_pruner(self.human_brt, xy, HUMAN_MODES[setup.human_mode], self.loop.fi, velocities,
                                 self.params.hj.dynamic.closed_loop.human_prediction_s)
        return Pruners(static=static, human=human)

    def _human_arrays(self, humans) -> tuple[np.ndarray, np.ndarray]:
        xy = np.array([(h.x, h.y) for h in humans], float).reshape(-1, 2)
        heading = np.radians([h.heading_deg for h in humans])
        return xy, self.human.speed * np.c_[np.cos(heading), np.sin(heading)]

    def _plan(self, setup: Setup) -> PlanOutcome:
        p = self.params.hj.planner
        anytime = setup.algorithm == "ANA*"
        pruners = self._pruners(setup)
        tolerance = p.goal_tolerance_anastar_m if anytime else p.goal_tolerance_astar_m
        room = self.rooms(setup.room)
        start = np.array([setup.start[0], setup.start[1], 0.0, math.radians(setup.start[2])])
        result = search(self.loop.spec, room.bounds, start, Goal(setup.goal, tolerance, p.goal_max_speed),
                        self.loop.heuristic_for(setup.heuristic)(setup.goal),
                        pruners=pruners, table=self.table,
                        budget=Budget(anytime=anytime, max_expansions=p.anastar_max_expansions if anytime else p.astar_max_expansions))
        return PlanOutcome(result, plan_clearance(room, self.robot.radius_m, self.loop.spec, result))

    def _scene(self, room_name: str, speed: float) -> str:
        if room_name not in self.brt_rooms:
            raise UserError(f"room {room_name} has no static BRT (hj.grids.rooms: {', '.join(self.brt_rooms)})")
        brt = load_static_brt(self.params, self.artifacts_dir, room_name)
        return brt_scene_html(self.rooms(room_name), np.asarray(brt.stored.values), brt.grid, speed)

    def _fields(self, room_name: str, goal, heading_deg: float, speed: float, humans, heuristic: str) -> Fields:
        room = self.rooms(room_name)
        xs = np.arange(FIELD_M / 2, room.width, FIELD_M)
        ys = np.arange(FIELD_M / 2, room.height, FIELD_M)
        x, y = np.meshgrid(xs, ys)
        states = np.stack([x.ravel(), y.ravel(), np.full(x.size, speed), np.full(x.size, math.radians(heading_deg))], 1)
        shape = x.shape
        ttr = self.loop.heuristic_for(heuristic)(goal)(states).reshape(shape)
        static = np.full(shape, np.nan)
        if room_name in self.brt_rooms:
            static = self.loop.static_pruner(room, "BRT").values(states).reshape(shape)
        human = np.full(shape, np.nan)
        if humans:
            xy, _ = self._human_arrays(humans)
            human = np.min([self.human_brt(states, np.broadcast_to(h, (len(states), 2))) for h in xy], axis=0)
            human = human.reshape(shape)
        return Fields(ttr, static, human, room.obstacle_distance(x, y) < 0)

    def _census(self, setup: Setup, speed: float) -> Census:
        """Each pruner on every successor of the slice's lattice cells (free ones) and of the plan's states."""
        spec, room = self.loop.spec, self.rooms(setup.room)
        c = spec.cell_m
        x, y = np.meshgrid(np.arange(c / 2, room.width, c), np.arange(c / 2, room.height, c))
        cells = np.c_[x.ravel(), y.ravel()]
        cells = cells[room.signed_distance(cells[:, 0], cells[:, 1], self.robot.radius_m) > 0]
        level = spec.level(round(speed / spec.dv) * spec.dv)
        rows = place(self.table[level], (0.0, 0.0, 0.0, math.radians(setup.start[2])))  # (P, S, 4) at the origin
        parents = np.c_[cells, np.full(len(cells), level * spec.dv), np.full(len(cells), math.radians(setup.start[2]))]
        plan = self.plans(setup).result.states[:-1]  # the plan's states that have a successor on it
        plan_samples = np.array([place(self.table[spec.level(round(st[2] / spec.dv) * spec.dv)], st) for st in plan])
        plan_samples = plan_samples.reshape(len(plan), *rows.shape)
        slice_samples = rows[None] + np.c_[cells, np.zeros((len(cells), 2))][:, None, None, :]
        slice_in, plan_in = self._inside(slice_samples, room), self._inside(plan_samples, room)
        removed, where, on_plan = {}, {}, {}
        for name, check in self._census_checks(setup).items():
            hit = self._hits(check, parents, slice_samples) & slice_in
            removed[name], where[name] = int(hit.sum()), cells[hit.any(axis=1)]
            on_plan[name] = int((self._hits(check, plan, plan_samples) & plan_in).sum()) if len(plan) else 0
        return Census(where, removed, int(slice_in.sum()), on_plan, int(plan_in.sum()))

    def _census_checks(self, setup: Setup) -> dict[str, Callable]:
        """name -> check(parents (N, 4), samples (N, S, 4), durations (N,)) -> (N,) removed, as the search asks."""
        room = self.rooms(setup.room)
        obs = self.loop.static_pruner(room, "OBS")
        checks = {"OBS": lambda p, s, d: obs(s)}  # the paper's instantaneous check at the sampled states
        if setup.room in self.brt_rooms:
            brt = self.loop.static_pruner(room, "BRT")
            checks["BRT"] = lambda p, s, d: brt(s)
        if setup.humans:
            pruners = self._pruners(setup)
            static, human = pruners.static, pruners.human
            if setup.human_mode == "OBS":
                checks["humans"] = lambda p, s, d: static(s)
            else:
                checks["humans"] = lambda p, s, d: human(p, s, np.zeros(len(p)), d)
        return checks

    @staticmethod
    def _inside(samples: np.ndarray, room: Room) -> np.ndarray:
        """(N, P) successors whose end lies in the room (the search drops the others before any pruner)."""
        ends = samples[:, :, -1]
        return (ends[..., 0] >= 0) & (ends[..., 0] < room.width) & (ends[..., 1] >= 0) & (ends[..., 1] < room.height)

    def _hits(self, check, parents: np.ndarray, samples: np.ndarray) -> np.ndarray:
        """(N, P): which successors of each parent ``check`` drops (one call over all of them)."""
        n, m = samples.shape[:2]
        flat = samples.reshape(n * m, *samples.shape[2:])
        return np.asarray(check(np.repeat(parents, m, axis=0), flat, np.full(n * m, self.loop.spec.dt))).reshape(n, m)


def with_human_discs(obs: StaticPruner, humans, radius: float) -> StaticPruner:
    """The OBS pruner with the humans' discs in its clearance field (the closed loop's "obs" human mode)."""
    f = obs.field
    h = 1.0 / np.asarray(f.inv_spacing)
    x, y = np.meshgrid(np.arange(f.shape[0]) * h[0], np.arange(f.shape[1]) * h[1], indexing="ij")
    gap = np.min([np.hypot(x - p.x, y - p.y) - radius for p in humans], axis=0)
    values = np.minimum(f.values, gap.reshape(-1).astype(f.values.dtype))
    return StaticPruner(obs.kind, f._replace(values=values), obs.par, "OBS")


def stopped_run(driven: np.ndarray, humans: list, start: np.ndarray, goal) -> Run:
    """A Run of what the loop drove before Stop, from the collision checks' positions: (t, x, y) per tick,
    speed and heading from the displacement (the playback needs them; no plan is kept: a reversing stretch
    plays back facing the way it moved)."""
    if len(driven) == 0:
        driven = np.array([[0.0, start[0], start[1]]])
    step = np.diff(driven[:, 1:], axis=0, prepend=start[None, :2])
    dt = np.diff(driven[:, 0], prepend=0.0)
    speed = np.hypot(*step.T) / np.where(dt > 0, dt, 1.0)
    heading = np.where(speed > 1e-6, np.arctan2(step[:, 1], step[:, 0]), start[3])
    run = Run(trips=[Trip(start=tuple(start[:2]), goal=tuple(goal), outcome="stopped", time_s=float(driven[-1, 0]))])
    run.trajectory = [np.array([t, x, y, v, th]) for (t, x, y), v, th in zip(driven, speed, heading, strict=True)]
    run.humans = list(humans[:len(driven)]) or [np.zeros((0, 2))] * len(driven)
    return run


def uses_ipympl() -> bool:
    """Does this kernel draw with ipympl (``%matplotlib widget``), whose canvases are clickable widgets?"""
    backend = matplotlib.get_backend().lower()
    return "ipympl" in backend or backend == "widget"


def room_figure() -> Figure:
    """The figure clicks land on: an ipympl canvas (no header, toolbar or resizing, so its pixels map to the
    room as ``AXES`` says) where the kernel runs ``%matplotlib widget``, else an Agg figure (tests, scripts)."""
    if not uses_ipympl():
        fig = Figure(figsize=FIGSIZE, dpi=80)
        FigureCanvasAgg(fig)
        return fig
    with plt.ioff():
        fig = plt.figure(figsize=FIGSIZE, dpi=80)
    canvas = fig.canvas
    canvas.header_visible = canvas.toolbar_visible = canvas.footer_visible = canvas.resizable = False
    canvas.capture_scroll = False
    return fig


def _room_axes(fig: Figure, k: int, room: Room, title: str):
    ax = fig.add_axes(AXES[k], label="room")  # the label tells a click on a room from one on the colour bar
    ax.set_xlim(0, room.width)
    ax.set_ylim(0, room.height)
    ax.tick_params(labelsize=7, length=2, pad=1)
    ax.set_title(title, fontsize=8, pad=3)
    return ax


def _marks(ax, setup: Setup, result: SearchResult, human_radius: float) -> None:
    """Plan, start (arrow: heading), goal (star) and humans (disc and heading arrow) on one panel."""
    if result.found:
        ax.plot(result.states[:, 0], result.states[:, 1], "-", color="tab:blue", lw=1.6)
    x, y, th = setup.start
    ax.plot(x, y, "o", color="tab:blue", mec="k", ms=6)
    ax.arrow(x, y, 0.45 * math.cos(math.radians(th)), 0.45 * math.sin(math.radians(th)), width=0.04,
             color="tab:blue", length_includes_head=True)
    ax.plot(*setup.goal, "*", color="gold", mec="k", ms=13)
    for h in setup.humans:
        ax.add_patch(matplotlib.patches.Circle((h.x, h.y), human_radius, color="tab:red", alpha=0.8))
        ax.arrow(h.x, h.y, 0.5 * math.cos(math.radians(h.heading_deg)), 0.5 * math.sin(math.radians(h.heading_deg)),
                 width=0.03, color="tab:red", length_includes_head=True)


def draw_setup(fig: Figure, playground: HJPlayground) -> None:
    """Left: the heuristic to the goal at the robot's heading and the slice speed, with the plan. Right: the
    static BRT (red) and human BRT (orange) slices there, and the cells whose successors each pruner removes."""
    p, setup = playground, playground._chosen()
    room, fields, census, plan = p.room, p.slice_fields(), p.census(), p.plan().result
    fig.clear()
    extent = (0, room.width, 0, room.height)
    where = f"θ = {setup.start[2]:.0f}°, v = {p.speed:.2f} m/s"
    ax = _room_axes(fig, 0, room, f"{setup.heuristic} heuristic to the goal (s) at {where}")
    ttr = np.ma.masked_where(fields.blocked, fields.ttr)
    ax.imshow(np.where(fields.blocked, 0.55, 1.0), cmap="gray", vmin=0, vmax=1, origin="lower", extent=extent)
    image = ax.imshow(ttr, cmap="viridis", origin="lower", extent=extent, vmin=0.0, vmax=float(np.nanmax(ttr)) or 1.0)
    ax.contour(fields.ttr, levels=8, colors="w", linewidths=0.4, origin="lower", extent=extent)
    fig.colorbar(image, cax=fig.add_axes(COLORBAR)).ax.tick_params(labelsize=6)  # its own axes: the panel keeps AXES
    _marks(ax, setup, plan, p.human.radius_m)
    rgb = np.ones((*fields.blocked.shape, 3))
    rgb[fields.static <= 0] = (1.0, 0.72, 0.72)
    rgb[fields.human < 0] = (1.0, 0.82, 0.55)
    rgb[fields.blocked] = 0.55
    ax = _room_axes(fig, 1, room, f"BRT slices at {where}; cells whose successors a pruner removes")
    ax.imshow(rgb, origin="lower", extent=extent)
    for name, cells in census.cells.items():
        colour, marker = MARKS[name]
        ax.plot(cells[:, 0], cells[:, 1], marker, color=colour, ms=2.5, ls="none",
                label=f"{name}: {census.removed[name]:,}")
    _marks(ax, setup, plan, p.human.radius_m)
    if census.cells:
        ax.legend(fontsize=6, loc="lower right", framealpha=0.8, handletextpad=0.2, borderpad=0.3)


CELL = 'style="padding:1px 12px 1px 0;text-align:left"'  # the census table's cells: headers apart, not run together


def summary_html(playground: HJPlayground) -> str:
    """The plan (status, expansions, time, cost, clearance) and the census as a small table."""
    out, census = playground.plan(), playground.census()
    r = out.result
    plan = (f"<b>plan</b>: {r.status}, {r.expansions:,} expansions, {1000 * r.seconds:.0f} ms search"
            + (f", cost {r.cost:.2f} s, {len(r.controls)} steps, densified clearance {out.clearance:.3f} m"
               if r.found else ""))
    rows = "".join(f"<tr><td {CELL}>{name}</td><td {CELL}>{census.removed[name]:,} of {census.total:,}</td>"
                   f"<td {CELL}>{census.on_plan[name]:,} of {census.plan_total:,}</td></tr>" for name in census.removed)
    head = "".join(f"<th {CELL}>{h}</th>" for h in ("pruner", "successors removed on the slice",
                                                     "of the plan's states' successors"))
    return f"<div>{plan}</div><table><tr>{head}</tr>{rows}</table>"


class HJView(PlaygroundView):
    """The widgets of the HJ playground: set-up menu, click mode, sliders and option menus, the clickable
    room figure, the plan's summary and the closed loop's controls and playback."""

    first_use = ("first use: numba compiles the lattice search and the pruners, a few minutes in a fresh clone "
                 "and under a minute once its cache is written; later clicks answer in a second")

    def __init__(self, playground: HJPlayground, scenario: str | None = None):
        super().__init__()
        self.playground = p = playground
        self._syncing = False  # True while the code, not a person, sets a control
        self._stop, self._thread = threading.Event(), None
        self.scenarios = widgets.Dropdown(options=[("choose a set-up", ""), *[(label, key) for key, (label, _)
                                                                              in p.scenarios.items()]],
                                          description="set-up", layout=widgets.Layout(width="420px"))
        self.mode = widgets.ToggleButtons(options=MODES, description="click sets")
        dv = p.loop.spec.dv
        self.heading = widgets.IntSlider(0, -180, 180, 15, description="robot θ°", continuous_update=False)
        self.human_heading = widgets.IntSlider(180, -180, 180, 15, description="human θ°", continuous_update=False)
        self.speed = widgets.FloatSlider(p.speed, min=float(p.robot.v_min), max=float(p.robot.v_max), step=dv,
                                         description="slice v", continuous_update=False)
        self.options = {name: widgets.Dropdown(options=choices, description=label, layout=widgets.Layout(width="210px"))
                        for name, label, choices in (("heuristic", "heuristic", HEURISTICS), ("static", "static", STATIC),
                                                     ("human_mode", "humans", tuple(HUMAN_MODES)),
                                                     ("algorithm", "search", ALGORITHMS))}
        self.seconds = widgets.IntSlider(8, 2, 30, 1, description="loop s", continuous_update=False)
        for widget, css in ((self.scenarios, "navlab-scenario"), (self.mode, "navlab-mode"),
                            (self.heading, "navlab-heading"), (self.human_heading, "navlab-human-heading"),
                            (self.speed, "navlab-speed")):
            widget.add_class(css)
        self.scenarios.observe(lambda c: self._forward(p.choose_scenario, c["new"]), names="value")
        self.mode.observe(lambda c: self.message.show(self.status()) if p.setup is not None else None, names="value")
        self.heading.observe(lambda c: self._forward(p.set_heading, c["new"]), names="value")
        self.human_heading.observe(lambda c: self._forward(p.set_human_heading, c["new"]), names="value")
        self.speed.observe(lambda c: self._forward(p.set_speed, c["new"]), names="value")
        for name, menu in self.options.items():
            menu.observe(lambda c, name=name: self._forward(p.set_option, name, c["new"]), names="value")
        self.fig = room_figure()
        self.fig.canvas.mpl_connect("button_press_event", self._on_press)
        self.result = self.fig.canvas if uses_ipympl() else widgets.Image(format="png")
        self.result.add_class("navlab-result")
        self.summary = widgets.HTML()
        self.summary.add_class("navlab-summary")
        # hidden until a closed loop has run (an empty image shows as a broken-image icon)
        self.replay = widgets.Image(format="gif", layout=widgets.Layout(width="560px", display="none"))
        self.replay.add_class("navlab-replay")
        self.scene = widgets.HTML()  # the meshcat scene, in an iframe (its own page: three.js, no kernel link)
        self.scene.add_class("navlab-scene")
        loop = widgets.HBox([self.seconds, self._plain_button("run closed loop", self.run_loop, "navlab-run"),
                             self._plain_button("stop", self.stop, "navlab-stop")])
        self.widget = widgets.VBox([
            widgets.HBox([self.scenarios, self.mode,
                          self.button("clear humans", p.clear_humans, css="navlab-clear-humans")]),
            widgets.HBox([self.heading, self.human_heading, self.speed]),
            widgets.HBox(list(self.options.values())),
            self.message.widget, self.result, self.summary, loop, self.replay,
            self.button("static BRT in 3D (meshcat)", self.show_scene, css="navlab-show-scene"), self.scene])
        if scenario is not None:
            self.start(scenario)

    def start(self, scenario: str) -> None:
        """The notebook's scenario: the menu shows it, then the controls follow the set-up; a refused one is
        a ParamsError naming the parameter."""
        with self._synced():
            if scenario in self.playground.scenarios:
                self.scenarios.value = scenario
        self.start_scenario(f"scenario = {scenario!r}", self.playground.choose_scenario, scenario)

    def snapshot(self):
        """The current drawing as a PNG image output: what an executed notebook (papermill) keeps."""
        from IPython.display import Image

        fig = Figure(figsize=FIGSIZE, dpi=80)
        draw_setup(fig, self.playground)
        return Image(figure_bytes(fig))

    def status(self) -> str:
        p = self.playground
        return f"{p.scenario}: {p.describe()}; next click sets the {self.mode.value}"

    def draw(self) -> None:
        p = self.playground
        draw_setup(self.fig, p)
        if uses_ipympl():
            self.fig.canvas.draw_idle()
        else:
            self.result.value = figure_bytes(self.fig)
        self.summary.value = summary_html(p)
        with self._synced():  # the controls show the set-up (a scenario choice changes them all)
            setup = p.setup
            self.heading.value = round(setup.start[2])
            for name, menu in self.options.items():
                menu.value = getattr(setup, name)
            if setup.humans:
                self.human_heading.value = round(setup.humans[-1].heading_deg)

    def run_loop(self, background: bool = True) -> None:
        """The closed loop for ``seconds`` simulated, in a thread (the kernel stays free for Stop and the
        progress line) unless ``background`` is False (tests, the benchmark)."""
        if self._thread is not None and self._thread.is_alive():
            self.message.show("the closed loop is already running: wait, or press stop", "error")
            return
        self._stop.clear()
        if background:
            self._thread = threading.Thread(target=self._loop, daemon=True)
            self._thread.start()
        else:
            self._loop()

    def stop(self) -> None:
        if self._thread is not None and self._thread.is_alive():
            self._stop.set()
            self.message.show("stopping the closed loop …", "progress")
        else:
            self.message.show("nothing to stop: the closed loop is not running", "error")

    def _loop(self) -> None:
        """Run, play back, and say how it ended (or why it failed) on the message line."""
        seconds, began = self.seconds.value, time.perf_counter()
        self.message.show(f"closed loop: starting ({seconds} s simulated at most) …", "progress")

        def progress(t: float) -> None:
            self.message.show(f"closed loop: {t:.1f} of {seconds} s simulated … (stop ends it)", "progress")

        try:
            replay = self.playground.closed_loop(seconds, progress, self._stop)
        except Exception as err:  # noqa: BLE001 - a widget callback must never end in a traceback
            self.message.show(one_line(err), "error")
            return
        self.replay.value = replay.gif
        self.replay.layout.display = None
        self.message.show(f"closed loop: {replay.outcome}; its playback is below "
                          f"({time.perf_counter() - began:.1f} s to simulate and render)")

    def show_scene(self) -> None:
        """The room's static BRT at the slice speed as a meshcat scene (drag to turn it) below the button."""
        doc = self.playground.brt_scene()
        self.scene.value = (f'<iframe srcdoc="{html.escape(doc)}" style="width: 100%; height: 440px; border: 0">'
                            "</iframe>")

    def _forward(self, action, *args) -> None:
        if not self._syncing:
            self.act(action, *args)

    def _on_press(self, event) -> None:
        """A click on the figure: the room position under it, in the mode the toggle says."""
        if event.inaxes is None or event.inaxes.get_label() != "room" or event.xdata is None:
            self.message.show("click inside one of the two room panels", "error")
            return
        self.act(self.playground.click, self.mode.value, event.xdata, event.ydata)

    def _plain_button(self, description: str, action, css: str) -> widgets.Button:
        button = widgets.Button(description=description)
        button.add_class(css)
        button.on_click(lambda _: action())
        return button

    @contextlib.contextmanager
    def _synced(self):
        """While the code sets a control, its observer does not act on the change."""
        self._syncing = True
        try:
            yield
        finally:
            self._syncing = False
