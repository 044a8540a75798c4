"""Receding-horizon execution of a 4D Dubins car among moving humans (HJ-search paper Sec. VIII-A).

The paper's robot re-plans at 12 Hz and its controller executes the first commands of each plan at
25 Hz, unmodified. This module does the same in simulated time: the clock ticks at the control rate;
whenever a re-plan is due the planner gets a (noisy) observation and returns a sequence of (a, ω)
commands, each held for exactly the planner's step ``dt`` (a tick that straddles a step boundary is
split there); the car integrates them under the paper's Eq. (19) (``search.dubins_lattice.integrate``),
so from the observed state it drives the very trajectory the planner checked. A planner that finds no plan
returns an empty sequence and the car brakes with ``a_min`` and ω = 0 (an emergency stop); a planner that
returns ``None`` found no new plan but vouches for the one the car is executing (re-checked, see
``hj.lattice_policy``): the car goes on with it, in step with the time it was issued, as the paper's
controller keeps executing the last action sequence it received.

A trip from one goal to the next ends as the paper scores it (Sec. VIII-A): success when the car is
within the goal tolerance; failure on a collision with a static obstacle, a *deadlock* (no progress of
``deadlock_progress_m`` towards the goal within ``deadlock_s``) or a timeout. A failed trip is an
"external intervention": the car is put down, stopped, at that trip's goal and the patrol goes on.
Contacts with humans (robot disc overlapping a human disc) are counted, each contact once, and make the
trip unsuccessful without stopping it, so Table IX's collision counts and times can both be read off.

Planning time is measured (wall clock) and recorded but does not delay the commands: the planner's
budget is deterministic (expansions), so a seeded run gives the same numbers on any machine.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from navlab.search.dubins_lattice import integrate


@dataclass(frozen=True)
class Observation:
    """What the planner sees at a re-plan: noisy poses, the current goal, the time."""

    time: float
    robot: np.ndarray  # (4,) x, y, v, θ (pose noise added)
    goal: tuple[float, float]
    humans: np.ndarray  # (H, 2) observed positions (noise added)
    human_velocities: np.ndarray  # (H, 2) estimates from the observations (``HumanTracks``)


@dataclass(frozen=True)
class Evasion:
    """Commands a planner issues without a plan it searched and checked (an evasive manoeuvre where the
    search found none): executed like a plan, counted like braking (no plan in force)."""

    commands: np.ndarray  # (K, 2) (a, ω)


class Planner(Protocol):
    dt: float  # s each returned command is held

    def __call__(self, observation: Observation) -> np.ndarray | Evasion | None: ...  # (K, 2) (a, ω); empty:
    # no plan (brake); None: no new plan, keep executing the current one; Evasion: no plan, but these commands


class Human(Protocol):
    position: np.ndarray
    velocity: np.ndarray

    def step(self, dt: float, robot_xy: np.ndarray, robot_speed: float) -> None: ...


@dataclass(frozen=True)
class SimSettings:
    replan_hz: float = 12.0
    control_hz: float = 25.0
    robot_radius: float = 0.285
    human_radius: float = 0.3
    v_max: float = 1.0
    a_min: float = -0.5
    goal_tolerance: float = 0.25
    trip_timeout_s: float = 60.0
    deadlock_s: float = 10.0
    deadlock_progress_m: float = 0.3
    pose_noise_m: float = 0.0  # std of the robot's own position estimate (the rooms: localisation)
    human_noise_m: float = 0.0  # std of each observed human position
    velocity_window_s: float = 0.5  # a human's velocity: its observed displacement over this long
    human_speed: float = 0.8  # m/s: a human moving 0.5 m further than this allows between observations is a new track
    # the car's reverse speed limit (< 0: it reverses, paper Sec. VII-A; 0: forward only) and its acceleration
    # bound, with which a reversing car brakes; hj.scenarios passes hj.grids.robot's v_min and accel_max
    v_min: float = 0.0
    a_max: float = 0.5

    def __post_init__(self):
        for name in ("replan_hz", "control_hz", "robot_radius", "v_max", "goal_tolerance", "trip_timeout_s",
                     "deadlock_s", "deadlock_progress_m"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"SimSettings.{name} must be a positive finite number, got {value}")
        if not (self.velocity_window_s > 0 and self.human_speed > 0):
            raise ValueError("SimSettings: velocity_window_s and human_speed must be > 0")
        if not (self.human_radius >= 0 and self.pose_noise_m >= 0 and self.human_noise_m >= 0):
            raise ValueError("SimSettings: human_radius and the noise levels must be >= 0")
        if not self.a_min < 0 < self.a_max:
            raise ValueError(f"SimSettings: need a_min < 0 < a_max (braking either way), got {self.a_min}, {self.a_max}")
        if not -self.v_max <= self.v_min <= 0.0:
            raise ValueError(f"SimSettings.v_min must lie in [-v_max, 0], got {self.v_min}")


@dataclass
class Trip:
    start: tuple[float, float]
    goal: tuple[float, float]
    outcome: str = "running"  # success | collision | deadlock | timeout
    time_s: float = 0.0
    human_contacts: int = 0
    replans: int = 0
    failed_replans: int = 0  # re-plans without a new plan (the car braked or kept its plan)
    kept_plans: int = 0  # of those, the ones where the car kept executing its previous plan
    contacts_braking: int = 0  # human contacts that began with no plan in force (braking, stopped or evading)

    @property
    def success(self) -> bool:
        return self.outcome == "success" and self.human_contacts == 0


@dataclass
class Run:
    trips: list[Trip] = field(default_factory=list)
    trajectory: list[np.ndarray] = field(default_factory=list)  # per tick: (t, x, y, v, θ)
    humans: list[np.ndarray] = field(default_factory=list)  # per tick: (H, 2)
    plan_seconds: list[float] = field(default_factory=list)
    cpu_s: float = 0.0  # CPU seconds the whole run took (recorded, never simulated: the run does not depend on it)
    plans: list[tuple[float, np.ndarray]] = field(default_factory=list)  # (time, commands) when kept

    @property
    def navigation_time(self) -> float:
        return float(sum(t.time_s for t in self.trips))

    @property
    def collisions(self) -> int:
        return int(sum(t.human_contacts for t in self.trips) + sum(t.outcome == "collision" for t in self.trips))


class HumanTracks:
    """Velocity estimates from noisy observed positions: the displacement over ``window_s`` (a two-point
    difference at 12 Hz turns 5 cm of noise into ~0.85 m/s of velocity noise; over 0.5 s, ~0.14 m/s). A
    human seen 0.5 m further than ``speed`` allows since the last observation (a new human of a Zig-Zag
    stream, or a lost track) starts afresh, with velocity 0 until it has history."""

    def __init__(self, window_s: float, speed: float):
        self.window_s, self.speed = window_s, speed
        self._history: list[tuple[float, np.ndarray]] = []  # (t, seen (H, 2)) over the last window
        self._since = np.zeros(0)  # (H,) when each human's track began

    def update(self, t: float, seen: np.ndarray) -> np.ndarray:
        if not self._history or self._history[-1][1].shape != seen.shape:
            self._history, self._since = [], np.full(len(seen), t)
        else:
            t_last, last = self._history[-1]
            jump = np.hypot(*(seen - last).T) > self.speed * (t - t_last) + 0.5
            self._since[jump] = t
        self._history = [(s, p) for s, p in self._history if t - s <= self.window_s + 1e-9]
        velocities = np.zeros_like(seen)
        for h in range(len(seen)):
            old = next(((s, p[h]) for s, p in self._history if s >= self._since[h]), None)
            if old is not None and t > old[0]:
                velocities[h] = (seen[h] - old[1]) / (t - old[0])
        self._history.append((t, seen.copy()))
        return velocities


def _drive(state: np.ndarray, commands: np.ndarray, elapsed: float, tick: float, dt: float,
           settings: SimSettings) -> np.ndarray:
    """The car's state one control tick on: each command held for exactly its ``dt`` of the plan (a tick
    that straddles a step boundary is split there, as the planner integrated it), its speed within
    [v_min, v_max]; braking straight to rest once the plan has run out (``a_min`` going forwards, ``a_max``
    reversing, ω = 0: the speed stops at 0, it does not drive on backwards)."""
    end = elapsed + tick
    while elapsed < end - 1e-12:
        k = int((elapsed + 1e-9) // dt)
        h = min(end, (k + 1) * dt) - elapsed if k < len(commands) else end - elapsed
        if k < len(commands):
            (a, omega), speeds = commands[k], (settings.v_min, settings.v_max)
        else:
            forwards = state[2] >= 0.0
            a, omega = (settings.a_min if forwards else settings.a_max), 0.0
            speeds = (0.0, settings.v_max) if forwards else (settings.v_min, 0.0)
        state = integrate(state, float(a), float(omega), h, max(1, round(4 * h / tick)), speeds)[-1]
        elapsed += h
    return state


def run_patrol(
    planner: Planner,
    obstacle_distance: Callable[[np.ndarray, np.ndarray], np.ndarray],
    start: np.ndarray,
    goals: Sequence[tuple[float, float]],
    humans: Sequence[Human],
    settings: SimSettings,
    rng: np.random.Generator,
    *,
    keep_plans: bool = False,
) -> Run:
    """Drive from ``start`` (x, y, v, θ) through ``goals`` in order, one trip per goal.

    ``obstacle_distance(x, y)`` is the signed distance to the static obstacles (negative inside), e.g.
    ``maps.rooms.Room.obstacle_distance``. The run is a pure function of its arguments and ``rng``.
    """
    state = np.asarray(start, dtype=float).copy()
    if state.shape != (4,) or not np.isfinite(state).all():
        raise ValueError(f"start must be a finite (x, y, v, θ) state, got {start}")
    if float(obstacle_distance(state[0], state[1])) < settings.robot_radius:
        raise ValueError(f"start {tuple(state[:2])} is in collision with a static obstacle; choose a free start")
    tick = 1.0 / settings.control_hz
    run, t, cpu0 = Run(), 0.0, time.process_time()
    tracks = HumanTracks(settings.velocity_window_s, settings.human_speed)
    for goal in goals:
        goal = (float(goal[0]), float(goal[1]))
        trip = Trip(start=(float(state[0]), float(state[1])), goal=goal)
        run.trips.append(trip)
        commands, plan_time, next_replan, evading = np.zeros((0, 2)), t, t, False
        best_dist, best_time, touching = math.hypot(goal[0] - state[0], goal[1] - state[1]), t, False
        trip_start = t
        while trip.outcome == "running":
            if t >= next_replan - 1e-9:
                seen = np.array([h.position for h in humans], dtype=float).reshape(-1, 2)
                seen = seen + rng.normal(0.0, settings.human_noise_m, seen.shape) if len(seen) else seen
                velocities = tracks.update(t, seen)
                pose = state.copy()
                pose[:2] += rng.normal(0.0, settings.pose_noise_m, 2)
                began = time.perf_counter()
                new = planner(Observation(t, pose, goal, seen, velocities))
                run.plan_seconds.append(time.perf_counter() - began)
                trip.replans += 1
                if new is None:  # keep executing the current plan (and its clock)
                    trip.failed_replans += 1
                    trip.kept_plans += 1
                else:
                    evading = isinstance(new, Evasion)
                    commands, plan_time = np.asarray(new.commands if evading else new, dtype=float), t
                    if len(commands) == 0 or evading:
                        trip.failed_replans += 1
                    elif keep_plans:
                        run.plans.append((t, commands.copy()))
                next_replan += 1.0 / settings.replan_hz
            k = int((t - plan_time + 1e-9) // planner.dt)
            state = _drive(state, commands, t - plan_time, tick, planner.dt, settings)
            t += tick
            for h in humans:
                h.step(tick, state[:2], state[2])
            run.trajectory.append(np.array([t, *state]))
            run.humans.append(np.array([h.position for h in humans], dtype=float).reshape(-1, 2))
            gaps = [math.hypot(*(h.position - state[:2])) for h in humans]
            now_touching = bool(gaps) and min(gaps) < settings.robot_radius + settings.human_radius
            if now_touching and not touching:
                trip.human_contacts += 1
                trip.contacts_braking += int(k >= len(commands) or evading)
            touching = now_touching
            dist = math.hypot(goal[0] - state[0], goal[1] - state[1])
            if dist < best_dist - settings.deadlock_progress_m:
                best_dist, best_time = dist, t
            if dist <= settings.goal_tolerance:
                trip.outcome = "success"
            elif float(obstacle_distance(state[0], state[1])) < settings.robot_radius:
                trip.outcome = "collision"
            elif t - best_time > settings.deadlock_s:
                trip.outcome = "deadlock"
            elif t - trip_start > settings.trip_timeout_s:
                trip.outcome = "timeout"
        trip.time_s = t - trip_start
        if trip.outcome != "success":  # external intervention: put the car down at the goal, stopped
            state = np.array([goal[0], goal[1], 0.0, state[3]])
    run.cpu_s = time.process_time() - cpu0
    return run
