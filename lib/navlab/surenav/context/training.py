"""SuReNav's estimator trained on the context demonstrations: the ``surenav_context_estimator`` artefact step.

Same recipe as ``surenav_estimator`` (``surenav.model``, ``surenav.train``: Eq. 13 through the
differentiable graph A*, AdamW, early stopping on the validation plan IoU, ``train.seeds``), reusing
``surenav.train``'s batch planner, loss and evaluation, on two differences of data and input:

- a sample is a context demonstration on the graph its walker relaxed on: the query window's region
  graph (``sim.semi_static.window_graph`` of the start-goal box grown by the margin), after the
  incremental update for the new obstacle, as the walker and the executor build it. Its target is the
  soft nodes of that graph holding a cell the demonstration entered;
- the node input is ``surenav.demos.context.node_features`` (``features``): "context" adds the rules'
  context per node.

The loop is ``train.train_estimator``'s, without its mid-run resume (a run is a couple of minutes);
``model.pt`` is kept when its key (code, parameters, samples, seed) matches. Folders:
``artifacts/surenav/context_gps/seed<k>/`` (context features, every ``train.seeds``) and
``artifacts/surenav/context_labels/seed<k>/`` (the old input, the first ``train.ablation_seeds``: the
ablation that measures what the features add), each with ``model.pt`` and ``log.tsv``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import torch

from navlab.core.fingerprint import code_fingerprint
from navlab.core.io import DataError, atomic_path, sha256_json
from navlab.core.labels import HARD_IDS, SOFT_IDS
from navlab.core.params import Params
from navlab.core.params.surenav_graph import GraphParams
from navlab.core.params.surenav_model import EstimatorParams, TrainParams
from navlab.core.seeding import rng
from navlab.graphs.incremental import update_graph
from navlab.maps.semantic_map import SemanticMap
from navlab.sim.semi_static import window_graph
from navlab.surenav.context.dataset import load_context_demos
from navlab.surenav.context.features import (
    FEATURE_SETS,
    ContextEstimator,
    EstimatorCost,
    architecture,
    context_features,
    from_architecture,
)
from navlab.surenav.episodes import window
from navlab.surenav.experts.environments import Demonstration
from navlab.surenav.train import (
    TRAIN_IOU_STRIDE,
    _write_log,
    evaluate,
    plan_batch,
    samples_key,
    training_loss,
)
from navlab.surenav.training_data import Sample, make_sample

FOLDERS = {"context": "context_gps", "labels": "context_labels"}  # node_features -> artifacts/surenav/<folder>


def demo_sample(smap: SemanticMap, demo: Demonstration, graph: GraphParams, model: EstimatorParams,
                node_features: str, name: str) -> Sample:
    """One context demonstration as a training sample on its walker's window graph (module docstring)."""
    res = smap.frame.resolution
    start, goal = smap.frame.world_to_cell(demo.start), smap.frame.world_to_cell(demo.goal)
    box = window(smap.labels.shape, start, goal, int(np.ceil(model.window_margin_m / res)))
    now = demo.labels_on(smap.labels)
    changed = now != smap.labels
    query = window_graph(smap.crop(*box), graph, smap.labels.size)
    if changed[box].any():
        query = update_graph(query, now[box], changed[box], compactness=graph.compactness, tau=graph.tau_m)
    g = query.with_endpoints(demo.start, demo.goal)
    rows, cols = np.unravel_index(demo.relaxed_cells, smap.labels.shape)
    inside = (rows >= box[0].start) & (rows < box[0].stop) & (cols >= box[1].start) & (cols < box[1].stop)
    nodes = g.node_raster[rows[inside] - box[0].start, cols[inside] - box[1].start]
    nodes = np.unique(nodes[nodes >= 0])
    sample = make_sample(g, nodes[np.isin(g.node_label[nodes], SOFT_IDS)], model, name)
    if node_features == "context":
        new_hard = (np.isin(now, HARD_IDS) & ~np.isin(smap.labels, HARD_IDS))[box]
        extra = torch.from_numpy(context_features(g, new_hard)[sample.data.nodes.numpy()])
        sample.data.x = torch.cat([sample.data.x, extra], dim=1)
    return sample


def context_samples(artifacts_dir: str | Path, split: str, graph: GraphParams, model: EstimatorParams,
                    node_features: str, max_demos: int = 0) -> list[Sample]:
    """Every stored context demonstration of ``split`` (train / val) as a sample (the first ``max_demos``)."""
    out = []
    for smap, md in load_context_demos(artifacts_dir, split):
        for i, demo in enumerate(md.semi_static):
            if max_demos and len(out) >= max_demos:
                return out
            out.append(demo_sample(smap, demo, graph, model, node_features, f"{smap.name}/semi_static/{i}"))
    return out


def _save(obj, path: Path) -> None:
    with atomic_path(path) as tmp:
        torch.save(obj, tmp)


