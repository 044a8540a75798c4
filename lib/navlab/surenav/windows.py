"""The planning window of a benchmark episode, and its widening when no route lies inside it (issue 25 item 5).

Every method of the benchmark plans and walks inside a window of the map: the start-goal box grown by
``surenav.benchmark.executor.window_margin_m`` (the box the synthetic expert plans in), so that the
region graph, the estimator's attention and the baselines' searches stay local. A window can hold no
route while the map does: a new obstacle closes the only passage inside it and the way round leaves
it. Fig. 4's milan SR of 0.93 was mostly that (issue 25: with a 400 m margin, 8 of seed 0's 9 failures
reach the goal), a limit of the window, not of the method.

So when a method finds no plan, the walker, where it stands and with everything it has observed,
doubles the margin and plans again with a fresh policy of the same method on the wider window, up to
the whole map. The windows are nested (each holds the one before, so the walker is always inside),
and the rule is the same for every method: a method's own query window (SuReNav's node window, the
Expert's search box) is scaled by the same factor (``PlanningWindow.scale``). A failure is then a
failure on the whole map: no route the method admits exists at all, or the step limit.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace

import numpy as np

from navlab.core.labels import HARD_IDS
from navlab.core.params.surenav_benchmark import ExecutorParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.metrics.navigation import shortest_feasible_length
from navlab.surenav.episodes import Environment, window
from navlab.surenav.semi_static import Policy, Replan, Status, execute


@dataclass(frozen=True)
class PlanningWindow:
    box: tuple[slice, slice]  # full-map cells the episode plays in
    scale: int  # the margin as a multiple of the configured one (1, 2, 4, ...)

    @property
    def offset(self) -> np.ndarray:
        """(row, col) of the window's first cell in the full map."""
        return np.array([self.box[0].start, self.box[1].start], dtype=np.int64)


# a fresh policy of one method for one window (its own query window scaled by ``PlanningWindow.scale``)
WindowedPolicy = Callable[[PlanningWindow], Policy]


def prior_hard(env: Environment, w: PlanningWindow) -> np.ndarray:
    """The prior map's hard cells in the window: what a policy that tells new obstacles from old ones
    (the context rules) must take as known, also in a window opened after it saw a new obstacle."""
    return np.isin(env.prior.labels[w.box], HARD_IDS)


def windows(shape, start, goal, margin_cells: int) -> Iterator[PlanningWindow]:
    """The nested windows of an episode: the margin, then twice it, four times, ... until a window covers
    the whole map (the last one yielded)."""
    if margin_cells < 1:
        raise ValueError(f"window margin of {margin_cells} cells: must be at least one cell "
                         "(surenav.benchmark.executor.window_margin_m)")
    scale = 1
    while True:
        box = window(shape, np.asarray(start), np.asarray(goal), margin_cells * scale)
        yield PlanningWindow(box, scale)
        if (box[0].start, box[1].start, box[0].stop, box[1].stop) == (0, 0, *shape):
            return
        scale *= 2


def shortest_in_windows(truth: np.ndarray, start, goal, margin_cells: int, resolution: float) -> float:
    """The shortest feasible length on the true map in the first of ``windows`` that has a route (inf if
    none has): the same for every method, and the window's own when no widening is needed."""
    for w in windows(truth.shape, start, goal, margin_cells):
        found = shortest_feasible_length(truth[w.box], np.asarray(start) - w.offset, np.asarray(goal) - w.offset,
                                         resolution)
        if np.isfinite(found):
            return found
    return float("inf")


@dataclass(frozen=True)
class Walk:
    trajectory: np.ndarray  # (K, 2) full-map cells walked, start first
    status: Status
    replans: tuple[Replan, ...]  # steps and positions in the whole episode / full map
    window: PlanningWindow  # the last (widest) window walked

    @property
    def reached(self) -> bool:
        return self.status == "reached"


def walk(env: Environment, make: WindowedPolicy, executor: ExecutorParams, graph: GraphParams) -> Walk:
    """Algorithm 1's walk of one episode (``surenav.semi_static.execute``) in its window, widened (see the
    module) each time the method finds no plan; the step limit counts over the whole walk."""
    res = env.prior.frame.resolution
    believed = env.prior.labels.copy()
    position = np.asarray(env.start, dtype=np.int64)
    cells, replans, walked = [position[None]], [], 0
    for w in windows(env.truth.shape, env.start, env.goal, int(np.ceil(executor.window_margin_m / res))):
        off = w.offset
        ex = execute(env.prior.crop(*w.box, labels=believed), env.truth[w.box], position - off,
                     np.asarray(env.goal) - off, make(w), replace(executor, max_steps=executor.max_steps - walked),
                     graph, full_cells=env.prior.labels.size)
        cells.append(ex.trajectory[1:] + off)
        replans += [replace(r, step=r.step + walked, position=tuple(int(v) for v in np.add(r.position, off)))
                    for r in ex.replans]
        believed[w.box] = ex.believed_labels
        position = ex.trajectory[-1] + off
        if ex.status != "no_plan":
            break
        walked += ex.replans[-1].step  # the steps walked before the plan that failed
    return Walk(np.concatenate(cells), ex.status, tuple(replans), w)
