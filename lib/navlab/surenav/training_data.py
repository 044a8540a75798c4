"""Training samples from the expert demonstrations (SuReNav Sec. IV-C.1): graph, query, relaxed regions.

Each demonstration becomes one sample on the region graph it was drawn on (``experts.demo_graph``:
the map's superpixels, after the incremental update for a semi-static one), cut to the query window
(``model.inputs.window_nodes``). Its target v*_rlx marks the soft regions the expert entered
(``relaxed_superpixels``; Eq. 12's B v_rlx): the demonstration projected onto the graph (Eq. 5)
restricted to R_soft. The static demonstrations of one map share its graph, so it is built once.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from torch_geometric.data import Data
from tqdm.auto import tqdm

from navlab.core.params.surenav_graph import GraphParams
from navlab.core.params.surenav_model import EstimatorParams
from navlab.graphs.region_graph import RegionGraph, build_region_graph
from navlab.maps.dataset import load_maps
from navlab.search.graph_astar import SearchGraph, csr_graph
from navlab.surenav.experts.environments import Demonstration
from navlab.surenav.experts.store import demo_graph, load_demos
from navlab.surenav.model.inputs import estimator_input, induced_edges, window_nodes


@dataclass(frozen=True)
class Sample:
    """One demonstration on its windowed region graph (node indices local to the window)."""

    data: Data  # estimator input (model.inputs.estimator_input)
    search: SearchGraph  # the window's CSR graph for (differentiable) graph A*
    start: int
    goal: int
    target: np.ndarray  # (n,) bool: v*_rlx, the soft regions the expert relaxed
    dropped: int  # relaxed regions outside the window (not learnable from this sample)
    name: str  # "<map>/<kind>/<index>"


def make_sample(graph: RegionGraph, relaxed_nodes: np.ndarray, model: EstimatorParams, name: str) -> Sample:
    """A sample from a graph with start/goal set and the (global) node indices the expert relaxed."""
    nodes = window_nodes(graph, graph.centroid[graph.start_node], graph.centroid[graph.goal_node],
                         model.window_margin_m)
    local = np.full(graph.num_nodes, -1, dtype=np.int64)
    local[nodes] = np.arange(len(nodes))
    relaxed_local = local[np.asarray(relaxed_nodes, dtype=np.int64)]
    target = np.zeros(len(nodes), dtype=bool)
    target[relaxed_local[relaxed_local >= 0]] = True
    edges, _ = induced_edges(graph, nodes)
    return Sample(data=estimator_input(graph, nodes, model.walk_steps), search=csr_graph(graph.centroid[nodes], edges),
                  start=int(local[graph.start_node]), goal=int(local[graph.goal_node]), target=target,
                  dropped=int((relaxed_local < 0).sum()), name=name)


def relaxed_nodes(graph: RegionGraph, demo: Demonstration) -> np.ndarray:
    """Node indices of the demonstration's relaxed superpixels (raster ids of ``graph``)."""
    nodes = np.searchsorted(graph.region_ids, demo.relaxed_superpixels)
    nodes = np.minimum(nodes, graph.num_nodes - 1)
    if not np.array_equal(graph.region_ids[nodes], demo.relaxed_superpixels):
        raise ValueError("a demonstration's relaxed superpixels are not regions of its graph; rebuild data/ with "
                         "`python -m navlab data build` (params surenav.graph changed since)")
    return nodes


def demo_samples(data_dir: str | Path, split: str, graph: GraphParams, model: EstimatorParams,
                 max_demos: int = 0, progress: bool = True) -> list[Sample]:
    """Every demonstration of ``split`` (map by map, static then semi-static) as a sample; ``max_demos``
    > 0 keeps only the first that many (a quick run)."""
    maps = {m.name: m for m in load_maps(data_dir, split)}
    stored = load_demos(data_dir, split)
    total = sum(len(md.static) + len(md.semi_static) for md in stored)
    limit = max_demos or total
    out: list[Sample] = []
    bar = tqdm(total=min(limit, total), desc=f"SuReNav samples ({split})", unit="demo", disable=not progress)
    for md in stored:
        smap = maps[md.map_name]
        base = build_region_graph(md.superpixels, smap.labels, smap.frame, graph.tau_m)
        for kind in ("static", "semi_static"):
            for i, demo in enumerate(getattr(md, kind)):
                if len(out) >= limit:
                    break
                g = base.with_endpoints(demo.start, demo.goal) if kind == "static" else demo_graph(md, demo, smap, graph)
                out.append(make_sample(g, relaxed_nodes(g, demo), model, f"{md.map_name}/{kind}/{i}"))
                bar.update()
    bar.close()
    return out
