"""Interleaved planning and execution in a semi-static map (SuReNav Algorithm 1, Sec. V).

The walker starts with the prior map as its belief. Each step it observes the true labels within the
sensor radius, writes them into its belief, updates the region graph incrementally where the belief
changed (``graphs.incremental``: "G_t <- update(G_{t-1}, R_t)"), re-plans, and walks ``step_m``
metres along the plan. It stops at the goal, when the policy finds no plan (failure), or at the step
limit (failure).

Algorithm 1 re-plans every step; a deterministic policy given the same belief returns the same plan,
so the walker re-plans only when the observation changed the belief (or when the plan is used up):
the trajectory is the same, the work is not. Because ``step_m`` is shorter than the sensor radius,
every cell the walker steps on was observed before the plan through it was made: a trajectory
never enters a hard cell, and every failure is a missing plan or the step limit.

Any relaxation policy plugs in through ``Policy.plan(believed_map, graph, position, goal) -> cells``;
a policy that needs no region graph says so (``uses_graph = False``) and the walker skips its upkeep.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Literal, Protocol

import numpy as np

from navlab.core.labels import HARD_IDS, SOFT_IDS
from navlab.core.params.surenav_benchmark import ExecutorParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.graphs.incremental import update_graph
from navlab.graphs.region_graph import RegionGraph, superpixel_graph
from navlab.maps.semantic_map import SemanticMap

Status = Literal["reached", "no_plan", "step_limit"]


class Policy(Protocol):
    """A relaxation-and-planning policy: the cell path from ``position`` to ``goal`` ((row, col) in the
    believed map's raster) on the believed map, or None when it finds none. ``graph`` is the region
    graph of the belief (None for a policy with ``uses_graph = False``). A policy may keep state
    between calls of one episode (D* Lite's search tree, RCR's relaxed set); one instance per episode.
    """

    uses_graph: bool

    def plan(self, believed_map: SemanticMap, graph: RegionGraph | None, position: tuple[int, int],
             goal: tuple[int, int]) -> np.ndarray | None: ...


@dataclass(frozen=True)
class Replan:
    step: int  # walker step at which the plan was made
    position: tuple[int, int]
    seconds: float  # wall time of the policy call
    plan_cells: int  # cells of the returned plan (0: none)


@dataclass(frozen=True)
class Execution:
    trajectory: np.ndarray  # (K, 2) int64 cells walked, start first
    status: Status
    replans: tuple[Replan, ...]
    believed_labels: np.ndarray  # the belief at the end
    graph: RegionGraph | None  # the region graph at the end (None for graph-free policies)
    relaxed_cells: np.ndarray  # sorted flat indices of the soft cells (true labels) the walker entered

    @property
    def reached(self) -> bool:
        return self.status == "reached"


def sensor_offsets(radius_m: float, resolution: float) -> np.ndarray:
    """(M, 2) cell offsets within the sensor disc (cell centres at most ``radius_m`` away)."""
    k = int(np.floor(radius_m / resolution))
    dr, dc = np.mgrid[-k:k + 1, -k:k + 1]
    inside = (dr * dr + dc * dc) * resolution**2 <= radius_m**2
    return np.stack([dr[inside], dc[inside]], axis=1)


def window_graph(semantic_map: SemanticMap, settings: GraphParams, full_cells: int) -> RegionGraph:
    """The region graph of an episode window, with the superpixel density of a whole map tile
    (``settings.target_nodes`` per ``full_cells`` cells)."""
    share = semantic_map.labels.size / max(full_cells, 1)
    scaled = replace(settings, target_nodes=max(1, round(settings.target_nodes * share)))
    return superpixel_graph(semantic_map.labels, semantic_map.frame, scaled)


def _check_plan(plan: np.ndarray, position: tuple[int, int], goal: tuple[int, int], believed: np.ndarray) -> np.ndarray:
    plan = np.asarray(plan, dtype=np.int64).reshape(-1, 2)
    if len(plan) == 0 or tuple(plan[0]) != position or tuple(plan[-1]) != goal:
        raise ValueError(f"policy returned a plan from {tuple(plan[0]) if len(plan) else None} to "
                         f"{tuple(plan[-1]) if len(plan) else None}; it must run from {position} to {goal}")
    if (np.abs(np.diff(plan, axis=0)).max(initial=0) > 1) or np.isin(believed[plan[:, 0], plan[:, 1]], HARD_IDS).any():
        raise ValueError("policy returned a plan with a jump or through a believed hard cell")
    return plan


def execute(prior: SemanticMap, truth: np.ndarray, start, goal, policy: Policy, settings: ExecutorParams,
            graph_settings: GraphParams, *, full_cells: int | None = None) -> Execution:
    """Walk from ``start`` to ``goal`` ((row, col) cells of ``prior``) believing ``prior`` while the world
    is ``truth`` (a label raster of the same shape). ``full_cells``: cells of the whole map tile the
    window was cut from, for the superpixel density (default: the window itself)."""
    if truth.shape != prior.labels.shape:
        raise ValueError(f"truth {truth.shape} and prior {prior.labels.shape} must have one shape")
    res = prior.frame.resolution
    if not 0 < settings.step_m < settings.sensor_radius_m:
        raise ValueError(f"executor step_m = {settings.step_m} must lie in (0, sensor_radius_m = "
                         f"{settings.sensor_radius_m}): the walker must see every cell before stepping on it")
    start, goal = tuple(int(v) for v in start), tuple(int(v) for v in goal)
    for name, cell in (("start", start), ("goal", goal)):
        if not prior.frame.contains(np.array(cell)) or np.isin(truth[cell], HARD_IDS):
            raise ValueError(f"{name} {cell} is outside the map or in a hard cell of the true map; pick another")
    offsets = sensor_offsets(settings.sensor_radius_m, res)
    shape = np.array(truth.shape)
    believed = prior.labels.copy()
    graph = window_graph(prior, graph_settings, full_cells or prior.labels.size) if policy.uses_graph else None
    position, trajectory, replans = start, [start], []
    plan, at = None, 0
    status: Status = "step_limit"
    for step in range(settings.max_steps):
        seen = np.array(position) + offsets
        seen = seen[((seen >= 0) & (seen < shape)).all(axis=1)]
        news = seen[believed[seen[:, 0], seen[:, 1]] != truth[seen[:, 0], seen[:, 1]]]
        if len(news):
            believed[news[:, 0], news[:, 1]] = truth[news[:, 0], news[:, 1]]
            if graph is not None:
                changed = np.zeros(truth.shape, dtype=bool)
                changed[news[:, 0], news[:, 1]] = True
                graph = update_graph(graph, believed, changed, compactness=graph_settings.compactness,
                                     tau=graph_settings.tau_m)
        if position == goal:
            status = "reached"
            break
        if plan is None or len(news) or at >= len(plan) - 1:
            belief = SemanticMap(prior.name, believed.copy(), prior.frame)
            tic = time.perf_counter()
            found = policy.plan(belief, graph, position, goal)
            seconds = time.perf_counter() - tic
            replans.append(Replan(step, position, seconds, 0 if found is None else len(found)))
            if found is None:
                status = "no_plan"
                break
            plan, at = _check_plan(found, position, goal, believed), 0
        walked = 0.0
        while at < len(plan) - 1 and walked < settings.step_m - 1e-9:
            walked += float(np.hypot(*(plan[at + 1] - plan[at]))) * res
            at += 1
            trajectory.append((int(plan[at, 0]), int(plan[at, 1])))
        position = trajectory[-1]
    if status == "step_limit" and position == goal:  # the last step arrived
        status = "reached"
    cells = np.asarray(trajectory, dtype=np.int64)
    flat = np.unique(cells[:, 0] * truth.shape[1] + cells[:, 1])
    relaxed = flat[np.isin(truth.ravel()[flat], SOFT_IDS)]
    return Execution(cells, status, tuple(replans), believed, graph, relaxed)
