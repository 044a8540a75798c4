"""The HJ-guided lattice planner as a receding-horizon policy (HJ-search paper Sec. VII-D, VIII).

At every re-plan the policy searches from the observed state to the current goal with a deterministic
expansion budget and returns the plan's (a, ω) commands; the simulator executes the first of them.
With ``anytime`` the search is ANA* (the paper's real-robot planner, Sec. VIII): greedy until a first
plan, then improving it until the budget is spent, so a budget far below what optimal A* needs over a
long trip still gives a plan; without, A* (the plan is optimal or there is none).
The search starts from the observed speed itself (``dubins_lattice.first_step``: the first step's
accelerations absorb the gap to the nearest speed level), so the commands the car executes unmodified
drive the states the pruners checked. Planned from the nearest level instead, the car drifted off its
plans by up to 6 cm/s and grazed a Dense Room wall (measured).

Human handling, the three rows of Tables VI and IX:

- ``"fi"`` / ``"fs"``: the human-robot BRT pruner (``hj.pruners.human_pruner``) with the observed
  human positions, forward-invariant (Eq. 14-18) or feasible-set; with ``human_prediction_s`` > 0 each
  node is checked against the humans where they walk by the node's time at their observed velocities
  (our addition: the paper's text checks the humans where they were seen);
- ``"obs"``: the paper's OBS baseline, "the human as a static obstacle at its instantaneous position":
  the humans are discs added to the clearance field of the OBS static pruner, re-built per re-plan.

A plan that cannot start (the observed state already pruned) or is not found within the budget is an
empty command list: the simulator then brakes straight. Where braking straight would not stop clear of the
walls, the policy swerves instead (``_stop``: the first step after which braking straight does), and where
no step does, it keeps the plan in force (re-checked from a pose 2 cm off, it may fail, but it was checked
clear where it was issued, while braking runs into the wall for certain). With a human pruner on and
humans in view, the policy evades (``_evade``: the one step that keeps the human BRT value highest). Both
are an ``Evasion``, which the simulator counts as no plan in force.

Between re-plans the anytime search is not thrown away blindly (``reuse``): when a re-plan stops at the
expansion limit without a plan, the policy re-checks the next ``reuse_horizon_s`` of the plan the car is
executing (the braking time; re-checked whole, the open-loop rest of a 15 s plan replayed from a pose
2 cm off drifts into an obstacle's clearance somewhere, and the Dense Room's return trip kept no plan) — replayed from the newly observed pose under the dynamics,
``samples_per_step`` points per step — and, if it passes,
answers ``None``: the car keeps executing it (a plan proven infeasible, or one the re-check rejects, still
makes the car brake). The re-check is the human pruner (the humans have moved) and, for the static map,
collision: the swept OBS check (``lattice_fields.swept_unsafe``, ours: the path between the
re-check's samples is covered too; with ``"obs"`` the humans' discs included). Not the
static BRT again: the map has not changed, the plan passed the BRT when it was made, and an optimal plan
runs along the BRT's boundary, so the pose noise alone (2 cm) would fail it almost every time. A kept
plan must also leave the simulator's fallback, braking straight, clear of the walls from any point of its
current step.

The same re-check keeps the car on its plan when a re-plan finds one that arrives no sooner (by less than
``switch_gain_s``): with 2 cm of pose noise, successive anytime searches return different plans of equal
cost, and a car switching between them at 12 Hz dithered in the Dense Room (turning on the spot between
plans that leave in different directions) until its trip deadlocked (measured). A plan that arrives
sooner, or a current plan that no longer re-checks safe, is replaced as before. Since only a plan that
arrives ``switch_gain_s`` sooner than the one in force would be taken, the re-plan's ANA* with no humans in
view is given that time as its incumbent cost from the start (``search(..., upper_bound=...)``: nodes that cannot beat it are
pruned, the rest ordered as after a solution), so its budget goes to finding such a plan rather than to
first solutions that would be discarded anyway (a moving car's 6,000-expansion re-plans mostly returned
such plans, bounds 2.5-4.5, and the car drove its first, long plans to the end, measured in the Dense Room).

A start inside the static BRT's pruned set (value <= margin) but clear of the obstacles (clearance >
robot radius) is planned from, not given up on: the search then prunes at the start's own BRT value
(just below it) instead of the margin, so it looks for plans that get no closer to the obstacles than
the car already is. Without this the car, once braked (straight, ω = 0) to a stop within the margin of a
wall, never plans again: the 2 cm pose noise puts every observed start at or inside the margin (0.05 m).
The same holds for a car still moving inside the set: braking straight (the fallback) is no escape there,
while a plan that keeps the BRT value at least where it is may be (restricting this to a car at rest made
TTR + BRT hit a wall on the Dense Room's return trip, measured).

A robot *at rest* that has no plan waits for one: when a search from rest stops at the expansion limit
without a plan, the next re-plan (still at rest, same goal) goes on with it, one more period's budget at a
time. With no humans in view nothing the search pruned can change, so it is *resumed* where it stopped
(``lattice_search.resume``: OPEN and every node kept, the same result as one search given the summed
budget), for as long as the car waits (the trip's deadlock timer ends a wait that never ends): in the
Dense Room the first plan from rest needs up to ~55,000 expansions with TTR (the obstacle-free TTR/Dist
heuristics fill the dead-end pocket between the walls first), ~7 periods' budget, and Dist + BRT's return
trip needed more than the 12 periods (72,000 expansions) the earlier rule allowed before it started afresh,
so that car never left (7 of 24 trips deadlocked at rest, measured). While humans move their predictions
change, so the search is re-run from the newly observed pose with the expansions spent plus one more
period's budget, for up to ``rest_periods`` periods (then afresh); its measured wall time is that of the
whole re-run. A resumed search plans from the pose first observed at rest, which differs from the car's
only by the pose noise, as every plan's start does.

A waiting car with no humans in view also lets an ANA* plan *improve* before it drives it: a plan whose
proven bound (ANA*'s G / min f over OPEN, the most it can cost above the optimum) exceeds ``rest_bound``
is held back and the search resumed, for up to ``rest_periods`` periods after its first solution; then the
best plan so far is taken. ANA*'s first solution from rest can be a long detour, and a moving car's re-plans
rarely find any plan within one period, so it kept driving that detour: on the Dense Room's return trip a
first plan of 24.5 s (bound 4.9) from (5.2, 1.2) drove up to the first wall's gap and back until the trip
deadlocked, where one more period's search (6,000 expansions) had found 11.0 s (bound 1.7) (measured).

The search prunes with the paper's pruners alone (OBS: the clearance at the sampled states; BRT: the
static BRT there), which do not look between samples, so a plan may graze an obstacle. Our safety rule:
the car never executes a plan that fails the paper's dense feasibility check (``hj.planning.plan_clearance``:
the plan replayed under the dynamics, 8 points per sample, exact clearance); such a plan is treated as no
plan (the plan in force is kept if it still re-checks safe, else the car brakes or evades), counted in
``dense_rejections``. A method whose plans keep failing the check loses time or the trip, which is what
the paper's tables measure.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from navlab.hj.planning import plan_clearance
from navlab.hj.pruners import FIParams, clearance_field, human_pruner, obs_pruner
from navlab.hj.receding_horizon import Evasion
from navlab.maps.rooms import Room
from navlab.reach.lookup import HumanBRTLookup
from navlab.search.dubins_lattice import LatticeSpec, first_step, integrate, place, primitive_table
from navlab.search.lattice_fields import GridField
from navlab.search.lattice_search import (
    NO_HUMAN,
    Budget,
    Frontier,
    Goal,
    Heuristic,
    Pruners,
    SearchResult,
    StaticPruner,
    require_finite,
    resume,
    search,
)

HUMAN_MODES = ("fi", "fs", "obs", "none")


class Planned(NamedTuple):
    """One period's search: its result, the expansions spent on it in earlier periods, and whether the car
    takes its plan now (False while a waiting car lets a found plan improve)."""

    result: SearchResult
    spent: int
    ready: bool


@dataclass(frozen=True)
class _WithHumans(StaticPruner):
    """The OBS pruner with the humans' discs in its field (``"obs"``). Its goal is checked against the map
    alone (``base``): a human standing on the goal walks on, and until then the search fails and the car
    brakes, as before; ``search`` refusing the goal would end the run."""

    base: StaticPruner = field(kw_only=True)

    def goal_clearance(self, goal: Goal) -> float:
        return self.base.goal_clearance(goal)


@dataclass
class LatticePolicy:
    spec: LatticeSpec
    room: Room
    heuristic_for: Callable[[tuple[float, float]], Heuristic]  # goal -> heuristic (cached per goal)
    static: StaticPruner
    goal_tolerance: float
    goal_max_speed: float
    max_expansions: int
    human_mode: str = "none"
    human_brt: HumanBRTLookup | None = None
    human_radius: float = 0.3
    fi: FIParams = field(default_factory=FIParams)
    anytime: bool = False
    rest_periods: int = 1  # with humans in view, a search from rest is re-run over this many periods (1: never)
    rest_bound: float = float("inf")  # no humans in view: a waiting car improves an ANA* plan with a larger bound
    reuse: bool = False  # keep the current plan when a re-plan runs out of budget and the plan re-checks safe
    robot_radius: float = 0.285  # m, the kept plan's collision re-check (the QBot's 570 mm base)
    human_prediction_s: float = 0.0  # "fi"/"fs": humans predicted along their observed velocity this far (0: frozen)
    switch_gain_s: float = 0.0  # with ``reuse``: a new plan replaces a still-safe one only if it arrives this much sooner
    reuse_horizon_s: float = 2.0  # s of the kept plan re-checked: the braking time from v_max = 1 m/s at 0.5 m/s²
    expansions: list[int] = field(default_factory=list)
    dense_rejections: int = 0  # found plans not executed: they failed the dense check
    _table: np.ndarray = field(init=False, repr=False)
    _obs: StaticPruner = field(init=False, repr=False)  # the swept check of re-checks and fallbacks (ours)
    _heuristics: dict = field(init=False, repr=False, default_factory=dict)
    _clearance: GridField | None = field(init=False, repr=False, default=None)
    _points: tuple[np.ndarray, np.ndarray] | None = field(init=False, repr=False, default=None)
    _carried: tuple[tuple, int, Frontier | None] | None = field(init=False, repr=False, default=None)  # goal, spent, search
    _current: tuple[tuple, float, np.ndarray] | None = field(init=False, repr=False, default=None)  # goal, t, plan

    def __post_init__(self):
        if not (isinstance(self.rest_periods, int) and self.rest_periods >= 1):
            raise ValueError(f"rest_periods must be an integer >= 1, got {self.rest_periods!r}")
        if not self.rest_bound >= 1.0:
            raise ValueError(f"rest_bound must be >= 1 (a suboptimality bound; inf: take the first plan), "
                             f"got {self.rest_bound!r}")
        if self.human_mode not in HUMAN_MODES:
            raise ValueError(f"human_mode {self.human_mode!r}: use one of {', '.join(HUMAN_MODES)}")
        if self.human_mode in ("fi", "fs") and self.human_brt is None:
            raise ValueError(f"human_mode {self.human_mode!r} needs the human-robot BRT: load it with "
                             f"hj.grids.load_human_brt (built by `dvc repro hj_grids`)")
        if self.human_mode == "obs" and self.static.name != "OBS":
            raise ValueError("human_mode 'obs' adds the humans to the OBS clearance field: pass an OBS static "
                             "pruner (hj.pruners.obs_pruner)")
        self._table = primitive_table(self.spec)
        self._obs = obs_pruner(self.room, self.robot_radius)
        if self.human_mode == "obs":
            self._clearance = clearance_field(self.room)
            n = self._clearance.shape
            h = 1.0 / self._clearance.inv_spacing
            self._points = np.meshgrid(np.arange(n[0]) * h[0], np.arange(n[1]) * h[1], indexing="ij")

    @property
    def dt(self) -> float:
        return self.spec.dt

    def _static_for(self, humans: np.ndarray) -> StaticPruner:
        if self.human_mode != "obs" or len(humans) == 0:
            return self.static
        x, y = self._points
        gap = np.min([np.hypot(x - hx, y - hy) - self.human_radius for hx, hy in humans], axis=0)
        values = np.minimum(self._clearance.values, gap.reshape(-1).astype(self._clearance.values.dtype))
        return _WithHumans(self.static.kind, self._clearance._replace(values=values), self.static.par, "OBS",
                           base=self.static)

    def __call__(self, observation) -> np.ndarray | Evasion | None:
        fix = "the simulator or tracker must hand the policy finite observations"
        state = require_finite(np.asarray(observation.robot, dtype=float).copy(), "observation.robot", fix)
        humans = require_finite(np.asarray(observation.humans, dtype=float).reshape(-1, 2), "observation.humans", fix)
        static = self._static_for(humans)
        (x0, x1), (y0, y1) = self.room.bounds
        if not (x0 <= state[0] < x1 and y0 <= state[1] < y1):
            self._carried = self._current = None
            return np.zeros((0, 2))
        start_value = float(static.values(state[None])[0])
        if start_value <= 0.0:
            # clear by the search's own conservative collision check (it bounds the raster's interpolation
            # error): a car 0 < d < that bound from a wall passed the exact distance test, then the search
            # refused its start with an error (a Table VIII sweep point, measured)
            clear = float(self._obs.values(state[None])[0]) > 0.0
            if static.name != "BRT" or not clear:
                # no plan from here: the fallback below (brake straight only where that stops clear of the
                # walls); blind braking took a Dist + OBS car whose noisy pose fell inside the OBS allowance
                # 4 cm from a wall, heading 10 degrees into it at 0.7 m/s, into that wall (measured)
                self._carried = None
                return self._fallback(state, observation)
            # prune at the start's own value: plans that get no closer than the car is
            static = static.with_threshold(static.par[0] + start_value - 1e-3)
        goal = tuple(observation.goal)
        if goal not in self._heuristics:
            self._heuristics[goal] = self.heuristic_for(goal)
        human = NO_HUMAN
        velocities = np.asarray(observation.human_velocities, dtype=float).reshape(-1, 2)
        if self.human_mode in ("fi", "fs") and len(humans):
            human = human_pruner(self.human_brt, humans, self.human_mode, self.fi, velocities, self.human_prediction_s)
        remaining = self._remaining_s(observation)
        waiting = state[2] == 0.0 and not 0.0 < remaining < np.inf  # at rest, no plan in force
        # a plan in force that still re-checks safe is kept unless a new one arrives switch_gain_s sooner, so
        # ANA* searches only for such plans: the kept plan's time is its incumbent cost from the start. Not
        # while humans move: there a search that finds no plan at all is the signal to evade, which a bounded
        # search ("none sooner") cannot give (bounded there, FS-BRT's Zig-Zag contacts rose, measured)
        moving = self.human_mode != "none" and len(humans) > 0
        keepable = self.reuse and 0.0 < remaining < np.inf and self._still_safe(observation, static, human)
        bound = remaining - self.switch_gain_s if keepable and self.anytime and not moving else np.inf
        if bound <= 0.0:  # no plan can arrive that much sooner
            self.expansions.append(0)
            return None
        result, spent, ready = self._plan(state, goal, Pruners(static=static, human=human),
                                          moving=moving, waiting=waiting, upper_bound=bound)
        self.expansions.append(result.expansions - spent)  # this period's share
        grazes = ready and plan_clearance(self.room, self.robot_radius, self.spec, result) <= 0.0
        if grazes:  # our safety rule: never execute a plan that fails the paper's dense check
            self.dense_rejections += 1
            ready = False
        if ready:
            if keepable and remaining <= result.cost + self.switch_gain_s:
                return None  # the plan in force arrives no later: keep it
            self._current = (goal, float(observation.time), result.controls)
            return result.controls
        if keepable and (grazes or result.status == "expansion limit" or np.isfinite(bound)):
            return None  # out of budget, (bounded) no plan arrives sooner, or it grazes: keep the plan in force
        if human.kind != NO_HUMAN.kind:
            self._current = None
            return self._evade(state, humans, velocities)
        return self._fallback(state, observation)

    def _fallback(self, state: np.ndarray, observation) -> np.ndarray | Evasion | None:
        """No new plan and none kept: brake straight, or swerve (``_stop``); where neither stops clear, the plan
        in force, checked clear where it was issued, is the least bad."""
        stop = self._stop(state)
        if stop is None and self.reuse and 0.0 < self._remaining_s(observation) < np.inf:
            return None
        self._current = None
        return np.zeros((0, 2)) if stop is None else stop

    def _plan(self, state: np.ndarray, goal: tuple, pruners: Pruners, *, moving: bool, waiting: bool,
              upper_bound: float = np.inf) -> Planned:
        """This period's search and the expansions spent on it before this period. A car ``waiting`` (at rest
        with no plan in force) for a plan to the same goal goes on with its search: resumed where it stopped
        in a static world (no humans in view: nothing it pruned has changed, and the car has not moved),
        re-run with one more period's budget while humans move (for up to ``rest_periods`` periods), since
        their predictions changed. A car at rest that follows a plan (turning on the spot) searches afresh
        from where it now is: a search begun at an earlier heading would plan from a pose it has left
        (resumed there, the Dense Room's car dithered between plans from stale headings, measured). A waiting car
        in a static world holds back a found plan while ``_improves`` says its search should go on."""
        carried = self._carried if waiting and self._carried is not None and self._carried[0] == goal else None
        self._carried = None
        if carried is not None and carried[2] is not None and not moving:
            spent = carried[2].expansions
            result = resume(carried[2], spent + self.max_expansions)
        else:
            spent = carried[1] if carried is not None else 0
            result = search(self.spec, self.room.bounds, state, Goal(goal, self.goal_tolerance, self.goal_max_speed),
                            self._heuristics[goal], pruners=pruners, table=self._table,
                            budget=Budget(anytime=self.anytime, max_expansions=spent + self.max_expansions),
                            keep_frontier=waiting and not moving, upper_bound=upper_bound)
        if waiting and not moving and result.found and self._improves(result):
            self._carried = (goal, result.expansions, result.frontier)
            return Planned(result, spent, False)
        if waiting and not result.found and result.status == "expansion limit" and (
                not moving or result.expansions < self.rest_periods * self.max_expansions):
            self._carried = (goal, result.expansions, result.frontier)
        return Planned(result, spent, result.found)

    def _improves(self, found: SearchResult) -> bool:
        """Whether a waiting car lets this found ANA* plan improve another period: the search stopped at its
        limit (OPEN left, so ``resume`` can go on), the plan's proven bound exceeds ``rest_bound``, and fewer
        than ``rest_periods`` periods' budget has gone into improving it since the first solution."""
        return (self.anytime and found.frontier is not None and found.solution_bounds[-1] > self.rest_bound
                and found.expansions < found.solution_expansions[0] + self.rest_periods * self.max_expansions)

    def _evade(self, state: np.ndarray, humans: np.ndarray, velocities: np.ndarray) -> Evasion | np.ndarray:
        """No plan found: brake straight, unless that step would take the human-robot BRT value below the
        pruner's margin; then the one step that keeps the value highest (the value function's own safety
        controller, its argmax over the controls), among those that stay clear of the walls and can still
        brake straight clear of them. Braking straight towards a human who turns into the car's path and
        does not yield to a moving robot was how FI-BRT's last Table IX contact began (measured)."""
        rows, controls = first_step(self.spec, float(state[2]))
        samples = place(rows, state)
        n, m = samples.shape[:2]
        times = np.minimum(np.arange(1, m + 1) * self.spec.dt / m, self.human_prediction_s)
        value = np.full(n, np.inf)
        for xy, v in zip(humans, velocities, strict=True):
            at = np.broadcast_to(xy + times[:, None] * v, (n, m, 2)).reshape(-1, 2)
            value = np.minimum(value, self.human_brt(samples.reshape(-1, 4), at).reshape(n, m).min(axis=1))
        brake = _stopping(rows, controls, float(state[2]))[0]  # the straight step closest to rest
        if value[brake] >= self.fi.margin or not (clear := self._stops_clear(state, samples)).any():
            stop = self._stop(state)
            return np.zeros((0, 2)) if stop is None else stop
        best = int(np.argmax(np.where(clear, value, -np.inf)))
        return Evasion(controls[best:best + 1])

    def _stops_clear(self, state: np.ndarray, samples: np.ndarray) -> np.ndarray:
        """Per first-step segment (P, S, 4) from ``state``: swept clear of the walls, and braking straight
        from its end stops clear of them too."""
        n = len(samples)
        swept = self._obs.swept(np.broadcast_to(state, (n, 4)), samples, np.full(n, self.spec.dt))
        return np.array([not hit and self._brakes_clear(seg[-1:]) for hit, seg in zip(swept, samples, strict=True)])

    def _stop(self, state: np.ndarray) -> np.ndarray | Evasion | None:
        """No plan in force: brake straight (the simulator's fallback, an empty command list) where that stops
        clear of the walls; else the first step, swept clear, after which braking straight does, the one ending
        nearest rest first (``_stopping``: a one-step safety controller, re-decided at every re-plan); None
        where no step does.
        Braking straight from 1 m/s needs 1 m: a car that gave up a plan turning away from a wall 0.4 m ahead
        (its re-check from a pose 2 cm off failed) braked straight into it (a Dense Room wall hit, measured)."""
        if state[2] == 0.0 or self._brakes_clear(state[None]):
            return np.zeros((0, 2))
        rows, controls = first_step(self.spec, float(state[2]))
        clear = self._stops_clear(state, place(rows, state))
        if not clear.any():
            return None
        order = _stopping(rows, controls, float(state[2]), straight=False)
        best = int(order[np.argmax(clear[order])])
        return Evasion(controls[best:best + 1])

    def _remaining_s(self, observation) -> float:
        """Time left on the plan in force for this goal (inf without one)."""
        if self._current is None or self._current[0] != tuple(observation.goal):
            return np.inf
        _, issued, plan = self._current
        return len(plan) * self.spec.dt - (float(observation.time) - issued)

    def _brakes_clear(self, states: np.ndarray) -> bool:
        """Braking straight to a stop from each of ``states`` stays clear of the walls: the lattice's lowest
        acceleration (ω = 0) going forwards, its highest reversing (the simulator's fallback, ``hj.receding_horizon``)."""
        stops = []
        for s in states:
            if s[2] != 0.0:
                brake = min(self.spec.accelerations) if s[2] > 0.0 else max(self.spec.accelerations)
                span = s[2] / -brake
                stops.append(integrate(s, brake, 0.0, span, max(1, int(np.ceil(span / 0.05))), self.spec.v_range))
        return not stops or bool((self.room.signed_distance(*np.concatenate(stops)[:, :2].T, self.robot_radius) > 0.0).all())

    def _still_safe(self, observation, static: StaticPruner, human) -> bool:
        """The next ``reuse_horizon_s`` of the current plan (same goal), replayed from the observed pose, is
        collision-free and passes the human pruner, and the simulator's fallback stays collision-free:
        braking straight (the lattice's lowest acceleration, ω = 0) from any point of the plan's current
        step, where the next re-plan may find no plan. Without that, a car kept on plans at 1 m/s towards a
        wall braked too late once the re-check failed (a Dense Room wall hit, measured). Where braking now
        would not stop clear either, the collision-free plan is kept: refusing it only brakes into the wall
        (a Long Hallway wall hit, measured)."""
        if self._current is None or self._current[0] != tuple(observation.goal):
            return False
        _, issued, plan = self._current
        dt, n = self.spec.dt, self.spec.samples_per_step
        elapsed = float(observation.time) - issued
        k = int((elapsed + 1e-9) // dt)
        if k >= len(plan):
            return False
        state = np.asarray(observation.robot, dtype=float)
        parents, segments, starts, durations = [], [], [], []
        end = min(len(plan), k + 1 + int(np.ceil(self.reuse_horizon_s / dt)))
        for i in range(k, end):
            duration = dt - (elapsed - k * dt) if i == k else dt
            if duration <= 1e-9:
                continue
            seg = integrate(state, float(plan[i, 0]), float(plan[i, 1]), duration, n, self.spec.v_range)
            parents.append(state)
            segments.append(seg)
            starts.append(sum(durations))
            durations.append(duration)
            state = seg[-1]
        if not segments:
            return False
        parents, segments = np.array(parents), np.array(segments)
        if not self._brakes_clear(segments[0]) and self._brakes_clear(np.asarray(observation.robot, float)[None]):
            return False  # braking now is the escape the plan would give up
        check = static if static.name == "OBS" else self._obs  # with "obs": the humans' discs too
        if check.swept(parents, segments, np.array(durations)).any():
            return False
        return not (human.kind != NO_HUMAN.kind and human(parents, segments, np.array(starts), np.array(durations)).any())


def _stopping(rows: np.ndarray, controls: np.ndarray, v: float, straight: bool = True) -> np.ndarray:
    """First-step primitive indices (``first_step``'s rows and controls from speed ``v``) ordered by how near
    rest each ends, then by the harder braking (towards 0 from either side: a car that reverses brakes with
    a > 0), then by the least turning; ``straight``: only those with ω = 0. Why not simply the lowest
    acceleration: from rest, or reversing, that one drives (further) backwards."""
    order = np.lexsort((np.abs(controls[:, 1]), controls[:, 0] * np.sign(v), np.abs(rows[:, -1, 2])))
    return order[controls[order, 1] == 0.0] if straight else order
