"""Simulated pedestrians for the HJ-search closed-loop tests (paper Sec. VII-D and VIII-C).

The paper's humans are point masses at a constant 0.8 m/s. In the simulation tests (Table VI) they do
not react to the robot at all: one walks a straight line (Face-to-Face), or a stream of them walks the
same line, a new one spawned at the start as soon as the last reaches the end (Zig-Zag). In the patrol
tests (Tables VIII-IX) a human follows three rules, which :class:`PatrolHuman` implements literally:

1. walk between pre-set points of interest (POIs), in order, cyclically;
2. avoid the robot only when it is stationary — a moving robot is not yielded to (the human is a
   non-cooperative dynamic obstacle); a stopped robot on the way is walked around;
3. switch to the next POI when the current one is occupied by the robot.

Every human exposes ``position`` and ``velocity`` (m, m/s) and a ``step(dt, robot_xy, robot_speed)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

STOPPED_SPEED = 0.05  # m/s: below this the robot counts as stationary (rule 2)


def _towards(position: np.ndarray, target: np.ndarray, speed: float, dt: float) -> tuple[np.ndarray, bool]:
    """Velocity that walks ``position`` to ``target`` at ``speed`` without overshooting in ``dt``."""
    delta = target - position
    dist = float(np.hypot(*delta))
    if dist <= speed * dt or dist == 0.0:
        return delta / dt if dt > 0 else np.zeros(2), True
    return delta / dist * speed, False


@dataclass
class StraightWalker:
    """A non-reactive human walking from ``start`` to ``goal`` at ``speed`` and then standing still."""

    start: tuple[float, float]
    goal: tuple[float, float]
    speed: float = 0.8
    position: np.ndarray = field(init=False)
    velocity: np.ndarray = field(init=False)

    def __post_init__(self):
        if not self.speed > 0:
            raise ValueError(f"human speed must be > 0 m/s, got {self.speed}")
        self.position = np.asarray(self.start, dtype=float).copy()
        self.velocity = np.zeros(2)

    def step(self, dt: float, robot_xy: np.ndarray, robot_speed: float) -> None:
        self.velocity, _ = _towards(self.position, np.asarray(self.goal, float), self.speed, dt)
        self.position = self.position + self.velocity * dt


@dataclass
class HumanStream(StraightWalker):
    """Zig-Zag (Sec. VII-D): on reaching ``goal`` the human is replaced by a new one at ``start``, once the
    robot is at least ``clear_m`` from ``start`` (the one that arrived waits at ``goal`` till then). The
    paper spawns at once; a human appearing on top of a robot that crosses near the start is a contact no
    planner could avoid (measured: one of FI-BRT's Zig-Zag contacts), and a real person would not walk into
    an occupied doorway."""

    clear_m: float = 0.0
    spawned: int = field(init=False, default=1)

    def step(self, dt: float, robot_xy: np.ndarray, robot_speed: float) -> None:
        self.velocity, arrived = _towards(self.position, np.asarray(self.goal, float), self.speed, dt)
        if arrived and float(np.hypot(*(np.asarray(self.start, float) - robot_xy))) < self.clear_m:
            self.position, self.velocity = np.asarray(self.goal, dtype=float).copy(), np.zeros(2)
        elif arrived:
            self.position = np.asarray(self.start, dtype=float).copy()
            self.velocity = np.zeros(2)
            self.spawned += 1
        else:
            self.position = self.position + self.velocity * dt


@dataclass
class PatrolHuman:
    """A human patrolling POIs under the paper's three rules (Sec. VIII-C)."""

    pois: tuple[tuple[float, float], ...]
    speed: float = 0.8
    occupied_radius: float = 0.6  # m: the robot within this of a POI occupies it (rule 3)
    avoid_radius: float = 1.0  # m: a stopped robot closer than this on the way is walked around (rule 2)
    position: np.ndarray = field(init=False)
    velocity: np.ndarray = field(init=False)
    target: int = field(init=False, default=1)
    switches: int = field(init=False, default=0)
    detours: int = field(init=False, default=0)

    def __post_init__(self):
        if len(self.pois) < 2:
            raise ValueError(f"a patrolling human needs at least 2 points of interest, got {len(self.pois)}")
        if not self.speed > 0:
            raise ValueError(f"human speed must be > 0 m/s, got {self.speed}")
        self.position = np.asarray(self.pois[0], dtype=float).copy()
        self.velocity = np.zeros(2)

    def _occupied(self, index: int, robot_xy: np.ndarray) -> bool:
        return float(np.hypot(*(np.asarray(self.pois[index]) - robot_xy))) <= self.occupied_radius

    def step(self, dt: float, robot_xy: np.ndarray, robot_speed: float) -> None:
        robot_xy = np.asarray(robot_xy, dtype=float)
        if self._occupied(self.target, robot_xy):  # rule 3: pick the next free POI
            for k in range(1, len(self.pois)):
                candidate = (self.target + k) % len(self.pois)
                if not self._occupied(candidate, robot_xy):
                    self.target, self.switches = candidate, self.switches + 1
                    break
        velocity, arrived = _towards(self.position, np.asarray(self.pois[self.target], float), self.speed, dt)
        to_robot = robot_xy - self.position
        dist = float(np.hypot(*to_robot))
        if abs(robot_speed) < STOPPED_SPEED and 0 < dist < self.avoid_radius and velocity @ to_robot > 0:
            # rule 2: walk around a stationary robot ahead: drop the heading's part towards it (never
            # closer), keep the tangential part; head-on, take the side the heading already leans to
            radial = to_robot / dist
            tangent = velocity - (velocity @ radial) * radial
            if np.hypot(*tangent) < 1e-6 * self.speed:
                tangent = np.array([-radial[1], radial[0]])
            velocity = tangent / np.hypot(*tangent) * self.speed
            self.detours += 1
            arrived = False
        self.velocity = velocity
        self.position = self.position + velocity * dt
        if arrived:
            self.target = (self.target + 1) % len(self.pois)
