"""The synthetic careful pedestrian: one demonstration from a start to a goal on a semantic map.

The walker first plans as if it were willing to jaywalk (roads at the persona's price). If that route
touches no road it is also the best careful route and is taken. Otherwise it plans again with roads
forbidden (crosswalks only) and jaywalks only when the crosswalk route is more than ``jaywalk_ratio``
times longer — so whether a road gets crossed depends on where the crosswalks are, not on a fixed
road cost. Grass, parking, living streets and rough ground cost what context_cost.py says. Planning
uses grid A* (navlab.search.grid_astar) inside a window around start and goal.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from navlab.core.grid import RasterFrame
from navlab.core.labels import FREE_IDS, SOFT_IDS
from navlab.search.grid_astar import plan
from navlab.surenav.experts.context_cost import ROAD, expert_cost
from navlab.surenav.experts.hand_noise import dense_cells, hand_drawn
from navlab.surenav.experts.personas import Persona


@dataclass(frozen=True)
class ExpertPath:
    path: np.ndarray  # (K, 2) world metres, hand-drawn
    cells: np.ndarray  # (M, 2) the planned cell path
    jaywalked: bool  # the hidden choice: crossed a road away from a crosswalk


class CostCache:
    """The persona's two cost rasters (jaywalking or not) of one map, computed once per map and persona."""

    def __init__(self, labels: np.ndarray, resolution: float):
        self.labels, self.resolution, self._cache = labels, resolution, {}

    def get(self, persona: Persona, jaywalk: bool) -> np.ndarray:
        key = (persona.name, jaywalk)
        if key not in self._cache:
            if jaywalk:
                self._cache[key] = expert_cost(self.labels, self.resolution, persona, jaywalk=True)
            else:  # the same raster with roads closed (saves the grass distance transform)
                self._cache[key] = np.where(self.labels == ROAD, np.inf, self.get(persona, True))
        return self._cache[key]


def _window(shape, start, goal, margin: int) -> tuple[slice, slice]:
    lo = np.maximum(np.minimum(start, goal) - margin, 0)
    hi = np.minimum(np.maximum(start, goal) + margin + 1, shape)
    return slice(lo[0], hi[0]), slice(lo[1], hi[1])


def _plan_in(cost: np.ndarray, window, start, goal, resolution: float) -> np.ndarray | None:
    offset = np.array([window[0].start, window[1].start])
    found = plan(cost[window], tuple(np.asarray(start) - offset), tuple(np.asarray(goal) - offset),
                 resolution=resolution)
    return None if found.cells is None else found.cells + offset


def _length(cells: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(cells, axis=0), axis=1).sum())


def plan_route(costs: CostCache, persona: Persona, start, goal, margin_cells: int) -> tuple[np.ndarray, bool] | None:
    """The walker's cell route and whether it jaywalks; None if the goal cannot be reached at all."""
    window = _window(costs.labels.shape, np.asarray(start), np.asarray(goal), margin_cells)
    res = costs.resolution
    jay = costs.get(persona, True)
    if not (np.isfinite(jay[tuple(start)]) and np.isfinite(jay[tuple(goal)])):
        return None
    bold = _plan_in(jay, window, start, goal, res)
    if bold is None:
        return None
    if not (costs.labels[bold[:, 0], bold[:, 1]] == ROAD).any():
        return bold, False
    careful_cost = costs.get(persona, False)
    careful = None
    if np.isfinite(careful_cost[tuple(start)]) and np.isfinite(careful_cost[tuple(goal)]):
        careful = _plan_in(careful_cost, window, start, goal, res)
    if careful is None or _length(careful) > persona.jaywalk_ratio * _length(bold):
        return bold, True
    return careful, False


def admissible_cells(labels: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Free cells plus the soft cells of every same-label patch the route walks through."""
    ok = np.isin(labels, FREE_IDS)
    soft = np.isin(labels, SOFT_IDS)
    on_route = np.zeros(labels.shape, dtype=bool)
    on_route[cells[:, 0], cells[:, 1]] = True
    for lab in np.unique(labels[on_route & soft]):
        patches, _ = ndimage.label(labels == lab)
        ok |= np.isin(patches, np.unique(patches[on_route & (labels == lab)]))
    return ok


def _through_corners(cells: np.ndarray, *costs: np.ndarray) -> np.ndarray | None:
    """The route with every diagonal step split into two straight ones through the cheaper side cell.

    Sides are compared by ``costs[0]``, ties broken by the next rasters. A person does not squeeze
    through the point where two buildings touch corners: a route that only gets through such a
    pinch is dropped (None).
    """
    diagonal = np.all(cells[1:] != cells[:-1], axis=1)
    if not diagonal.any():
        return cells
    a = np.stack([cells[1:, 0], cells[:-1, 1]], axis=1)[diagonal]
    b = np.stack([cells[:-1, 0], cells[1:, 1]], axis=1)[diagonal]
    ca = np.stack([c[a[:, 0], a[:, 1]] for c in costs], axis=1)
    cb = np.stack([c[b[:, 0], b[:, 1]] for c in costs], axis=1)
    if not np.isfinite(np.minimum(ca, cb)).any(axis=1).all():
        return None
    first_diff = np.argmax(ca != cb, axis=1)
    pick_a = ca[np.arange(len(a)), first_diff] <= cb[np.arange(len(a)), first_diff]
    side = np.where(pick_a[:, None], a, b)
    return np.insert(cells, np.nonzero(diagonal)[0] + 1, side, axis=0)


def demonstrate(costs: CostCache, frame: RasterFrame, start, goal, persona: Persona, rng: np.random.Generator,
                margin_cells: int) -> ExpertPath | None:
    """One hand-drawn demonstration from cell ``start`` to cell ``goal``; None if the goal is unreachable."""
    route = plan_route(costs, persona, start, goal, margin_cells)
    if route is None:
        return None
    cells, jaywalked = route
    cells = _through_corners(cells, costs.get(persona, False), costs.get(persona, True))
    if cells is None:
        return None
    admissible = admissible_cells(costs.labels, cells)
    path = hand_drawn(cells, frame, admissible, rng, persona.noise_amplitude_m, persona.noise_wavelength_m)
    return ExpertPath(path=path, cells=cells, jaywalked=jaywalked)


def relaxed_cells(labels: np.ndarray, path_xy: np.ndarray, frame: RasterFrame) -> np.ndarray:
    """Sorted flat indices of the soft cells a path enters: the demonstration's relaxed-region mask."""
    rc = dense_cells(path_xy, frame)
    flat = np.unique(rc[:, 0] * labels.shape[1] + rc[:, 1])
    return flat[np.isin(labels.ravel()[flat], SOFT_IDS)]
