"""Static and semi-static navigation environments with one expert demonstration each (SuReNav Sec. VI-A).

Per map: start-goal pairs on sidewalks, 30-200 m apart; the static demonstration on the map as it
is; then the semi-static variant: a superpixel on the demonstrated path is perturbed (maps.perturb:
a new obstacle or an obfuscated prior), and the expert redraws from a point shortly before the
change, reusing the prefix of its first drawing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from navlab.core.io import DataError
from navlab.core.labels import FREE_IDS
from navlab.core.params.demos import DemosParams
from navlab.graphs.incremental import resegment
from navlab.maps.perturb import obstruct_route
from navlab.maps.queries import sample_pairs
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.experts.hand_noise import dense_cells
from navlab.surenav.experts.pedestrian import CostCache, demonstrate, relaxed_cells
from navlab.surenav.experts.personas import PERSONAS

PERTURB_TRIES = 4  # seeds tried before a pair gets no semi-static variant


@dataclass(frozen=True)
class Demonstration:
    kind: str  # "static" or "semi_static"
    path: np.ndarray  # (K, 2) world metres
    start: np.ndarray  # (2,) world metres
    goal: np.ndarray  # (2,) world metres
    persona: int  # index into personas.PERSONAS
    jaywalked: bool
    relaxed_cells: np.ndarray  # sorted flat indices of the soft cells the path enters
    relaxed_superpixels: np.ndarray  # sorted superpixel ids containing them (semi-static: of the updated raster)
    delta_cells: np.ndarray  # semi-static: flat indices of the perturbed cells (empty for static)
    delta_labels: np.ndarray  # semi-static: their new labels
    prefix_len: int  # semi-static: points of ``path`` reused from the static drawing (0 for static)

    def labels_on(self, labels: np.ndarray) -> np.ndarray:
        """The label raster this demonstration was drawn on (the perturbed one for semi-static)."""
        out = labels.copy()
        out.ravel()[self.delta_cells] = self.delta_labels
        return out


def _record(kind, path, scene, ends, persona, jaywalked, delta=None, prefix_len=0):
    """One demonstration: ``scene`` = (labels, superpixels, frame) the path was drawn on, ``ends`` = its
    (start, goal) cells; ``delta`` the semi-static change (cells, new labels) where there is one."""
    labels, superpixels, frame = scene
    start, goal = ends
    relaxed = relaxed_cells(labels, path, frame)
    cells, new = delta if delta is not None else (np.zeros(0, np.int64), np.zeros(0, np.uint8))
    return Demonstration(kind=kind, path=path.astype(np.float32), start=frame.cell_to_world(start),
                         goal=frame.cell_to_world(goal), persona=persona, jaywalked=jaywalked,
                         relaxed_cells=relaxed.astype(np.int64),
                         relaxed_superpixels=np.unique(superpixels.ravel()[relaxed]).astype(np.int64),
                         delta_cells=cells, delta_labels=new, prefix_len=prefix_len)


def _semi_static(semantic_map, superpixels, static, start, goal, persona, rng, settings: DemosParams,
                 margin: int, compactness: float):
    labels, frame = semantic_map.labels, semantic_map.frame
    res = frame.resolution
    route = dense_cells(static.path, frame)
    route = route[np.r_[True, np.any(route[1:] != route[:-1], axis=1)]]
    for _ in range(PERTURB_TRIES):
        change = obstruct_route(labels, superpixels, route, 1, rng, obstacle_probability=settings.obstacle_probability,
                                clearance_cells=int(np.ceil(settings.endpoint_clearance_m / res)))
        if not change.changed.any():
            return None
        at = frame.world_to_cell(static.path)
        first = int(np.argmax(change.changed[at[:, 0], at[:, 1]]))
        back = int(rng.uniform(3.0, 8.0) / (res / 2))  # redraw from a few metres before the change
        cut = max(first - back, 1)
        restart = at[cut - 1]
        redraw = demonstrate(CostCache(change.labels, res), frame, restart, goal, PERSONAS[persona], rng, margin)
        if redraw is None:
            continue
        path = np.concatenate([static.path[:cut], redraw.path])
        updated = resegment(superpixels, change.labels, change.changed, compactness)
        return _record("semi_static", path, (change.labels, updated, frame), (start, goal), persona,
                       redraw.jaywalked, delta=change.delta(), prefix_len=cut)
    return None


def map_environments(semantic_map: SemanticMap, superpixels: np.ndarray, n_pairs: int, settings: DemosParams,
                     rng: np.random.Generator, compactness: float) -> tuple[list[Demonstration], list[Demonstration]]:
    """(static, semi_static) demonstrations of ``n_pairs`` start-goal pairs on one map (same order).

    A semi-static demonstration's ``relaxed_superpixels`` are ids of the incrementally updated raster
    (graphs.incremental.resegment with ``compactness``), the graph a planner sees after the change.
    A map that cannot give ``n_pairs`` usable pairs is a DataError (a one-line stop in the data build);
    any other exception is a bug and keeps its traceback.
    """
    labels, frame = semantic_map.labels, semantic_map.frame
    res = frame.resolution
    margin = int(np.ceil(settings.window_margin_m / res))
    costs = CostCache(labels, res)
    try:
        candidates = sample_pairs(semantic_map, FREE_IDS, 4 * n_pairs, settings.min_distance_m,
                                  settings.max_distance_m, rng)
    except ValueError as err:  # the map cannot hold the asked pairs: a data problem, one line (CLI exit 2)
        raise DataError(f"{err} (data.demos in params.yaml)") from None
    static, semi = [], []
    for start, goal in candidates:
        persona = int(rng.integers(len(PERSONAS)))
        demo = demonstrate(costs, frame, start, goal, PERSONAS[persona], rng, margin)
        if demo is None:
            continue
        variant = _semi_static(semantic_map, superpixels, demo, start, goal, persona, rng, settings, margin,
                               compactness)
        if variant is None:
            continue
        static.append(_record("static", demo.path, (labels, superpixels, frame), (start, goal), persona,
                              demo.jaywalked))
        semi.append(variant)
        if len(static) == n_pairs:
            break
    if len(static) < n_pairs:
        raise DataError(f"{semantic_map.name}: only {len(static)} of {n_pairs} start-goal pairs have a reachable "
                        "goal and a perturbable path; lower data.demos.pairs_per_map or check the map")
    return static, semi
