"""The stack's motion layer: HJ-search's lattice planner following the route among pedestrians, re-planning at
``stack.replan_hz`` in a square window around the robot, or grid A* with an instantaneous point check in its
place (the ablation's simpler counterpart).

The HJ follower (HJ-search Sec. IV-VI, as the paper runs it): A* over the 4D Dubins lattice (the reversing car
of ``hj.planner.lattice``) toward the route point ``stack.lookahead_m`` ahead, guided by the goal-centred
general TTR (inside its +-4 m grid), the window's ground checked by the paper's OBS point pruner (and the
swept check every accepted segment passes), the pedestrians in the window by the FI-BRT rule, frozen where
they are seen (prediction-free, Sec. IV). A plan that fails the dense feasibility check (replayed under the
dynamics) is not driven; with no plan the car brakes at its deceleration limit: it stops rather than collides
with the ground (a pedestrian may still walk into a stopped robot: counted as a contact).

The ground a window holds is what the route layer allows: free cells, and the soft regions its walked route
relaxed (SuReNav's R_free U R_rlx, at the map's cells); everything else, and the truth's hard cells, is an
obstacle, and so is the window's border.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from navlab.core.labels import FREE_IDS, HARD_IDS
from navlab.core.params import Params
from navlab.hj.grids import load_human_brt, load_ttr
from navlab.hj.guidance import ttr_heuristic
from navlab.hj.planning import lattice_spec
from navlab.hj.pruners import FIParams, human_pruner, obs_point_pruner, obs_pruner
from navlab.search.dubins_lattice import densify, primitive_table
from navlab.search.grid_astar import plan as grid_plan
from navlab.search.lattice_search import Budget, Goal, Pruners, search
from navlab.stack.world import StackEpisode, arc_length

# the pruners' clearance raster: the window's own cells are 0.1 m and exact to half of one, so a finer raster
# buys nothing; at 0.05 m it costs a quarter of the 0.02 m the rooms use (the swept check's allowance, half the
# raster's diagonal, is then 3.5 cm)
CLEARANCE_RESOLUTION_M = 0.05


def allowed_ground(episode: StackEpisode, route_cells: np.ndarray) -> np.ndarray:
    """(H, W) bool: free cells and the superpixels of the soft cells the route walked, minus the truth's hard."""
    truth = episode.truth
    walked = episode.superpixels[route_cells[:, 0], route_cells[:, 1]]
    relaxed = np.isin(episode.superpixels, walked[(walked >= 0) & ~np.isin(truth[route_cells[:, 0], route_cells[:, 1]],
                                                                          FREE_IDS)])
    allowed = np.isin(truth, FREE_IDS) | relaxed
    allowed[route_cells[:, 0], route_cells[:, 1]] = True
    return allowed & ~np.isin(truth, HARD_IDS)


class RasterRoom:
    """A window of a blocked/allowed raster as the HJ pruners read a room (``maps.rooms.Room``): signed
    distance to the blocked cells (and to the window's border), in the window's own frame (x right, y down,
    origin at its corner). The distance transform is exact to half a cell (0.05 m at 0.1 m cells)."""

    def __init__(self, blocked: np.ndarray, resolution: float):
        self.name, self.res = "stack window", resolution
        self.height, self.width = blocked.shape[0] * resolution, blocked.shape[1] * resolution
        outside = ndimage.distance_transform_edt(~blocked) if blocked.any() else np.full(blocked.shape, 1e6)
        self.sdf = np.where(blocked, 0.5 - ndimage.distance_transform_edt(blocked), outside - 0.5) * resolution

    @property
    def bounds(self):
        return (0.0, self.width), (0.0, self.height)

    def obstacle_distance(self, x, y) -> np.ndarray:
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        inside = ndimage.map_coordinates(self.sdf, [y.ravel() / self.res - 0.5, x.ravel() / self.res - 0.5],
                                         order=1, mode="nearest").reshape(x.shape)
        return np.minimum.reduce([inside, x, y, self.width - x, self.height - y])

    def signed_distance(self, x, y, robot_radius: float) -> np.ndarray:
        return self.obstacle_distance(x, y) - robot_radius


def window_blocked(allowed: np.ndarray, map_resolution: float, origin_xy, side_m: float, resolution: float) -> np.ndarray:
    """(n, n) bool at ``resolution``: the window's cells outside the allowed ground (or off the map)."""
    n = round(side_m / resolution)
    centres = (np.arange(n) + 0.5) * resolution
    rows = np.floor((origin_xy[1] + centres) / map_resolution).astype(np.int64)
    cols = np.floor((origin_xy[0] + centres) / map_resolution).astype(np.int64)
    on_map_r = (rows >= 0) & (rows < allowed.shape[0])
    on_map_c = (cols >= 0) & (cols < allowed.shape[1])
    ok = allowed[np.clip(rows, 0, allowed.shape[0] - 1)][:, np.clip(cols, 0, allowed.shape[1] - 1)]
    return ~(ok & on_map_r[:, None] & on_map_c[None, :])


