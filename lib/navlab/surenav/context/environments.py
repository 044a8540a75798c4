"""Table I's human-likeness environments, redrawn by the context demonstrator.

Built as ``experts.environments`` builds the per-label benchmark's (start-goal pairs on sidewalks,
``data.demos`` distances; the semi-static variant perturbs a superpixel on the demonstrated path and
the walker redraws from a few metres before the change, knowing the obstacle is new), on the same
test maps, with the context walker and its personas in place of the per-label pedestrian. Only the
semi-static demonstrations are kept: they are Table I's environments.

The walker relaxes regions of the query's own region graph: the episode window (start-goal box grown
by the margin) segmented as the paper segments a query's map (``surenav.semi_static.window_graph``), and
after the change updated incrementally (Algorithm 1). A region-level choice made on another partition
(the whole tile's) would put a lane-wide walk along a road into other superpixels than the same
choice on the query's graph: measured on the first draft, the walker's own plans matched its
demonstrations at IoU 0.73 on the tile's partition and 0.49 on the window's.
"""

from __future__ import annotations

import numpy as np

from navlab.core.io import DataError
from navlab.core.labels import FREE_IDS, HARD_IDS
from navlab.core.params.demos import DemosParams
from navlab.core.params.surenav_demos import ContextDemosParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.core.seeding import rng
from navlab.graphs.incremental import resegment, update_graph
from navlab.graphs.region_graph import RegionGraph
from navlab.graphs.superpixels import label_consistent_slic
from navlab.maps.dataset import load_maps
from navlab.maps.perturb import obstruct_route
from navlab.maps.queries import sample_pairs
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.context.personas import CONTEXT_PERSONAS
from navlab.surenav.context.walker import ContextWalker
from navlab.surenav.episodes import Environment, window
from navlab.surenav.experts import Demonstration, relaxed_cells
from navlab.surenav.experts.hand_noise import dense_cells, hand_drawn
from navlab.surenav.semi_static import window_graph

PERTURB_TRIES = 4  # seeds tried before a pair gets no semi-static variant (as experts.environments)


def demonstrate(graph: RegionGraph, labels: np.ndarray, start, goal, persona: int, rng_: np.random.Generator,
                margin_m: float, known_hard: np.ndarray) -> tuple[np.ndarray, bool] | None:
    """(hand-drawn world path, jaywalked) from cell ``start`` to ``goal`` on ``labels`` and its region
    graph; None when the walker finds no way."""
    walker = ContextWalker(CONTEXT_PERSONAS[persona], margin_m, known_hard)
    cells = walker.plan(SemanticMap("demonstration", labels, graph.frame), graph, start, goal)
    if cells is None:
        return None
    who = CONTEXT_PERSONAS[persona]
    return hand_drawn(cells, graph.frame, walker.admissible, rng_, who.noise_amplitude_m,
                      who.noise_wavelength_m), walker.jaywalked


def _semi_static(smap: SemanticMap, superpixels: np.ndarray, path: np.ndarray, start, goal, persona: int,
                 rng_: np.random.Generator, settings: DemosParams, graph: GraphParams, query: RegionGraph
                 ) -> Demonstration | None:
    labels, frame = smap.labels, smap.frame
    res = frame.resolution
    box = window(labels.shape, start, goal, int(np.ceil(settings.window_margin_m / res)))
    off = np.array([box[0].start, box[1].start])
    route = dense_cells(path, frame)
    route = route[np.r_[True, np.any(route[1:] != route[:-1], axis=1)]]
    for _ in range(PERTURB_TRIES):
        change = obstruct_route(labels, superpixels, route, 1, rng_, obstacle_probability=settings.obstacle_probability,
                                clearance_cells=int(np.ceil(settings.endpoint_clearance_m / res)))
        if not change.changed.any():
            return None
        at = frame.world_to_cell(path)
        first = int(np.argmax(change.changed[at[:, 0], at[:, 1]]))
        cut = max(first - int(rng_.uniform(3.0, 8.0) / (res / 2)), 1)  # redraw from a few metres before the change
        updated = update_graph(query, change.labels[box], change.changed[box], compactness=graph.compactness,
                               tau=graph.tau_m)
        redraw = demonstrate(updated, change.labels[box], at[cut - 1] - off, np.asarray(goal) - off, persona, rng_,
                             settings.window_margin_m, np.isin(labels[box], HARD_IDS))
        if redraw is None:
            continue
        full = np.concatenate([path[:cut], redraw[0]])
        relaxed = relaxed_cells(change.labels, full, frame)
        reference = resegment(superpixels, change.labels, change.changed, graph.compactness)
        cells, new = change.delta()
        return Demonstration(kind="semi_static", path=full.astype(np.float32), start=frame.cell_to_world(start),
                             goal=frame.cell_to_world(goal), persona=persona, jaywalked=redraw[1],
                             relaxed_cells=relaxed.astype(np.int64),
                             relaxed_superpixels=np.unique(reference.ravel()[relaxed]).astype(np.int64),
                             delta_cells=cells, delta_labels=new, prefix_len=cut)
    return None


def map_demonstrations(smap: SemanticMap, superpixels: np.ndarray, n_pairs: int, settings: DemosParams,
                       rng_: np.random.Generator, graph: GraphParams) -> list[Demonstration]:
    """``n_pairs`` semi-static demonstrations of the context walker on one map; ``superpixels``: the
    tile's stored partition (what the relaxed sets refer to, as in Table I)."""
    margin = int(np.ceil(settings.window_margin_m / smap.frame.resolution))
    try:
        candidates = sample_pairs(smap, FREE_IDS, 4 * n_pairs, settings.min_distance_m, settings.max_distance_m, rng_)
    except ValueError as err:
        raise DataError(f"{err} (data.demos in params.yaml)") from None
    out = []
    for start, goal in candidates:
        persona = int(rng_.integers(len(CONTEXT_PERSONAS)))
        box = window(smap.labels.shape, start, goal, margin)
        off = np.array([box[0].start, box[1].start])
        query = window_graph(smap.crop(*box), graph, smap.labels.size)
        static = demonstrate(query, smap.labels[box], start - off, goal - off, persona, rng_, settings.window_margin_m,
                             np.isin(smap.labels[box], HARD_IDS))
        demo = None if static is None else _semi_static(smap, superpixels, static[0], start, goal, persona, rng_,
                                                         settings, graph, query)
        if demo is not None:
            out.append(demo)
        if len(out) == n_pairs:
            return out
    raise DataError(f"{smap.name}: only {len(out)} of {n_pairs} start-goal pairs have a reachable goal and a "
                    "perturbable path; lower surenav.demos.context.test_pairs_per_map")


def context_environments(data_dir, settings: DemosParams, context: ContextDemosParams, graph: GraphParams
                         ) -> tuple[list[Environment], dict[str, np.ndarray]]:
    """(environments, each test map's stored superpixels — the partition the relaxed sets refer to)."""
    envs, stored = [], {}
    for smap in load_maps(data_dir, "test"):
        stored[smap.name] = label_consistent_slic(smap.labels, graph.target_nodes, graph.compactness)
        demos = map_demonstrations(smap, stored[smap.name], context.test_pairs_per_map, settings,
                                   rng(context.seed, "context demos", smap.name), graph)
        for i, demo in enumerate(demos):
            envs.append(Environment(f"{smap.name}/{i}", smap.name, smap, demo.labels_on(smap.labels),
                                    smap.frame.world_to_cell(demo.start), smap.frame.world_to_cell(demo.goal),
                                    demo.persona, demo))
    return envs, stored