def train_context_estimator(train_samples: Sequence[Sample], val_samples: Sequence[Sample], model_params: EstimatorParams,
                            train: TrainParams, node_features: str, out_dir: str | Path, *, seed: int) -> Path:
    """``train.train_estimator``'s loop for a ``ContextEstimator`` (GPS); returns ``model.pt``."""
    if not train_samples:
        raise DataError("no context training samples; build the surenav_context_demos stage")
    out_dir = Path(out_dir)
    torch.set_num_threads(train.threads)
    settings = {k: v for k, v in dataclasses.asdict(train).items() if k not in ("device", "threads", "seeds", "ablation_seeds")}
    key = sha256_json({"code": code_fingerprint(__name__), "model": dataclasses.asdict(model_params), "train": settings,
                       "seed": seed, "features": node_features,
                       "inputs": [samples_key(train_samples), samples_key(val_samples)]})
    model_path = out_dir / "model.pt"
    if model_path.is_file() and torch.load(model_path, map_location="cpu", weights_only=False).get("key") == key:
        return model_path
    torch.manual_seed(seed)
    model = ContextEstimator(model_params, True, FEATURE_SETS[node_features])
    optimiser = torch.optim.AdamW(model.parameters(), lr=train.lr, weight_decay=train.weight_decay)
    rows: list[dict] = []
    best: dict = {"val_iou": -1.0, "epoch": 0, "weights": None}
    for epoch in range(train.epochs):
        if train.patience and epoch - best["epoch"] >= train.patience:
            break
        model.train()
        order = rng(seed, "surenav.context.train", epoch).permutation(len(train_samples))
        losses = []
        for lo in range(0, len(order), train.batch_size):
            chunk = [train_samples[i] for i in order[lo:lo + train.batch_size]]
            result, v, target = plan_batch(model, chunk, train.temperature)
            loss = training_loss(result, v, target, train)
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            losses.append(float(loss.detach()))
        val_loss, val_iou = evaluate(model, val_samples, train)
        train_iou = evaluate(model, train_samples[::TRAIN_IOU_STRIDE], train)[1]
        rows.append({"epoch": epoch + 1, "train_loss": float(np.mean(losses)), "val_loss": val_loss,
                     "val_iou": val_iou, "train_iou": train_iou})
        if best["weights"] is None or not val_iou <= best["val_iou"]:
            best = {"val_iou": val_iou, "epoch": epoch + 1,
                    "weights": {k: w.detach().clone() for k, w in model.state_dict().items()}}
        _write_log(rows, out_dir / "log.tsv")
    _save({**architecture(model), "weights": best["weights"], "best_epoch": best["epoch"], "key": key, "seed": seed,
           "features": node_features, "log": rows}, model_path)
    return model_path


def context_model_path(artifacts_dir: str | Path, features: str, seed: int) -> Path:
    if features not in FOLDERS:
        raise ValueError(f"node_features {features!r}: choose one of {', '.join(FOLDERS)}")
    return Path(artifacts_dir, "surenav", FOLDERS[features], f"seed{seed}", "model.pt")


def feature_runs(main: str, train: TrainParams) -> dict[str, tuple[int, ...]]:
    """node_features -> training seeds: ``main`` on every seed, the other input on the first
    ``ablation_seeds`` (the ablation)."""
    other = next(f for f in FOLDERS if f != main)
    return {main: tuple(train.seeds), other: tuple(train.seeds[:train.ablation_seeds])}


def build_context_estimators(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
    """Artefact step ``surenav_context_estimator`` (module docstring)."""
    s = params.surenav
    for features, seeds in feature_runs(s.demos.context.node_features, s.train).items():
        train = context_samples(artifacts_dir, "train", s.graph, s.model, features, s.train.max_demos)
        val = context_samples(artifacts_dir, "val", s.graph, s.model, features, s.train.max_demos)
        for seed in seeds:
            train_context_estimator(train, val, s.model, s.train, features,
                                    context_model_path(artifacts_dir, features, seed).parent, seed=seed)


def load_context_estimator(artifacts_dir: str | Path, features: str, seed: int) -> tuple[ContextEstimator, str]:
    """(trained estimator in eval mode, its node_features) of one run."""
    path = context_model_path(artifacts_dir, features, seed)
    if not path.is_file():
        raise DataError(f"{path} is missing; build it with `python -m navlab artifacts build --only "
                        "surenav_context_estimator`")
    saved = torch.load(path, map_location="cpu", weights_only=False)
    model = from_architecture(saved)
    model.load_state_dict(saved["weights"])
    return model.eval(), saved["features"]


def context_cost(artifacts_dir: str | Path, features: str, seed: int):
    """A factory of fresh ``EstimatorCost`` relaxation costs (one per episode: each tracks its own known
    hard space) from the trained estimator of one run, loaded once."""
    model, features = load_context_estimator(artifacts_dir, features, seed)
    return lambda: EstimatorCost(model, features)
