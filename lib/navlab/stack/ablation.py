"""The stack and its ablation on the same episodes (issue 64): each layer replaced by its simpler counterpart,
one at a time — label costs for PACER's, D* Lite for SuReNav's relaxation, grid A* with a point check for
HJ-search's planner — and per episode the robot's own path measured: success, time, pedestrian contacts,
the share of the path on the operator's preferred terrain tier (PACER's metric), Fréchet distance and
relaxation IoU against SuReNav's context demonstrator, SPL.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import ndimage

from navlab.core.labels import HARD_IDS
from navlab.core.params import Params
from navlab.metrics.cost_tiers import cost_tier_proportions
from navlab.metrics.frechet import normalised_frechet
from navlab.metrics.intervals import bootstrap_mean_ci
from navlab.metrics.navigation import shortest_feasible_length, spl
from navlab.metrics.relaxation import relaxed_regions, set_iou
from navlab.pacer.preferences import environment_tiers
from navlab.pacer.terrain import TerrainBank
from navlab.pacer.train import load_model
from navlab.stack.motion import HJFollower, PointCheckFollower, allowed_ground
from navlab.stack.route import TerrainDStarLite, TerrainSuReNavPolicy, expert_route, walk_route
from navlab.stack.terrain import label_costs, pacer_costs
from navlab.stack.world import StackEpisode, arc_length
from navlab.surenav.context.dataset import load_context_demos
from navlab.surenav.context.training import context_cost, main_run
from navlab.surenav.demo_priors import dstar_label_costs, label_traversal

STACK = "stack (PACER + SuReNav + HJ-search)"
NO_PACER = "label costs for PACER"
NO_SURENAV = "D* Lite for SuReNav"
NO_HJ = "grid A*, point check for HJ-search"
ROWS = (STACK, NO_PACER, NO_SURENAV, NO_HJ)
METRICS = ("success", "time_s", "contacts", "low_tier", "frechet", "relaxation_iou", "spl")
GOAL_REACHED_M = 0.5  # the robot is at the goal cell's centre within this distance


@dataclass(frozen=True)
class Drive:
    trajectory: np.ndarray  # (T, 5): t, x, y, v, theta
    outcome: str  # success, collision, timeout, no_route
    contacts: int  # pedestrian contacts (disc overlaps begun)
    plan_seconds: np.ndarray  # wall time of every re-plan


def _lookahead(route: np.ndarray, arc: np.ndarray, progress: float, distance: float) -> tuple[np.ndarray, bool]:
    s = min(progress + distance, arc[-1])
    return np.array([np.interp(s, arc, route[:, 0]), np.interp(s, arc, route[:, 1])]), s >= arc[-1]


def drive(episode: StackEpisode, route_xy: np.ndarray, allowed: np.ndarray, follower, params: Params,
          hard: Callable[[np.ndarray], float] | None = None) -> Drive:
    """The motion layer following ``route_xy`` (world metres) on ``allowed`` ground among the episode's
    pedestrians, a re-plan every 1 / ``stack.replan_hz`` s of simulated time, until the goal, a static
    collision (clearance below the robot's radius on the truth's hard ground) or ``stack.timeout_s``.

    The route is the route layer's walk, finished first (SuReNav's executor senses and re-plans on its own,
    Algorithm 1); where that walk went into a dead end and came back (it met the blockage), the robot,
    standing where the walk returns, skips the spur: the layers hand over a route, not a shared clock.
    ``hard``: the episode's ``hard_distance`` (built here when not given; an episode's rows share one)."""
    S, res = params.stack, episode.prior.frame.resolution
    dt, reach = 1.0 / S.replan_hz, params.hj.grids.robot.radius_m + params.hj.grids.human.radius_m
    origin = np.asarray(episode.prior.frame.origin, dtype=float)
    route = route_xy - origin
    arc = arc_length(route)
    heading = math.atan2(*(route[min(3, len(route) - 1)] - route[0])[::-1])
    state = np.array([route[0, 0], route[0, 1], 0.0, heading])
    hard = hard_distance(episode) if hard is None else hard
    rows, seconds, contacts, touching, progress = [], [], 0, np.zeros(len(episode.walkers), bool), 0.0
    outcome, t = "timeout", 0.0
    while t < S.timeout_s:
        rows.append([t, *(state[:2] + origin), *state[2:]])
        ahead = np.flatnonzero((arc >= progress) & (arc <= progress + 2 * S.lookahead_m))
        gaps = np.linalg.norm(route[ahead] - state[:2], axis=1)
        here = ahead[gaps <= GOAL_REACHED_M]  # the route may come back here (a dead end it walked): skip it
        progress = float(arc[here.max()] if len(here) else arc[ahead[np.argmin(gaps)]])
        if np.linalg.norm(state[:2] - route[-1]) <= GOAL_REACHED_M:
            outcome = "success"
            break
        goal, final = _lookahead(route, arc, progress, S.lookahead_m)
        offset = goal - state[:2]  # kept inside the window (the route may bend back towards the robot)
        goal = state[:2] + offset * min(1.0, (S.window_m / 2 - 0.5) / max(np.linalg.norm(offset), 1e-9))
        humans = np.array([w.position(t) - origin for w in episode.walkers]).reshape(-1, 2)
        began = time.perf_counter()
        state = follower.step(state, allowed, res, goal, final, humans, dt).state
        seconds.append(time.perf_counter() - began)
        t += dt
        humans = np.array([w.position(t) - origin for w in episode.walkers]).reshape(-1, 2)
        now = np.linalg.norm(humans - state[:2], axis=1) < reach if len(humans) else touching
        contacts += int(np.sum(now & ~touching))
        touching = now
        if hard(state[:2]) < params.hj.grids.robot.radius_m - S.window_resolution_m / 2:  # the rasters' exactness
            outcome = "collision"
            break
    rows.append([t, *(state[:2] + origin), *state[2:]])
    return Drive(np.array(rows), outcome, contacts, np.array(seconds))


def hard_distance(episode: StackEpisode) -> Callable[[np.ndarray], float]:
    """xy (box metres) -> distance (m) to the truth's hard cells (a building, water, the blockage)."""
    res = episode.prior.frame.resolution
    hard = np.isin(episode.truth, HARD_IDS)
    fine = 10  # 0.1 m at 1 m cells
    hard = np.repeat(np.repeat(hard, fine, 0), fine, 1)
    sdf = (ndimage.distance_transform_edt(~hard) - 0.5) * res / fine if hard.any() else np.full(hard.shape, 1e6)

    def distance(xy: np.ndarray) -> float:
        return float(ndimage.map_coordinates(sdf, [[xy[1] * fine / res - 0.5], [xy[0] * fine / res - 0.5]],
                                             order=1, mode="nearest")[0])
    return distance


