"""How well the trained context estimators reproduce the demonstrations' relaxations on the graph
(validation vs test), and the learned costs Fig. 6 draws.

Per run of ``surenav_context_estimator`` (the main run, the paper's training, on every seed; the other input
and our training variants on the first seeds) and training seed: the relaxation IoU of the plan that exact
graph A* makes under the predicted Psi (``train.evaluate``), averaged over the validation (real
validation tiles) and the test (the test tiles' context demonstrations) samples; the spread is over
training seeds. This is the graph-level quantity the training optimises; Table I's IoU comes from full
episodes. The floor beside them: Psi = 0, the shortest graph path through any soft region.

Fig. 6 (``learned_cost_scenarios``): the paper draws the learned costs on two test scenarios, a lawn
shortcut and a detour over a parking lot beside a new obstacle. Ours: the two context test demonstrations
that relax the most superpixels (on different tiles), planned by the main run's first seed, with the
estimator told which hard cells are new (the prior map's hard space is known, as in the executor).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np
import torch
from torch import nn

from navlab.core.labels import HARD_IDS
from navlab.core.params import Params
from navlab.core.params.surenav_model import TrainParams
from navlab.graphs.region_graph import RegionGraph
from navlab.maps.semantic_map import SemanticMap
from navlab.metrics.tables import Table
from navlab.surenav.context.benchmark import run_name
from navlab.surenav.context.dataset import load_context_demos
from navlab.surenav.context.training import (
    context_cost,
    context_samples,
    estimator_runs,
    load_context_estimator,
    main_run,
)
from navlab.surenav.experts import demo_graph
from navlab.surenav.experts.environments import Demonstration
from navlab.surenav.policy import SuReNavPolicy
from navlab.surenav.train import evaluate
from navlab.surenav.training_data import Sample

TABLE_ID = "estimator_relaxation_iou"
FLOOR = "Psi = 0 (shortest graph path, floor)"
NOTES = ("Relaxation IoU of the exact graph A* plan under the predicted Psi (path regions in R_soft) vs the "
         "demonstration's relaxed superpixels, on the demonstration's query-window graph as the walker relaxed on "
         "it; mean and standard deviation over training seeds. val = the real validation tiles' context "
         "demonstrations, test = the test tiles' (Table I's environments); test_minus_val is the gap. The Psi = 0 row "
         "is the floor: the shortest graph path. model.pt holds each seed's epoch of best validation IoU (early "
         "stopping). The paper prints no such number.")
COLUMNS = ("method", "val_iou", "val_iou_sd", "test_iou", "test_iou_sd", "test_minus_val", "seeds")


class ZeroCost(nn.Module):
    """Psi = 0 on every node: graph A* then plans the shortest path through any soft region (the floor)."""

    def forward(self, data) -> torch.Tensor:
        return torch.zeros(data.num_nodes)


def estimator_rows(runs: Mapping[str, tuple[Sequence[nn.Module], Mapping[str, Sequence[Sample]]]],
                   train: TrainParams) -> list[dict]:
    """One row per run name: (its model per training seed, its samples per split — keys ``val`` and
    ``test``, built for its input); mean and standard deviation over seeds of the plan IoU on each split,
    then the Psi = 0 floor on the first run's samples."""
    rows = []
    for name, (models, samples) in runs.items():
        row = {"method": name, "seeds": len(models)}
        for split, chosen in samples.items():
            values = [evaluate(model, chosen, train)[1] for model in models]
            row[f"{split}_iou"] = float(np.mean(values))
            row[f"{split}_iou_sd"] = float(np.std(values, ddof=1)) if len(values) > 1 else None
        rows.append(row)
    first = next(iter(runs.values()))[1]
    rows.append({"method": FLOOR, "seeds": None, **{f"{split}_iou_sd": None for split in first},
                 **{f"{split}_iou": evaluate(ZeroCost(), chosen, train)[1] for split, chosen in first.items()}})
    for row in rows:
        if "val_iou" in row and "test_iou" in row:
            row["test_minus_val"] = row["test_iou"] - row["val_iou"]
    return rows


def context_estimator_table(params: Params, artifacts_dir: str | Path) -> Table:
    """``estimator_rows`` of every ``surenav_context_estimator`` run as a report (no paper rows, no claim)."""
    s = params.surenav
    main = main_run(s.demos.context, s.train)
    samples: dict[str, dict[str, list[Sample]]] = {}
    runs = {}
    for run, seeds in estimator_runs(s.demos.context, s.train).items():
        if run.features not in samples:
            samples[run.features] = {split: context_samples(artifacts_dir, split, s.graph, s.model, run.features)
                                     for split in ("val", "test")}
        runs[run_name(run, main)] = ([load_context_estimator(artifacts_dir, run, seed)[0] for seed in seeds],
                                     samples[run.features])
    return Table(TABLE_ID, "SuReNav Sec. IV-D (no printed figure)", list(COLUMNS), estimator_rows(runs, s.train), [],
                 NOTES)


class CostScenario(NamedTuple):
    """One Fig. 6 panel: the map the demonstration walked, its graph, the window's nodes and their Psi,
    the graph plan (node ids, None without a path) and the demonstration."""
    view: SemanticMap
    graph: RegionGraph
    nodes: np.ndarray
    psi: np.ndarray
    route: np.ndarray | None
    demo: Demonstration


def relax_on_prior(estimator, prior_labels: np.ndarray, graph: RegionGraph, start_xy, goal_xy, params: Params
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """SuReNav's graph plan on ``graph`` (``policy.SuReNavPolicy.relax``: window nodes, their Psi, the route)
    with a fresh relaxation cost from ``estimator`` (``context.training.context_cost``) that knows the prior
    map's hard space, so hard cells beyond it read as new obstacles, as in the executor."""
    s = params.surenav
    cost = estimator()
    cost.known_hard = np.isin(prior_labels, HARD_IDS)
    return SuReNavPolicy(cost, s.planner.mode, s.model.window_margin_m).relax(graph, start_xy, goal_xy)


def learned_cost_scenarios(params: Params, artifacts_dir: str | Path, count: int = 2) -> list[CostScenario]:
    """The ``count`` test demonstrations relaxing the most superpixels, one per tile, planned by the main run's
    first seed (module docstring)."""
    s = params.surenav
    estimator = context_cost(artifacts_dir, main_run(s.demos.context, s.train), s.train.seeds[0])
    ranked = sorted(((len(demo.relaxed_superpixels), smap.name, i, smap, md, demo)
                     for smap, md in load_context_demos(artifacts_dir, "test") for i, demo in enumerate(md.semi_static)),
                    key=lambda t: (-t[0], t[1], t[2]))
    chosen, tiles = [], set()
    for _, name, _, smap, md, demo in ranked:
        if name in tiles:
            continue
        tiles.add(name)
        graph = demo_graph(md, demo, smap, s.graph)
        nodes, psi, route = relax_on_prior(estimator, smap.labels, graph, demo.start, demo.goal, params)
        chosen.append(CostScenario(SemanticMap(smap.name, demo.labels_on(smap.labels), smap.frame), graph, nodes, psi,
                                   route, demo))
        if len(chosen) == count:
            break
    return chosen
