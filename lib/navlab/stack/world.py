"""The stack's world (issue 64): one SuReNav test tile (real OSM), its aerial image painted from its labels
with PACER's terrain photographs, one semi-static blockage on the walkway route, and pedestrians walking
the sidewalks head-on at HJ-search's human speed; every draw seeded from ``stack.seed``.

Why these choices: the blockage is placed as SuReNav's episodes place theirs (``maps.perturb.obstruct_route``
on the walkway route, clear of both ends), so relaxing a soft region is the only way on; the aerial image is
painted at PACER's ground scale (``pacer.data.layout.street_zoom`` pixels per map cell) from a fixed
label-to-terrain table, so the operator's preference context names terrains PACER can see; the pedestrians
walk the route a person would take (soft regions allowed at a detour cost) from the goal towards the start,
so that every episode meets them on a narrow walkway, where the local planner's safety matters.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from navlab.core.labels import HARD_IDS, LABELS, label_id
from navlab.core.params import Params
from navlab.maps.dataset import load_maps
from navlab.maps.perturb import obstruct_route
from navlab.maps.semantic_map import SemanticMap
from navlab.pacer.bev import render_aerial
from navlab.pacer.context import preference_context
from navlab.pacer.preferences import order_terrains
from navlab.pacer.terrain import TerrainBank
from navlab.search.grid_astar import plan as grid_plan
from navlab.surenav.context.personas import CONTEXT_PERSONAS
from navlab.surenav.semi_static import window_graph

WALKWAYS = ("sidewalk", "crosswalk")  # the route before the blockage: what a map router would give
PERSON_SOFT_COST = 3.0  # a pedestrian's cost per metre on soft ground (sidewalk 1): they detour only if blocked
DRAWS = 400  # start-goal draws per episode before the tile is declared unusable
MIN_BOX_CELLS = 48  # PACER's 64-px windows need a map larger than one window (x street_zoom)
BLOCKAGE_CLEARANCE_M = 6.0  # the blockage stays this far from the start and the goal (SuReNav context episodes: 8 m)


@dataclass(frozen=True)
class Walker:
    """A pedestrian walking a polyline at constant speed, not reacting (HJ-search's non-interactive human)."""

    path: np.ndarray  # (K, 2) world metres
    offset_m: float  # arc length along ``path`` at t = 0
    speed: float  # m/s

    def _arc(self) -> np.ndarray:
        return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(self.path, axis=0), axis=1))])

    def position(self, t: float) -> np.ndarray:
        """(2,) where it is at time ``t`` (s); it stands at the end of its path once there."""
        arc = self._arc()
        s = min(self.offset_m + self.speed * t, arc[-1])
        return np.array([np.interp(s, arc, self.path[:, 0]), np.interp(s, arc, self.path[:, 1])])

    def velocity(self, t: float, dt: float = 0.1) -> np.ndarray:
        return (self.position(t + dt) - self.position(t)) / dt


@dataclass(frozen=True)
class StackEpisode:
    name: str
    prior: SemanticMap  # the episode's box of the tile as mapped (OSM labels); world metres of the tile
    truth: np.ndarray  # (H, W) labels as they are: the blockage in
    superpixels: np.ndarray  # (H, W) the box's label-consistent SLIC partition (relaxation IoU's regions)
    start: tuple[int, int]  # (row, col) cells
    goal: tuple[int, int]
    terrain: np.ndarray  # (H, W) int64 terrain id painted on each cell of the truth
    aerial: np.ndarray  # (3, zH, zW) float32 in [0, 1]: the truth painted at PACER's ground scale
    preference: str  # the operator's order: realistic or inverted
    ordering: np.ndarray  # the operator's order of the terrains in view, most preferred first
    context: np.ndarray  # (3n, 2h, w) PACER's preference context drawn from ``ordering``
    persona: int  # the context demonstrator's persona (SuReNav's Expert) for this episode
    walkers: tuple[Walker, ...]


def label_terrains(params: Params, bank: TerrainBank) -> np.ndarray:
    """(NUM_LABELS,) terrain id painted on each SuReNav label (``stack.terrain_of_label``)."""
    table = params.stack.terrain_of_label
    names = [label.name for label in LABELS]
    missing = [name for name in names if name not in table]
    if missing:
        raise ValueError(f"stack.terrain_of_label names no terrain for {', '.join(missing)}: give every label one")
    return np.array([bank.id_of(table[name]) for name in names], dtype=np.int64)


def _walkway_route(labels: np.ndarray, start, goal, resolution: float) -> np.ndarray | None:
    cost = np.where(np.isin(labels, [label_id(n) for n in WALKWAYS]), 1.0, np.inf)
    return grid_plan(cost, start, goal, resolution=resolution).cells


def _person_route(labels: np.ndarray, start, goal, resolution: float) -> np.ndarray | None:
    cost = np.where(np.isin(labels, HARD_IDS), np.inf,
                    np.where(np.isin(labels, [label_id(n) for n in WALKWAYS]), 1.0, PERSON_SOFT_COST))
    return grid_plan(cost, start, goal, resolution=resolution).cells