@dataclass(frozen=True)
class Outcome:
    row: str
    episode: str
    outcome: str
    values: dict[str, float]  # METRICS
    plan_seconds: np.ndarray
    trajectory: np.ndarray
    route_cells: np.ndarray


def _cells(episode: StackEpisode, xy: np.ndarray) -> np.ndarray:
    cells = episode.prior.frame.world_to_cell(xy)
    cells = np.clip(cells, 0, np.array(episode.truth.shape) - 1)
    keep = np.concatenate([[True], np.any(np.diff(cells, axis=0) != 0, axis=1)])
    return cells[keep]


def measure(episode: StackEpisode, row: str, drive_: Drive, route_cells: np.ndarray, expert_cells: np.ndarray,
            bank_size: int) -> Outcome:
    res = episode.prior.frame.resolution
    frame = episode.prior.frame
    xy = drive_.trajectory[:, 1:3]
    cells = _cells(episode, xy)
    ok = drive_.outcome == "success" and drive_.contacts == 0
    length = float(np.linalg.norm(np.diff(xy, axis=0), axis=1).sum())
    shortest = shortest_feasible_length(episode.truth, episode.start, episode.goal, res)
    tiers = environment_tiers(episode.ordering, bank_size)
    ends = frame.cell_to_world(np.array([episode.start, episode.goal]))
    expert_xy = frame.cell_to_world(expert_cells)
    values = {"success": float(ok), "time_s": float(drive_.trajectory[-1, 0]), "contacts": float(drive_.contacts),
              "low_tier": cost_tier_proportions(cells, episode.terrain, tiers)["low"],
              "frechet": normalised_frechet(xy, expert_xy, ends[0], ends[1]),
              "relaxation_iou": set_iou(relaxed_regions(cells, episode.truth, episode.superpixels),
                                        relaxed_regions(expert_cells, episode.truth, episode.superpixels)),
              "spl": spl(ok, length, shortest)}
    return Outcome(row, episode.name, drive_.outcome, values, drive_.plan_seconds, drive_.trajectory, route_cells)


