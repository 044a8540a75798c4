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
from functools import cached_property

import numpy as np

from navlab.core.labels import FREE_IDS, HARD_IDS, LABELS, label_id
from navlab.core.params import Params
from navlab.maps.dataset import load_maps
from navlab.maps.perturb import NO_REGION, OBSTACLE, adjacent_superpixels, obstruct_route
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
STANDING_CLEARANCE_M = 2.0  # a standing pedestrian this far from them: the robot can leave its start and stop at its goal
OPERATOR_PREFERENCES = ("realistic", "inverted")  # what a person may choose (stack.preferences draws among them)
MAX_PEDESTRIANS = 8  # walking ones a person may ask for: the window's pruner checks each, every re-plan
MAX_STANDING = 4
MAX_SPEED = 2.0  # m/s, a brisk walk: faster than the human BRT's 0.8 m/s, which its safety margin does not cover


@dataclass(frozen=True)
class Walker:
    """A pedestrian walking a polyline at constant speed, not reacting (HJ-search's non-interactive human)."""

    path: np.ndarray  # (K, 2) world metres
    offset_m: float  # arc length along ``path`` at t = 0
    speed: float  # m/s

    @cached_property
    def arc(self) -> np.ndarray:
        """(K,) arc length at each vertex of ``path``: once per walker, the drive asks ``position`` every tick."""
        return arc_length(self.path)

    def position(self, t: float) -> np.ndarray:
        """(2,) where it is at time ``t`` (s); it stands at the end of its path once there."""
        arc = self.arc
        s = min(self.offset_m + self.speed * t, arc[-1])
        return np.array([np.interp(s, arc, self.path[:, 0]), np.interp(s, arc, self.path[:, 1])])

    def track(self, times: np.ndarray) -> np.ndarray:
        """(T, 2) where it is at each of ``times`` (s): ``position`` at many times at once (the figures)."""
        s = np.minimum(self.offset_m + self.speed * np.asarray(times, dtype=float), self.arc[-1])
        return np.stack([np.interp(s, self.arc, self.path[:, 0]), np.interp(s, self.arc, self.path[:, 1])], axis=-1)

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
    preference: str  # the operator's order: realistic or inverted (custom: a person's EpisodeChoices.order)
    ordering: np.ndarray  # the operator's order of the terrains in view, most preferred first
    context: np.ndarray  # (3n, 2h, w) PACER's preference context drawn from ``ordering``
    persona: int  # the context demonstrator's persona (SuReNav's Expert) for this episode
    walkers: tuple[Walker, ...]
    walkway: np.ndarray | None = None  # (K, 2) cells: the walkway route (start to goal) the blockage was put on


@dataclass(frozen=True)
class EpisodeChoices:
    """What a person sets in place of an episode's draw (the stack playground); a field left at its default
    keeps the draw or the parameter, so ``EpisodeChoices()`` is the ablation's episode. Out-of-range values
    are refused here, in one line naming the field and its range; those that depend on the episode (how near
    the ends a blockage may go) by ``stack_episode``."""

    preference: str | None = None  # realistic or inverted; None: stack.preferences[index mod k]
    order: tuple[str, ...] | None = None  # terrain names, most preferred first, in place of ``preference``
    blockage: bool = True  # False: the walkway stays open (no semi-static change)
    blockage_at: float | None = None  # fraction of the walkway route's length from the start; None: drawn
    pedestrians: int | None = None  # walking ones; None: stack.pedestrians
    speed: float | None = None  # their speed (m/s); None: hj.grids.human.speed (the speed the BRTs assume)
    standing: tuple[float, ...] = ()  # fractions of the pedestrians' path, from the start, where one stands still

    def __post_init__(self):
        if self.preference is not None and self.preference not in OPERATOR_PREFERENCES:
            raise ValueError(f"preference = {self.preference!r}: choose {' or '.join(OPERATOR_PREFERENCES)}")
        if self.order is not None and (self.preference is not None or len(set(self.order)) != len(self.order)
                                       or not self.order):
            raise ValueError(f"order = {self.order!r}: name distinct terrains, most preferred first, and leave "
                             "preference unset")
        if not (self.blockage_at is None or (self.blockage and 0.0 < self.blockage_at < 1.0)):
            raise ValueError(f"blockage_at = {self.blockage_at!r}: choose a fraction between 0 and 1 of the "
                             "walkway route (with a blockage), or None for the drawn place")
        if self.pedestrians is not None and not (isinstance(self.pedestrians, int | np.integer)
                                                 and 0 <= self.pedestrians <= MAX_PEDESTRIANS):
            raise ValueError(f"pedestrians = {self.pedestrians!r}: choose 0 to {MAX_PEDESTRIANS}")
        if self.speed is not None and not 0.0 <= self.speed <= MAX_SPEED:  # NaN fails too
            raise ValueError(f"speed = {self.speed!r}: choose 0 to {MAX_SPEED:g} m/s")
        if len(self.standing) > MAX_STANDING or not all(0.0 <= f <= 1.0 for f in self.standing):
            raise ValueError(f"standing = {self.standing!r}: at most {MAX_STANDING} fractions between 0 and 1 "
                             "of the pedestrians' path")


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