def _draw_pair(tile: SemanticMap, params: Params, rng: np.random.Generator):
    """(start, goal, walkway route) on the tile's sidewalks, the route at most 1.6x the straight line."""
    res = tile.frame.resolution
    sidewalk = np.argwhere(tile.labels == label_id("sidewalk"))
    lo, hi = params.stack.route_m
    for _ in range(DRAWS):
        start = sidewalk[rng.integers(len(sidewalk))]
        distance = np.linalg.norm(sidewalk - start, axis=1) * res
        candidates = np.flatnonzero((distance >= lo) & (distance <= hi))
        if not len(candidates):
            continue
        goal = sidewalk[candidates[rng.integers(len(candidates))]]
        route = _walkway_route(tile.labels, tuple(start), tuple(goal), res)
        if route is not None and len(route) * res <= 1.6 * np.linalg.norm(goal - start) * res + 2.0:
            return tuple(int(v) for v in start), tuple(int(v) for v in goal), route
    raise ValueError(f"{tile.name}: no sidewalk start-goal pair {lo}-{hi} m apart joined by a walkway in "
                     f"{DRAWS} draws; widen stack.route_m")


def _box(route: np.ndarray, shape, margin: int, multiple: int) -> tuple[slice, slice]:
    """The route's box grown by ``margin`` cells (each side at least ``MIN_BOX_CELLS``), clipped to the tile,
    each side a multiple of ``multiple``."""
    grow = np.maximum(MIN_BOX_CELLS - (route.max(axis=0) - route.min(axis=0) + 1 + 2 * margin), 0) // 2 + 1
    lo = np.maximum(route.min(axis=0) - margin - grow, 0)
    hi = np.minimum(route.max(axis=0) + margin + grow + 1, shape)
    size = (hi - lo) // multiple * multiple
    sides = []
    for axis in range(2):  # the rounding drops cells at the end the route leaves room at (the margin > multiple)
        fits = [a for a in (lo[axis], hi[axis] - size[axis])
                if a <= route[:, axis].min() and route[:, axis].max() < a + size[axis]]
        first = int(fits[0] if fits else lo[axis])
        sides.append(slice(first, first + int(size[axis])))
    return sides[0], sides[1]


def stack_episode(index: int, tiles: list[SemanticMap], params: Params, bank: TerrainBank) -> StackEpisode:
    """Episode ``index``: tile ``index mod 5``, the operator's order ``stack.preferences[index mod k]``."""
    S, D = params.stack, params.pacer.data
    rng = np.random.default_rng([S.seed, index])
    tile = tiles[index % len(tiles)]
    res = tile.frame.resolution
    for _ in range(DRAWS // 4):
        route = _draw_pair(tile, params, rng)[2]
        rows, cols = _box(route, tile.labels.shape, round(S.box_margin_m / res), 8)
        inside = [box.start <= route[:, k].min() and route[:, k].max() < box.stop for k, box in enumerate((rows, cols))]
        if not all(inside):  # a tile smaller than the box
            continue
        prior = tile.crop(rows, cols)
        local = route - [rows.start, cols.start]
        graph = window_graph(prior, params.surenav.graph, tile.labels.size)
        blockage = obstruct_route(prior.labels, graph.superpixels, local, 1, rng, obstacle_probability=1.0,
                                  clearance_cells=round(BLOCKAGE_CLEARANCE_M / res))
        s, g = tuple(int(v) for v in local[0]), tuple(int(v) for v in local[-1])
        walk = _person_route(blockage.labels, g, s, res)
        if blockage.changed[local[:, 0], local[:, 1]].any() and walk is not None:
            break
    else:
        raise ValueError(f"{tile.name}: no blockage on the walkway route that leaves a way round; "
                         "widen stack.route_m or stack.box_margin_m")
    terrains = label_terrains(params, bank)[blockage.labels]
    zoom = D.layout.street_zoom
    painted = render_aerial(np.repeat(np.repeat(terrains, zoom, 0), zoom, 1), bank, rng, D)
    preference = S.preferences[index % len(S.preferences)]
    ordering = order_terrains(np.unique(terrains), preference, bank, rng)
    context, _ = preference_context(bank, ordering, rng, D)
    path = prior.frame.cell_to_world(walk)
    length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
    walkers = tuple(Walker(path, float(offset), params.hj.grids.human.speed)
                    for offset in np.sort(rng.uniform(0.1, 0.6, S.pedestrians)) * length)
    return StackEpisode(f"{tile.name}/{index}", prior, blockage.labels, graph.superpixels, s, g, terrains,
                        np.ascontiguousarray(painted.transpose(2, 0, 1)), preference, ordering, context,
                        index % len(CONTEXT_PERSONAS), walkers)


def stack_episodes(params: Params, data_dir: str, bank: TerrainBank, count: int | None = None) -> list[StackEpisode]:
    """The ablation's episodes, cycling over the five SuReNav test tiles."""
    tiles = load_maps(data_dir, "test")
    return [stack_episode(i, tiles, params, bank) for i in range(params.stack.episodes if count is None else count)]