@dataclass(frozen=True)
class Layers:
    """What each row is made of: the terrain costs, the route policy's factory and the motion layer."""

    pacer: object  # (episode) -> (H, W) PACER costs
    labels: object  # (episode) -> (H, W) label-table costs
    surenav_cost: object  # () -> a fresh SuReNav relaxation cost (the trained context estimator)
    dstar_costs: np.ndarray  # (NUM_LABELS,) D* Lite's fitted cost per metre
    hj: object  # HJFollower
    point: object  # PointCheckFollower
    bank_size: int


def load_layers(params: Params, artifacts_dir: str, bank: TerrainBank) -> Layers:
    """Every layer from the three tracks' committed artefacts: PACER's phase-3 model, SuReNav's context
    estimator (its main run, seed 0) and D* Lite's costs fitted on the context training demonstrations,
    HJ-search's general TTR and human BRT grids."""
    s = params.surenav
    model = load_model(Path(artifacts_dir) / "pacer" / "phase3" / "model.pt", params.pacer.train.device).eval()
    train = load_context_demos(artifacts_dir, "train")
    dstar = dstar_label_costs(label_traversal([md for _, md in train], [m for m, _ in train]), s.benchmark.dstar_cost_floor)
    return Layers(lambda episode: pacer_costs(model, episode, params), lambda episode: label_costs(episode, bank),
                  context_cost(artifacts_dir, main_run(s.demos.context, s.train), seed=s.train.seeds[0]), dstar,
                  HJFollower(params, artifacts_dir), PointCheckFollower(params), len(bank))


def run_episode(episode: StackEpisode, layers: Layers, params: Params, rows=ROWS) -> list[Outcome]:
    """Every row on one episode (the paired design: the same world, route draws and pedestrians)."""
    S = params.stack
    expert = expert_route(episode, params).trajectory
    pacer, hard = layers.pacer(episode), hard_distance(episode)
    out = []
    for row in rows:
        terrain = layers.labels(episode) if row == NO_PACER else pacer
        policy = (TerrainDStarLite(layers.dstar_costs, terrain, S.terrain_weight) if row == NO_SURENAV else
                  TerrainSuReNavPolicy(layers.surenav_cost(), terrain, S.terrain_weight,
                                       params.surenav.model.window_margin_m))
        walked = walk_route(episode, policy, params)
        if walked.status != "reached":
            traj = np.array([[0.0, *episode.prior.frame.cell_to_world(np.array(episode.start)), 0.0, 0.0]])
            out.append(measure(episode, row, Drive(traj, "no_route", 0, np.zeros(0)), walked.trajectory, expert,
                               layers.bank_size))
            continue
        follower = layers.point if row == NO_HJ else layers.hj
        route_xy = episode.prior.frame.cell_to_world(walked.trajectory)
        allowed = allowed_ground(episode, walked.trajectory)
        out.append(measure(episode, row, drive(episode, route_xy, allowed, follower, params, hard), walked.trajectory,
                           expert, layers.bank_size))
    return out


def paired_rows(outcomes: list[Outcome], seed: int) -> list[dict]:
    """Per row and metric: the mean over episodes with its 95% bootstrap interval, and the row minus the
    stack, paired over the same episodes, with its interval."""
    rng = np.random.default_rng(seed)
    by_row = {row: {o.episode: o for o in outcomes if o.row == row} for row in ROWS}
    episodes = sorted(by_row[STACK])
    table = []
    for row in ROWS:
        entry = {"row": row, "episodes": len(episodes)}
        for metric in METRICS:
            mine = np.array([by_row[row][e].values[metric] for e in episodes])
            base = np.array([by_row[STACK][e].values[metric] for e in episodes])
            entry[metric] = [float(mine.mean()), *bootstrap_mean_ci(mine, rng)]
            if row != STACK:
                diff = mine - base
                entry[f"{metric}_vs_stack"] = [float(diff.mean()), *bootstrap_mean_ci(diff, rng)]
        table.append(entry)
    return table
