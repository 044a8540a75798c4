"""The HJ-search paper's closed-loop experiments as seeded runs (Sec. VII-D Table VI, VIII-B Table VIII,
VIII-C Table IX), built from params.yaml ``hj.dynamic``.

Each function sets up one run — room, start, goals, humans, heuristic, pruners — and drives the
receding-horizon loop (``hj.receding_horizon.run_patrol``) with the HJ-guided lattice planner as the
policy (``hj.lattice_policy.LatticePolicy``). Run ``r`` of a cell draws its sensing noise from
``hj.dynamic.seed + r``, so every cell is reproducible and the methods of one table see the same draws
(in Table VI, noise-free like the paper's simulation, the draw is where along its line the human starts).

- Table VI (``face_to_face``, ``zig_zag``): non-reactive humans in the open room; the paper's three rows
  differ only in the human pruner (FI-BRT, FS-BRT, OBS), the walls are pruned by OBS in every row. Its
  search is prediction-free (Sec. IV), so are these rows; ``human_rows`` adds ours, FI-/FS-BRT with the
  humans predicted along their observed velocity, as labelled variant rows (Tables VI and IX).
- Table VIII (``room_patrol``): no humans; the Long Hallway and Dense Room patrols with the four
  heuristic x static-pruner combinations (Dist/TTR x OBS/static BRT with its measured margin).
- Table IX (``human_patrol``): 1 or 2 humans patrolling their points of interest under the paper's three
  rules (``hj.humans.PatrolHuman``) while the robot patrols its goals, for three patrol cycles.

``run_cells`` runs many such runs in worker processes: a run is a pure function of its arguments and its
seed (the planner's wall time is recorded, never simulated), so no result depends on how many.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Hashable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from navlab.core.params import Params
from navlab.hj.grids import forward_only, forward_only_root, load_human_brt, load_ttr
from navlab.hj.guidance import dist_heuristic, ttr_heuristic
from navlab.hj.humans import HumanStream, PatrolHuman, StraightWalker
from navlab.hj.lattice_policy import LatticePolicy
from navlab.hj.planning import Planner, lattice_spec
from navlab.hj.pruners import FIParams, obs_point_pruner
from navlab.hj.receding_horizon import Run, SimSettings, run_patrol
from navlab.maps.rooms import Room, load_room

HUMAN_ROWS = {"FI-BRT": "fi", "FS-BRT": "fs", "OBS": "obs"}  # Tables VI and IX, the paper's rows -> LatticePolicy mode
ROOM_COMBOS = (("Dist", "OBS"), ("Dist", "BRT"), ("TTR", "OBS"), ("TTR", "BRT"))  # Table VIII rows
ROOM_NAMES = {"long_hallway": "Long Hallway", "dense_room": "Dense Room"}


def human_rows(dynamic) -> dict[str, tuple[str, float]]:
    """Tables VI and IX: row -> (``LatticePolicy`` human mode, prediction horizon in s). First the paper's three
    rows at ``closed_loop.human_prediction_s`` (0, prediction-free, is the paper's method; OBS never predicts),
    then ours where ``prediction_variant_s`` differs from it: FI-/FS-BRT with the humans predicted along their
    observed velocity that far, named "FI-BRT (1.5 s prediction, ours)"."""
    c = dynamic.closed_loop
    rows = {m: (mode, 0.0 if mode == "obs" else c.human_prediction_s) for m, mode in HUMAN_ROWS.items()}
    if c.prediction_variant_s > 0 and c.prediction_variant_s != c.human_prediction_s:
        rows.update({f"{m} ({c.prediction_variant_s:g} s prediction, ours)": (mode, c.prediction_variant_s)
                     for m, mode in HUMAN_ROWS.items() if mode != "obs"})
    return rows


def start_state(xy, heading_deg: float) -> np.ndarray:
    """A robot at rest at ``xy`` facing ``heading_deg``."""
    return np.array([float(xy[0]), float(xy[1]), 0.0, math.radians(heading_deg)])


def cyclic_goals(points, cycles: int) -> list[tuple[float, float]]:
    """Starting at ``points[0]``: visit the others in order and come back, ``cycles`` times (the paper's
    "full patrol cycle" starts and ends at the same goal)."""
    if len(points) < 2:
        raise ValueError(f"a patrol needs at least 2 goals, got {len(points)}")
    one = [tuple(map(float, p)) for p in (*points[1:], points[0])]
    return one * cycles


class ClosedLoop:
    """What the closed-loop runs share: params, lattice, value functions (loaded once, on first use)."""

    def __init__(self, params: Params, artifacts_dir: str | Path, log=print):
        self.params, self.artifacts_dir, self.log = params, artifacts_dir, log
        self.d = params.hj.dynamic
        self.robot = params.hj.grids.robot
        self.spec = lattice_spec(params)
        fi = params.hj.planner.fi_brt
        self.fi = FIParams(fi.dt_s, fi.margin, fi.gamma_min, fi.gamma_max, fi.k_theta, fi.w_theta, fi.w_dist,
                           fi.d_threshold_m)
        self._ttr = self._human_brt = None
        self._planners: dict[str, Planner] = {}
        self.rows = human_rows(self.d)  # Tables VI and IX

    def settings(self, pose_noise_m: float) -> SimSettings:
        c, h = self.d.closed_loop, self.params.hj.grids.human
        return SimSettings(c.replan_hz, c.control_hz, self.robot.radius_m, h.radius_m, self.robot.v_max,
                           self.robot.accel_min, c.goal_tolerance_m, c.trip_timeout_s, c.deadlock_s,
                           c.deadlock_progress_m, pose_noise_m, c.human_noise_m, velocity_window_s=c.velocity_window_s,
                           human_speed=h.speed, v_min=self.robot.v_min, a_max=self.robot.accel_max)

    def rules(self) -> str:
        """The loop's rules beyond the paper's text (hj.lattice_policy, hj.receding_horizon), for the reports."""
        c = self.d.closed_loop
        keep = (f"a re-plan out of budget keeps the car's current plan if its next 2 s re-check collision-free (and pass "
                f"the human pruner), and so does one whose new plan arrives less than {c.plan_switch_gain_s:g} s sooner "
                f"(with no humans in view ANA* then searches only for plans that arrive that much sooner: the plan in force "
                f"is its incumbent)"
                if c.reuse_plan else "a re-plan out of budget brakes the car")
        return (f"The search prunes with the paper's pruners alone (OBS: the clearance at the sampled states, the "
                f"humans' discs included in the OBS rows; BRT: the static BRT there); ours: the car never executes a "
                f"found plan that fails the paper's dense feasibility check, which counts as no plan. "
                f"Between re-plans (hj.lattice_policy): {keep}; a car at rest without a plan lets its search run on "
                f"while it waits (resumed with no humans in view; re-run for up to {c.rest_periods} period(s) while "
                f"humans move), and with no humans in view holds back an ANA* plan whose proven bound exceeds "
                f"{c.rest_bound:g} while its search improves it, for up to {c.rest_periods} period(s) after the first "
                f"solution; without a plan the car brakes straight where "
                f"that stops clear of the walls, else swerves (the one step after which braking does), else keeps the "
                f"plan in force; a start inside the static BRT's margin but clear "
                f"of obstacles is planned from with the pruning threshold at its own value. Plans start from the "
                f"observed speed exactly (the first step absorbs the gap to a lattice level) and the car executes "
                f"their commands unmodified, so it drives the trajectory the pruners checked from the observed pose; "
                f"under pose noise both static pruners prune {c.pose_allowance_sigmas:g} noise stds further out. "
                f"{self._prediction_rule()}, and without a plan the car evades (the one step with the highest human "
                f"BRT value) where braking straight would enter the human BRT (contacts then count as not on a plan).")

    def _prediction_rule(self) -> str:
        c = self.d.closed_loop
        paper = ("FI-/FS-BRT check each node against the humans where they were last observed (prediction-free, the "
                 "paper's Sec. IV)" if c.human_prediction_s == 0 else
                 f"FI-/FS-BRT check each node against the humans where they walk by then at their observed velocity "
                 f"(held after {c.human_prediction_s:g} s; the paper's search is prediction-free)")
        if not any(a == c.prediction_variant_s > 0 for _, a in self.rows.values()) or c.human_prediction_s > 0:
            return paper
        return (f"{paper}; the rows marked 'prediction, ours' check it against the humans where they walk by then at "
                f"their observed velocity (over {c.velocity_window_s:g} s; held after {c.prediction_variant_s:g} s)")

    def _human_row(self, name: str, pose_noise_m: float = 0.0) -> tuple[str, float, float]:
        """A Table VI / IX row's ``policy`` arguments after the static pruner: human mode, pose noise, prediction
        horizon; an unknown row is one line listing them."""
        if name not in self.rows:
            raise ValueError(f"human row {name!r}: use one of {', '.join(self.rows)}")
        mode, ahead = self.rows[name]
        return mode, pose_noise_m, ahead

    def heuristic_for(self, name: str):
        if name == "Dist":
            tol = self.params.hj.planner.goal_tolerance_astar_m
            return lambda goal: dist_heuristic(goal, self.robot.v_max, tol)
        if name == "TTR":
            if self._ttr is None:
                self._ttr = load_ttr(self.params, self.artifacts_dir)
            return lambda goal: ttr_heuristic(self._ttr, goal)
        raise ValueError(f"heuristic {name!r}: the closed-loop runs use 'Dist' or 'TTR'")

    def static_pruner(self, room: Room, name: str):
        if name == "OBS":  # the paper's instantaneous check (hj.pruners.obs_point_pruner)
            return obs_point_pruner(room, self.robot.radius_m)
        if name == "BRT":  # the room's static BRT with the margin measured against a finer solve (cached)
            if room.name not in self._planners:
                self._planners[room.name] = Planner(self.params, self.artifacts_dir, room.name, costs=False,
                                                    log=self.log)
            return self._planners[room.name].pruner("BRT")
        raise ValueError(f"static pruner {name!r}: use 'OBS' or 'BRT'")

    def policy(self, room: Room, heuristic: str, static: str, human_mode: str = "none",
               pose_noise_m: float = 0.0, prediction_s: float | None = None) -> LatticePolicy:
        """The receding-horizon planner; its static pruner prunes ``pose_allowance_sigmas`` pose-noise stds
        further out (the BRT's value is 1-Lipschitz in position, OBS's clearance too), because plans are made
        from the observed pose and driven from the true one. ``prediction_s``: how far FI-/FS-BRT predict the
        humans (None: ``closed_loop.human_prediction_s``)."""
        if human_mode in ("fi", "fs") and self._human_brt is None:
            self._human_brt = load_human_brt(self.params, self.artifacts_dir)
        p = self.params.hj.planner
        pruner = self.static_pruner(room, static)
        pruner = pruner.with_threshold(pruner.par[0] + self.d.closed_loop.pose_allowance_sigmas * pose_noise_m)
        return LatticePolicy(self.spec, room, self.heuristic_for(heuristic), pruner,
                             p.goal_tolerance_astar_m, p.goal_max_speed, self.d.closed_loop.max_expansions,
                             human_mode, self._human_brt if human_mode in ("fi", "fs") else None,
                             self.params.hj.grids.human.radius_m, self.fi,
                             anytime=self.d.closed_loop.algorithm == "ANA*",
                             rest_periods=self.d.closed_loop.rest_periods, rest_bound=self.d.closed_loop.rest_bound,
                             reuse=self.d.closed_loop.reuse_plan,
                             switch_gain_s=self.d.closed_loop.plan_switch_gain_s, robot_radius=self.robot.radius_m,
                             human_prediction_s=self.d.closed_loop.human_prediction_s if prediction_s is None
                             else prediction_s)

    def _rng(self, run: int) -> np.random.Generator:
        return np.random.default_rng(self.d.seed + run)

    def _table6_settings(self) -> SimSettings:
        return dataclasses.replace(self.settings(self.d.table6.pose_noise_m), human_noise_m=self.d.table6.human_noise_m)

    def _jittered(self, start, goal, rng: np.random.Generator) -> tuple[float, float]:
        """Table VI, run by run: the human starts U(0, jitter) m further along its line (first draw of the run)."""
        a, b = np.asarray(start, float), np.asarray(goal, float)
        shift = rng.uniform(0.0, self.d.table6.human_start_jitter_m) / np.linalg.norm(b - a)
        return tuple(float(c) for c in a + shift * (b - a))

    def face_to_face(self, row: str, run: int, keep_plans: bool = False) -> Run:
        """Table VI, Face-to-Face: one human walks head-on at the robot; both start together."""
        t, speed, rng = self.d.table6, self.params.hj.grids.human.speed, self._rng(run)
        f, room = t.face_to_face, load_room(t.room)
        human = StraightWalker(self._jittered(f.human_start, f.human_goal, rng), tuple(f.human_goal), speed)
        return run_patrol(self.policy(room, self.d.closed_loop.heuristic, "OBS", *self._human_row(row)),
                          room.obstacle_distance, start_state(f.robot_start[:2], f.robot_start[2]), [f.robot_goal],
                          [human], self._table6_settings(), rng, keep_plans=keep_plans)

    def zig_zag(self, row: str, run: int) -> Run:
        """Table VI, Zig-Zag: a stream of humans along one line; the robot crosses it at every trip."""
        t, speed, rng = self.d.table6, self.params.hj.grids.human.speed, self._rng(run)
        z, room = t.zig_zag, load_room(t.room)
        human = HumanStream(tuple(z.human_start), tuple(z.human_goal), speed, z.spawn_clear_m)
        human.position = np.asarray(self._jittered(z.human_start, z.human_goal, rng))  # the stream's phase
        return run_patrol(self.policy(room, self.d.closed_loop.heuristic, "OBS", *self._human_row(row)),
                          room.obstacle_distance, start_state(z.robot_start[:2], z.robot_start[2]),
                          list(z.robot_goals), [human], self._table6_settings(), rng)

    def room_patrol(self, room_name: str, heuristic: str, static: str, run: int = 0,
                    keep_plans: bool = False) -> Run:
        """Table VIII: the cyclic patrol of one room's named goals, no humans."""
        t = self.d.table8
        route = {"long_hallway": t.hallway_route, "dense_room": t.dense_route}.get(room_name)
        if route is None:
            raise ValueError(f"room {room_name!r}: Table VIII runs in {', '.join(ROOM_NAMES)}")
        room = load_room(room_name)
        missing = [g for g in route if g not in room.goals]
        if missing:
            raise ValueError(f"hj.dynamic.table8: goal {missing[0]!r} is not a goal of room {room_name} "
                             f"(its goals: {', '.join(room.goals)})")
        points = [room.goals[g] for g in route]
        return run_patrol(self.policy(room, heuristic, static, pose_noise_m=t.pose_noise_m), room.obstacle_distance,
                          start_state(points[0], t.start_heading_deg), cyclic_goals(points, t.cycles), [],
                          self.settings(t.pose_noise_m), self._rng(run), keep_plans=keep_plans)

    def human_patrol(self, row: str, n_humans: int, run: int = 0, keep_plans: bool = False) -> Run:
        """Table IX: the robot's cyclic patrol among ``n_humans`` patrolling humans."""
        t, speed = self.d.table9, self.params.hj.grids.human.speed
        if not 1 <= n_humans <= len(t.human_pois):
            raise ValueError(f"{n_humans} humans: hj.dynamic.table9.human_pois lists {len(t.human_pois)}")
        room = load_room(t.room)
        humans = [PatrolHuman(tuple(map(tuple, pois)), speed) for pois in t.human_pois[:n_humans]]
        return run_patrol(self.policy(room, self.d.closed_loop.heuristic, "OBS", *self._human_row(row, t.pose_noise_m)),
                          room.obstacle_distance, start_state(t.robot_goals[0], t.robot_start_heading_deg),
                          cyclic_goals(t.robot_goals, t.cycles), humans, self.settings(t.pose_noise_m),
                          self._rng(run), keep_plans=keep_plans)


_WORKER_LOOP: ClosedLoop | None = None  # each worker process's own ClosedLoop (value functions loaded once)


def _start_worker(params: Params, artifacts_dir: str | Path) -> None:
    import torch

    global _WORKER_LOOP
    torch.set_num_threads(1)  # one thread per process: two processes' thread pools would contend for the cores
    _WORKER_LOOP = ClosedLoop(params, artifacts_dir, log=lambda *_: None)


def _call(call: tuple[str, tuple]) -> Run:
    name, args = call
    return getattr(_WORKER_LOOP, name)(*args)


def forward_only_loop(params: Params, artifacts_dir: str | Path, log=print) -> ClosedLoop | None:
    """The forward-only car's closed loop (v >= 0, its own TTR and human-robot BRT,
    ``navlab.hj.grids.forward_only``) for the labelled variant rows of Tables VI, VIII and IX, which check the
    walls with OBS (its static BRT is not built); None when the paper's car does not reverse."""
    if params.hj.grids.robot.v_min >= 0:
        return None
    return ClosedLoop(forward_only(params), forward_only_root(artifacts_dir), log)


def run_cells(loop: ClosedLoop, cells: Mapping[Hashable, Sequence[tuple[str, tuple]]],
              workers: int) -> dict[Hashable, list[Run]]:
    """Each cell's runs, a cell being a list of ``(method, args)`` calls of ``loop`` —
    ``{"TTR + BRT": [("room_patrol", ("dense_room", "TTR", "BRT", r)) for r in range(4)]}`` — run here
    (``workers`` <= 1) or in ``workers`` processes with a ClosedLoop of the same params each."""
    calls = [call for cell in cells.values() for call in cell]
    unknown = sorted({name for name, _ in calls} - {"face_to_face", "zig_zag", "room_patrol", "human_patrol"})
    if unknown:
        raise ValueError(f"run_cells: {unknown[0]!r} is not a closed-loop run; use face_to_face, zig_zag, "
                         f"room_patrol or human_patrol")
    if workers <= 1 or len(calls) <= 1:
        runs = [getattr(loop, name)(*args) for name, args in calls]
    else:
        with ProcessPoolExecutor(min(workers, len(calls)), initializer=_start_worker,
                                 initargs=(loop.params, loop.artifacts_dir)) as pool:
            runs = list(pool.map(_call, calls))
    done = iter(runs)
    return {key: [next(done) for _ in cell] for key, cell in cells.items()}