def _draw(tile: SemanticMap, params: Params, rng: np.random.Generator):
    """(box of the tile, walkway route in it, its region graph, the seeded blockage, the pedestrians' path in
    cells): start-goal pairs drawn until the blockage cuts the route and leaves a way round."""
    S, res = params.stack, tile.frame.resolution
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
        walk = _person_route(blockage.labels, *_ends(local)[::-1], res)
        if blockage.changed[local[:, 0], local[:, 1]].any() and walk is not None:
            return prior, local, graph, blockage.labels, walk
    raise ValueError(f"{tile.name}: no blockage on the walkway route that leaves a way round; "
                     "widen stack.route_m or stack.box_margin_m")


def arc_length(points: np.ndarray) -> np.ndarray:
    """(K,) arc length along a polyline (cells or metres, as its points), from its first point."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])


def _ends(route: np.ndarray) -> tuple[tuple[int, int], tuple[int, int]]:
    """(start, goal) cells of a route."""
    return tuple(int(v) for v in route[0]), tuple(int(v) for v in route[-1])


def place_blockage(labels: np.ndarray, superpixels: np.ndarray, route: np.ndarray, fraction: float,
                   clearance_cells: int) -> np.ndarray:
    """``labels`` with the blockage at ``fraction`` of the route's length, by the seeded draw's rules
    (``obstruct_route``) at a chosen place instead of a drawn one: the superpixel the route crosses nearest
    there, outside those within ``clearance_cells`` of its ends, on free ground where the route has any, and
    its neighbours of the same label (not the protected ones) become an obstacle."""
    on_route = superpixels[route[:, 0], route[:, 1]]
    near_end = (np.abs(route[:, None, :] - route[[0, -1]][None]).max(axis=2) <= clearance_cells).any(axis=1)
    protected = np.unique(on_route[near_end])
    usable = (on_route != NO_REGION) & ~np.isin(on_route, protected)
    free = usable & np.isin(labels[route[:, 0], route[:, 1]], FREE_IDS)
    usable = free if free.any() else usable
    if not usable.any():
        raise ValueError("blockage_at: every region the walkway route crosses lies within "
                         f"{BLOCKAGE_CLEARANCE_M:g} m of the start or the goal; choose no blockage")
    arc = arc_length(route)
    k = np.flatnonzero(usable)[np.argmin(np.abs(arc[usable] - fraction * arc[-1]))]
    seed, label = on_route[k], labels[tuple(route[k])]
    same = adjacent_superpixels(superpixels, np.array([seed]))
    region = (superpixels == seed) | (np.isin(superpixels, same[~np.isin(same, protected)]) & (labels == label))
    return np.where(region, OBSTACLE, labels).astype(labels.dtype)


def _chosen_blockage(prior: SemanticMap, superpixels: np.ndarray, route: np.ndarray, choices: EpisodeChoices):
    """(labels as they are, the pedestrians' path in cells) for a chosen blockage, or None: the seeded one."""
    if choices.blockage and choices.blockage_at is None:
        return None
    res = prior.frame.resolution
    if not choices.blockage:
        return prior.labels, _person_route(prior.labels, *_ends(route)[::-1], res)
    length = arc_length(route)[-1] * res
    lo = BLOCKAGE_CLEARANCE_M / length
    if not lo <= choices.blockage_at <= 1 - lo:
        raise ValueError(f"blockage_at = {choices.blockage_at:g}: choose {lo:.2f} to {1 - lo:.2f} of this "
                         f"{length:.0f} m walkway route (the blockage stays {BLOCKAGE_CLEARANCE_M:g} m from the "
                         "start and the goal)")
    labels = place_blockage(prior.labels, superpixels, route, choices.blockage_at, round(BLOCKAGE_CLEARANCE_M / res))
    walk = _person_route(labels, *_ends(route)[::-1], res)
    if walk is None:
        raise ValueError(f"blockage_at = {choices.blockage_at:g}: a blockage there closes every way from the "
                         "start to the goal (buildings or water all round it); choose another place")
    return labels, walk


def _ordering(terrains: np.ndarray, preference: str, order: tuple[str, ...] | None, bank: TerrainBank,
              rng: np.random.Generator) -> np.ndarray:
    """The terrains in view most preferred first: by ``preference``, or as ``order`` names them (the terrains
    in view it leaves out after those, in the realistic order)."""
    if order is None:
        return order_terrains(np.unique(terrains), preference, bank, rng)
    unknown = [name for name in order if name not in bank.names]
    if unknown:
        raise ValueError(f"order names {', '.join(map(repr, unknown))}: not a terrain; choose among "
                         f"{', '.join(bank.names)}")
    named = np.array([bank.id_of(name) for name in order], dtype=np.int64)
    rest = order_terrains(np.setdiff1d(terrains, named), "realistic", bank, rng)  # realistic: no draw
    return np.concatenate([named[np.isin(named, terrains)], rest])


def _standing(path: np.ndarray, fraction: float) -> Walker:
    """A pedestrian standing still ``fraction`` of the way along the pedestrians' path, counted from the
    robot's start (the path runs from the goal to the start)."""
    arc = arc_length(path)
    length = arc[-1]
    lo = STANDING_CLEARANCE_M / length
    if not lo <= fraction <= 1 - lo:
        raise ValueError(f"standing = {fraction:g}: choose {lo:.2f} to {1 - lo:.2f} of this {length:.0f} m "
                         f"pedestrian path (a standing pedestrian keeps {STANDING_CLEARANCE_M:g} m from the start "
                         "and the goal)")
    s = (1.0 - fraction) * length
    spot = np.array([np.interp(s, arc, path[:, 0]), np.interp(s, arc, path[:, 1])])
    return Walker(np.array([spot, spot]), 0.0, 0.0)


def stack_episode(index: int, tiles: list[SemanticMap], params: Params, bank: TerrainBank,
                  choices: EpisodeChoices | None = None) -> StackEpisode:
    """Episode ``index``: tile ``index mod 5``, the operator's order ``stack.preferences[index mod k]``; what
    ``choices`` sets replaces the draw (the start, the goal and the box stay the index's). Without choices, the
    ablation's episode: the same draws in the same order."""
    choices = EpisodeChoices() if choices is None else choices
    S, D = params.stack, params.pacer.data
    rng = np.random.default_rng([S.seed, index])
    tile = tiles[index % len(tiles)]
    prior, local, graph, labels, walk = _draw(tile, params, rng)
    labels, walk = _chosen_blockage(prior, graph.superpixels, local, choices) or (labels, walk)
    terrains = label_terrains(params, bank)[labels]
    zoom = D.layout.street_zoom
    painted = render_aerial(np.repeat(np.repeat(terrains, zoom, 0), zoom, 1), bank, rng, D)
    preference = choices.preference or ("custom" if choices.order else S.preferences[index % len(S.preferences)])
    ordering = _ordering(terrains, preference, choices.order, bank, rng)
    context, _ = preference_context(bank, ordering, rng, D)
    path = prior.frame.cell_to_world(walk)
    length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
    count = S.pedestrians if choices.pedestrians is None else choices.pedestrians
    speed = params.hj.grids.human.speed if choices.speed is None else choices.speed
    walkers = tuple(Walker(path, float(offset), speed) for offset in np.sort(rng.uniform(0.1, 0.6, count)) * length)
    s, g = _ends(local)
    return StackEpisode(f"{tile.name}/{index}", prior, labels, graph.superpixels, s, g, terrains,
                        np.ascontiguousarray(painted.transpose(2, 0, 1)), preference, ordering, context,
                        index % len(CONTEXT_PERSONAS), walkers + tuple(_standing(path, f) for f in choices.standing),
                        local)


def stack_episodes(params: Params, data_dir: str, bank: TerrainBank, count: int | None = None) -> list[StackEpisode]:
    """The ablation's episodes, cycling over the five SuReNav test tiles."""
    tiles = load_maps(data_dir, "test")
    return [stack_episode(i, tiles, params, bank) for i in range(params.stack.episodes if count is None else count)]
