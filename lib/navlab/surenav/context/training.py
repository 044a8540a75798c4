"""SuReNav's estimator trained on the context demonstrations: the ``surenav_context_estimator`` artefact step.

Same recipe as ``surenav_estimator`` (``surenav.model``, ``surenav.train``: Eq. 13 through the
differentiable graph A*, AdamW, early stopping on the validation plan IoU, ``train.seeds``), reusing
``surenav.train``'s batch planner, loss and evaluation, on two differences of data and input:

- a sample is a context demonstration on the graph its walker relaxed on: the query window's region
  graph (``surenav.semi_static.window_graph`` of the start-goal box grown by the margin), after the
  incremental update for the new obstacle, as the walker and the executor build it. Its target is the
  soft nodes of that graph holding a cell the demonstration entered;
- the node input is ``surenav.demos.context.node_features`` (``features``): "context" adds the rules'
  context per node.

and two of training:

- the gradient through the A* (``surenav.demos.context.estimator.gradient``): ``straight_through``
  is the paper's (Neural A*'s selection softmax) on ``surenav.train``'s schedule (lr, epochs, early
  stopping); ``blackbox`` (``surenav.blackbox``, Vlastelica et al. 2020; ours) trains ``estimator.epochs``
  on a cosine schedule from ``estimator.lr`` and keeps the best validation epoch (before the paper's
  closed-set count became the default, seed 0's validation plan IoU was 0.57 blackbox, 0.53
  straight-through; ``benchmarks/README.md``);
- where Eq. (12) counts the false positives (``surenav.train.false_positives_on``, straight-through
  only): the search's closed set (``closed``, the paper's) or the plan's relaxed regions (``path``, ours);
  the blackbox loss counts both terms on the plan by construction (``surenav.blackbox``).

The loop is ``train.train_estimator``'s (``core.training.fit``): a checkpoint after every epoch, resumed
when its key (code, parameters, samples, seed) matches, and ``model.pt`` kept when that key matches. Runs
(``estimator_runs``): the main run (the paper's training with the configured input) on every
``train.seeds``; on the first ``train.ablation_seeds``: the other input, the other gradient and the other
false-positive count (the variants that measure what each choice adds); and ``held_out_runs``: the main
run trained without one shipped city's tiles (train and validation), once per city, on the first seed
(the leave-one-city-out table). Each in ``artifacts/surenav/context_estimators/<run folder>/seed<k>/``
with ``model.pt``, ``checkpoint.pt`` and ``log.tsv``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from pathlib import Path
from typing import NamedTuple

import numpy as np
import torch

from navlab.core.fingerprint import code_fingerprint
from navlab.core.io import DataError, sha256_json
from navlab.core.labels import HARD_IDS, SOFT_IDS
from navlab.core.params import Params
from navlab.core.params.surenav_demos import ContextDemosParams, ContextEstimatorParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.core.params.surenav_model import EstimatorParams, TrainParams
from navlab.core.seeding import rng
from navlab.core.training import TrainingRun, descend, fit, load_torch, save_torch
from navlab.graphs.incremental import update_graph
from navlab.maps.osm import CITIES
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.blackbox import estimator_blackbox_loss
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
from navlab.surenav.semi_static import window_graph
from navlab.surenav.train import (
    TRAIN_IOU_STRIDE,
    _write_log,
    better_iou,
    evaluate,
    plan_batch,
    samples_key,
    training_loss,
)
from navlab.surenav.training_data import Sample, make_sample

GRADIENTS = ("blackbox", "straight_through")
FALSE_POSITIVES = ("closed", "path")  # where Eq. (12) counts them (surenav.train.false_positives_on)


class EstimatorRun(NamedTuple):
    """One trained configuration: the node input (``FEATURE_SETS``), the gradient (``GRADIENTS``), where
    Eq. (12) counts false positives (``FALSE_POSITIVES``; ``path`` for blackbox, whose loss is on the
    plan) and the shipped city whose tiles it never saw ("" = trained on every city)."""

    features: str
    gradient: str
    false_positives: str = "closed"
    held_out: str = ""

    @property
    def folder(self) -> str:
        fp = f"_fp-{self.false_positives}" if self.gradient == "straight_through" else ""
        return f"{self.features}_{self.gradient}{fp}" + (f"_without-{self.held_out}" if self.held_out else "")


def tile_city(name: str) -> str:
    """The shipped city a tile was cut from: ``<city>_r<row>c<col>`` (``maps.tiles.cut_tiles``)."""
    return name.rsplit("_r", 1)[0]


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
    """Every stored context demonstration of ``split`` (train / val) as a sample (the first ``max_demos``),
    named ``<tile>/semi_static/<i>``."""
    out = []
    for smap, md in load_context_demos(artifacts_dir, split):
        for i, demo in enumerate(md.semi_static):
            if max_demos and len(out) >= max_demos:
                return out
            out.append(demo_sample(smap, demo, graph, model, node_features, f"{smap.name}/semi_static/{i}"))
    return out


def without_city(samples: Sequence[Sample], city: str) -> list[Sample]:
    """The samples whose tile was not cut from ``city`` (all of them for "")."""
    return [s for s in samples if not city or tile_city(s.name.split("/")[0]) != city]


def _schedule(run: EstimatorRun, train: TrainParams, estimator: ContextEstimatorParams) -> TrainParams:
    """``surenav.train`` as the run trains: the paper's schedule for straight-through (with the run's
    false-positive count), the blackbox one's epochs and lr without early stopping (its cosine schedule keeps
    the best validation epoch) for blackbox."""
    if run.gradient == "straight_through":
        return dataclasses.replace(train, false_positives_on=run.false_positives)
    return dataclasses.replace(train, epochs=estimator.epochs, lr=estimator.lr, patience=0)


def train_context_estimator(train_samples: Sequence[Sample], val_samples: Sequence[Sample], model_params: EstimatorParams,
                            train: TrainParams, run: EstimatorRun, estimator: ContextEstimatorParams,
                            out_dir: str | Path, *, seed: int) -> Path:
    """``train.train_estimator``'s loop for a ``ContextEstimator`` (GPS) with ``run``'s input and gradient;
    returns ``model.pt``."""
    if not train_samples:
        raise DataError("no context training samples; build the surenav_context_demos stage")
    out_dir = Path(out_dir)
    torch.set_num_threads(train.threads)
    train = _schedule(run, train, estimator)
    settings = {k: v for k, v in dataclasses.asdict(train).items() if k not in ("device", "threads", "seeds", "ablation_seeds")}
    key = sha256_json({"code": code_fingerprint(__name__), "model": dataclasses.asdict(model_params), "train": settings,
                       "seed": seed, "run": run._asdict(), "lambda_m": estimator.lambda_m,
                       "inputs": [samples_key(train_samples), samples_key(val_samples)]})
    model_path = out_dir / "model.pt"
    if model_path.is_file() and torch.load(model_path, map_location="cpu", weights_only=False).get("key") == key:
        return model_path
    torch.manual_seed(seed)
    model = ContextEstimator(model_params, True, FEATURE_SETS[run.features])
    optimiser = torch.optim.AdamW(model.parameters(), lr=train.lr, weight_decay=train.weight_decay)
    steps = train.epochs * -(-len(train_samples) // train.batch_size)
    # torch's recursive cosine, not core.training.cosine_schedule: it differs in the last bits, and these
    # weights were trained with it; its state_dict resumes it exactly
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimiser, steps) if run.gradient == "blackbox" else None

    def train_epoch(epoch: int) -> dict[str, float]:
        order = rng(seed, "surenav.context.train", epoch).permutation(len(train_samples))
        losses = []
        for lo in range(0, len(order), train.batch_size):
            chunk = [train_samples[i] for i in order[lo:lo + train.batch_size]]
            if run.gradient == "blackbox":
                loss, value = estimator_blackbox_loss(model, chunk, train, estimator.lambda_m)
            else:
                loss = training_loss(*plan_batch(model, chunk, train.temperature), train)
                value = float(loss.detach())
            descend(loss, optimiser, schedule)
            losses.append(value)
        val_loss, val_iou = evaluate(model, val_samples, train)
        train_iou = evaluate(model, train_samples[::TRAIN_IOU_STRIDE], train)[1]
        return {"train_loss": float(np.mean(losses)), "val_loss": val_loss, "val_iou": val_iou, "train_iou": train_iou}

    fitted = fit(model, optimiser, TrainingRun(out_dir / "checkpoint.pt", key, train.epochs, train.patience,
                                               f"context estimator {run.folder} seed {seed}", progress=True),
                 train_epoch, better_iou, scheduler=schedule, on_epoch=lambda rows: _write_log(rows, out_dir / "log.tsv"))
    save_torch(model_path, {**architecture(model), "weights": model.state_dict(), "best_epoch": fitted.best_epoch,
                            "key": key, "seed": seed, "features": run.features, "gradient": run.gradient,
                            "log": fitted.log})
    return model_path


def context_model_path(artifacts_dir: str | Path, run: EstimatorRun, seed: int) -> Path:
    if (run.features not in FEATURE_SETS or run.gradient not in GRADIENTS or run.false_positives not in FALSE_POSITIVES
            or run.held_out not in ("", *CITIES)):
        raise ValueError(f"estimator run {tuple(run)}: choose node_features from {', '.join(FEATURE_SETS)}, the "
                         f"gradient from {', '.join(GRADIENTS)}, false positives from {', '.join(FALSE_POSITIVES)} "
                         f"and the held-out city from {', '.join(CITIES)} (or none)")
    return Path(artifacts_dir, "surenav", "context_estimators", run.folder, f"seed{seed}", "model.pt")


def main_run(context: ContextDemosParams, train: TrainParams) -> EstimatorRun:
    """The main row's training: the configured input and gradient, Eq. (12) counted as ``surenav.train`` says
    (blackbox counts on the plan)."""
    gradient = context.estimator.gradient
    return EstimatorRun(context.node_features, gradient,
                        train.false_positives_on if gradient == "straight_through" else "path")


def estimator_runs(context: ContextDemosParams, train: TrainParams) -> dict[EstimatorRun, tuple[int, ...]]:
    """run -> training seeds: the main run on every seed; on the first ``ablation_seeds``, the other input,
    the other gradient and (for a straight-through main run) the other false-positive count."""
    main = main_run(context, train)
    ablation = tuple(train.seeds[:train.ablation_seeds])
    other_input = next(f for f in FEATURE_SETS if f != main.features)
    other_gradient = next(g for g in GRADIENTS if g != main.gradient)
    runs = {main: tuple(train.seeds), main._replace(features=other_input): ablation,
            main._replace(gradient=other_gradient,
                          false_positives="path" if other_gradient == "blackbox" else train.false_positives_on): ablation}
    if main.gradient == "straight_through":
        runs[main._replace(false_positives=next(f for f in FALSE_POSITIVES if f != main.false_positives))] = ablation
    return runs


def held_out_runs(context: ContextDemosParams, train: TrainParams) -> dict[str, tuple[EstimatorRun, int]]:
    """city -> (the main run trained without that city's tiles, its seed: the first training seed), for
    each of ``estimator.held_out_cities``."""
    return {city: (main_run(context, train)._replace(held_out=city), train.seeds[0])
            for city in context.estimator.held_out_cities}


def build_context_estimators(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
    """Artefact step ``surenav_context_estimator`` (module docstring): every ``estimator_runs`` run, then the
    ``held_out_runs``."""
    s = params.surenav
    samples: dict[str, tuple[list[Sample], list[Sample]]] = {}
    runs = [(run, seed) for run, seeds in estimator_runs(s.demos.context, s.train).items() for seed in seeds]
    runs += list(held_out_runs(s.demos.context, s.train).values())
    for run, seed in runs:
        if run.features not in samples:
            samples[run.features] = tuple(context_samples(artifacts_dir, split, s.graph, s.model, run.features,
                                                          s.train.max_demos) for split in ("train", "val"))
        train_samples, val_samples = (without_city(part, run.held_out) for part in samples[run.features])
        if not val_samples:
            raise DataError(f"no validation tile outside {run.held_out}: the leave-one-city-out run has nothing to "
                            "stop on; raise surenav.demos.context.val_tiles")
        train_context_estimator(train_samples, val_samples, s.model, s.train, run, s.demos.context.estimator,
                                context_model_path(artifacts_dir, run, seed).parent, seed=seed)


def load_context_estimator(artifacts_dir: str | Path, run: EstimatorRun, seed: int) -> tuple[ContextEstimator, str]:
    """(trained estimator in eval mode, its node_features) of one run."""
    path = context_model_path(artifacts_dir, run, seed)
    fix = "rebuild it with `python -m navlab artifacts build --only surenav_context_estimator`"
    if not path.is_file():
        raise DataError(f"{path} is missing; {fix}")
    try:
        saved = load_torch(path)
    except DataError as err:  # truncated or garbage bytes
        raise DataError(f"{err}; {fix}") from None
    try:
        model = from_architecture(saved)
        model.load_state_dict(saved["weights"])
        features = saved["features"]
    except (KeyError, TypeError, RuntimeError, ValueError, AttributeError) as err:
        raise DataError(f"{path} does not hold an estimator this code can load ({type(err).__name__}: "
                        f"{str(err).splitlines()[0][:200] if str(err) else ''}); {fix}") from None
    return model.eval(), features


def context_cost(artifacts_dir: str | Path, run: EstimatorRun, seed: int):
    """A factory of fresh ``EstimatorCost`` relaxation costs (one per episode: each tracks its own known
    hard space) from the trained estimator of one run, loaded once."""
    model, features = load_context_estimator(artifacts_dir, run, seed)
    return lambda: EstimatorCost(model, features)