def clear_point(room: RasterRoom, xy: np.ndarray, radius: float, humans: np.ndarray | None = None,
                keep_off_m: float = 0.0) -> np.ndarray:
    """``xy``, or the nearest point whose clearance exceeds the radius by a cell and which lies farther than
    ``keep_off_m`` from every pedestrian in ``humans`` (window frame), searched within a metre beyond that
    distance; ``xy`` itself where there is none. Why: a route drawn through 1 m cell centres may pass closer to
    a wall than the car fits, and a route point beside a standing pedestrian lies in its BRT, where no plan may
    end: the local goal steps aside (the planner then passes the pedestrian where the ground has room, and the
    car waits where it has none)."""
    humans = np.zeros((0, 2)) if humans is None else np.asarray(humans, dtype=float).reshape(-1, 2)

    def clear(x, y):
        ok = room.obstacle_distance(x, y) > radius + room.res
        for h in humans:
            ok &= np.hypot(x - h[0], y - h[1]) > keep_off_m
        return ok

    if clear(np.array([xy[0]]), np.array([xy[1]]))[0]:
        return xy
    search_m = 1.0 + (keep_off_m if len(humans) else 0.0)
    offsets = np.arange(-search_m, search_m + 1e-9, room.res)
    x, y = np.meshgrid(xy[0] + offsets, xy[1] + offsets)
    ok = clear(x, y)
    if not ok.any():
        return xy
    d = np.where(ok, np.hypot(x - xy[0], y - xy[1]), np.inf)
    k = np.unravel_index(np.argmin(d), d.shape)
    return np.array([x[k], y[k]])


def rest_keep_off(lookup, margin: float) -> float:
    """The farthest a car at rest (v = 0) can be from a pedestrian and still lie in the stored human-robot BRT
    (value <= ``margin``, any bearing), plus one grid cell: a goal at least this far from every pedestrian is
    one the FI / FS pruners can accept."""
    grid, values = lookup.grid, lookup.stored.values
    axes = [np.linspace(lo, hi, n) for lo, hi, n in zip(grid.lo, grid.hi, grid.shape)]
    rest = values[:, :, int(np.argmin(np.abs(axes[2])))]
    radius = np.hypot(*np.meshgrid(axes[0], axes[1], indexing="ij"))
    cell = max((hi - lo) / (n - 1) for lo, hi, n in zip(grid.lo[:2], grid.hi[:2], grid.shape[:2]))
    return float(radius[rest <= margin].max(initial=lookup.collision_radius)) + cell


@dataclass(frozen=True)
class Step:
    state: np.ndarray  # (x, y, v, theta) after the period
    planned: bool  # False: no feasible plan, the car braked


def brake(state: np.ndarray, dt: float, decel: float) -> np.ndarray:
    """The fall-back: straight ahead, speed to zero at the deceleration limit."""
    x, y, v, theta = state
    v_next = max(v - decel * dt, 0.0) if v >= 0 else min(v + decel * dt, 0.0)
    mean = 0.5 * (v + v_next)
    return np.array([x + mean * dt * math.cos(theta), y + mean * dt * math.sin(theta), v_next, theta])


class HJFollower:
    """HJ-search's planner as the stack's motion layer (see the module's docstring)."""

    def __init__(self, params: Params, artifacts_dir: str):
        self.params, S = params, params.stack
        self.spec = lattice_spec(params)
        self.ttr, self.human_brt = load_ttr(params, artifacts_dir), load_human_brt(params, artifacts_dir)
        fi = params.hj.planner.fi_brt
        self.fi = FIParams(fi.dt_s, fi.margin, fi.gamma_min, fi.gamma_max, fi.k_theta, fi.w_theta, fi.w_dist,
                           fi.d_threshold_m)
        self.radius = params.hj.grids.robot.radius_m
        self.decel = -params.hj.grids.robot.accel_min
        self.side, self.res = S.window_m, S.window_resolution_m
        self.table = primitive_table(self.spec)  # once: the search would rebuild it on every re-plan
        self.clearance_resolution_m = CLEARANCE_RESOLUTION_M
        self.keep_off_m = rest_keep_off(self.human_brt, fi.margin)

    def step(self, state: np.ndarray, allowed: np.ndarray, map_resolution: float, goal_xy, final: bool,
             humans: np.ndarray, dt: float) -> Step:
        origin = state[:2] - self.side / 2
        room = RasterRoom(window_blocked(allowed, map_resolution, origin, self.side, self.res), self.res)
        local = state - [origin[0], origin[1], 0.0, 0.0]
        near = humans[np.linalg.norm(humans - state[:2], axis=1) <= self.side] - origin if len(humans) else humans
        goal = clear_point(room, np.asarray(goal_xy, dtype=float) - origin, self.radius, near, self.keep_off_m)
        P = self.params.hj.planner
        pruners = Pruners(static=obs_point_pruner(room, self.radius, self.clearance_resolution_m),
                          collision=obs_pruner(room, self.radius, self.clearance_resolution_m),
                          **({"human": human_pruner(self.human_brt, near, "fi", self.fi)} if len(near) else {}))
        try:
            result = search(self.spec, room.bounds, local, Goal(tuple(goal), P.goal_tolerance_astar_m,
                                                                P.goal_max_speed if final else self.spec.v_max),
                            ttr_heuristic(self.ttr, goal), pruners=pruners, table=self.table,
                            budget=Budget(False, self.params.stack.max_expansions))
        except ValueError:  # the start or the goal wholly pruned (a pedestrian on it, the car grazing a wall)
            return Step(brake(state, dt, self.decel), False)
        if not result.found or len(result.controls) == 0:
            return Step(brake(state, dt, self.decel), False)
        dense = densify(self.spec, result.states[0], result.controls)
        if room.signed_distance(dense[:, 0], dense[:, 1], self.radius).min() <= 0.0:  # the dense check
            return Step(brake(state, dt, self.decel), False)
        per = self.spec.dt / (self.spec.samples_per_step * self.spec.micro_steps)
        position = min(dt / per, len(dense) - 1)
        lo = int(position)
        hi, w = min(lo + 1, len(dense) - 1), position - lo
        nxt = (1 - w) * dense[lo] + w * dense[hi]
        nxt[3] = dense[lo, 3] + w * math.remainder(dense[hi, 3] - dense[lo, 3], 2 * math.pi)
        return Step(nxt + [origin[0], origin[1], 0.0, 0.0], True)


class PointCheckFollower:
    """The ablation's motion layer: grid A* on the window's ground (inflated by the robot's radius) with the
    pedestrians as discs where they are now (an instantaneous point check), driven at full speed with no
    dynamics; no plan: it stands."""

    def __init__(self, params: Params):
        self.params, S = params, params.stack
        self.radius = params.hj.grids.robot.radius_m
        self.reach = self.radius + params.hj.grids.human.radius_m
        self.v_max = params.hj.grids.robot.v_max
        self.side, self.res = S.window_m, S.window_resolution_m

    def step(self, state: np.ndarray, allowed: np.ndarray, map_resolution: float, goal_xy, final: bool,
             humans: np.ndarray, dt: float) -> Step:
        origin = state[:2] - self.side / 2
        room = RasterRoom(window_blocked(allowed, map_resolution, origin, self.side, self.res), self.res)
        centres = (np.arange(round(self.side / self.res)) + 0.5) * self.res
        x, y = np.meshgrid(centres, centres)
        free = room.obstacle_distance(x, y) > self.radius
        for h in humans - origin:
            free &= np.hypot(x - h[0], y - h[1]) > self.reach
        here = tuple(np.clip(np.floor((state[[1, 0]] - origin[::-1]) / self.res).astype(int), 0, len(centres) - 1))
        goal = clear_point(room, np.asarray(goal_xy, dtype=float) - origin, self.radius, humans - origin,
                           self.reach + self.res)
        there = tuple(np.clip(np.floor(goal[::-1] / self.res).astype(int), 0, len(centres) - 1))
        free[here] = True
        found = grid_plan(np.where(free, 1.0, np.inf), here, there, resolution=self.res).cells if free[there] else None
        if found is None or len(found) < 2:
            return Step(np.array([*state[:2], 0.0, state[3]]), False)
        path = np.column_stack([centres[found[:, 1]], centres[found[:, 0]]]) + origin
        path[0] = state[:2]
        arc = arc_length(path)
        s = min(self.v_max * dt, arc[-1])
        xy = np.array([np.interp(s, arc, path[:, 0]), np.interp(s, arc, path[:, 1])])
        heading = math.atan2(*(xy - state[:2])[::-1]) if s > 0 else state[3]
        return Step(np.array([xy[0], xy[1], s / dt, heading]), True)
