"""PACER's staged training (Sec. V-C): phase 1 D_real → phase 2 + D_shuffled → phase 3 + D_synthetic.

Each phase starts from the previous phase's weights and trains until its selection score stops
improving: the learning rate follows a cosine decay over the phase's maximum epochs, the best
checkpoint is kept, and training stops after ``patience`` epochs without improvement. What "best"
means is ``pacer.train.select_on``: ``map_windows`` (the default, issue 24) the highest pixel-pair AUC
on a fixed, seeded set of validation map windows cut from training geography
(``map_windows.selection_score``: it tracks navigation, which the loss and named-pair agreement do not),
the validation loss breaking ties; ``val_loss`` the lowest validation loss (the behaviour before).
An epoch draws ``examples_per_epoch`` examples,
first a dataset uniformly among the phase's datasets (as the paper does), then an example uniformly
within it; the draw is keyed by (seed, phase, epoch), and datasets that render examples on the fly
are told the epoch (``set_epoch``) so each epoch sees fresh images; so a run resumed from a checkpoint sees exactly
the batches an uninterrupted run would have seen and ends at the same weights.

Files in a phase's folder: ``checkpoint.pt`` (after every epoch, atomic), ``model.pt`` (the best
weights, byte-deterministic), ``val_loss.tsv`` (one row per epoch, for `dvc plots`: the training loss, Eq. 3
plus the matching and contrast losses (``ExtraLosses``); the validation loss, Eq. 3 alone, so that it reads
against the entropy floor; and the map-window score, NaN when not measured), ``summary.json`` (best epoch,
its validation loss beside the entropy floor of the validation targets, what it was selected on and its
score) and ``training_cost.json`` (what the run cost where it ran: wall seconds per epoch, peak memory; named
in ``.dvcignore``, so it is no part of the folder's DVC hash, and the folder a machine trains is byte for byte
the one another machine running the same kernels trains). The checkpoint is keyed on
``run_key``: the code fingerprint of the training and dataset modules, every parameter that shapes the
weights (epochs included, so fewer epochs give the shorter model), the inputs and the initial weights;
only a run of the same key resumes.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import resource
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch.utils.data import DataLoader, Dataset
from tqdm.auto import tqdm

from navlab.core.fingerprint import code_fingerprint
from navlab.core.io import sha256_file, sha256_json, write_json, write_text
from navlab.core.params.pacer import PacerModelParams, PacerTrainParams
from navlab.core.seeding import rng
from navlab.core.training import TrainingRun, cosine_schedule, descend, fit, save_torch
from navlab.pacer.checkpoints import load_network
from navlab.pacer.loss import contrast_loss, entropy_floor, masked_bce, matching_loss
from navlab.pacer.map_windows import MapWindow, selection_score
from navlab.pacer.model import PacerNet, build_model

PHASES = ("phase1", "phase2", "phase3")
PHASE_DATASETS = {"phase1": ("real",), "phase2": ("real", "shuffled"), "phase3": ("real", "shuffled", "synthetic")}
BATCH_KEYS = ("image", "context", "costmap", "fov_mask", "labels", "pairs")
SELECT_ON = ("map_windows", "val_loss")  # pacer.train.select_on


def collate(items: Sequence[dict]) -> dict[str, torch.Tensor]:
    """Stack the tensors the losses need; the ordering stays with the datasets."""
    return {k: torch.stack([torch.as_tensor(np.asarray(it[k])) for it in items]) for k in BATCH_KEYS}


def epoch_draws(sizes: Sequence[int], count: int, seed: int, phase: str, epoch: int) -> list[tuple[int, int]]:
    """``count`` (dataset, example) pairs: dataset uniform over the phase's sets, example uniform within."""
    if not sizes or min(sizes) == 0:
        raise ValueError(f"{phase}: every training dataset needs at least one example (sizes {list(sizes)})")
    gen = rng(seed, "pacer.train", phase, epoch)
    which = gen.integers(0, len(sizes), size=count)
    index = (gen.random(count) * np.asarray(sizes)[which]).astype(np.int64)
    return list(zip(which.tolist(), index.tolist()))


@dataclasses.dataclass(frozen=True)
class ExtraLosses:
    """The losses ours adds beside Eq. 3 (``pacer.train``; all 0 in the paper's recipe)."""

    match_weight: float = 0.0  # the matcher's matching loss (pacer.loss.matching_loss)
    contrast_weight: float = 0.0  # the terrain-contrast hinge (pacer.loss.contrast_loss)
    contrast_margin: float = 1.0

    @classmethod
    def of(cls, train_cfg: PacerTrainParams) -> ExtraLosses:
        return cls(train_cfg.match_loss_weight, train_cfg.contrast_loss_weight, train_cfg.contrast_margin)


def batch_loss(model: PacerNet, batch: dict[str, torch.Tensor], device,
               extra: ExtraLosses = ExtraLosses()) -> torch.Tensor:
    """Masked BCE of one batch (Eq. 3), plus the ``extra`` losses; images and contexts go in channels-last,
    the layout in which the CPU (oneDNN) convolutions of a channels-last model run fastest (1.4x per
    training step, default profile)."""
    image, context = (batch[k].to(device, torch.float32, memory_format=torch.channels_last)
                      for k in ("image", "context"))
    logits, cosines = model.scored(image, context)
    target, labels = batch["costmap"].to(device), batch["labels"].to(device)
    loss = masked_bce(logits, target, batch["fov_mask"].to(device))
    if extra.match_weight > 0:
        pairs = batch["pairs"].to(device)
        loss = loss + extra.match_weight * matching_loss(cosines, model.matcher.log_temperature.exp(), labels,
                                                         torch.cat([pairs[:, :, 0], pairs[:, :, 1]], 1))
    if extra.contrast_weight > 0:
        loss = loss + extra.contrast_weight * contrast_loss(logits, target, labels, extra.contrast_margin)
    return loss


@torch.no_grad()
def validation_loss(model: PacerNet, datasets: Sequence[Dataset], batch_size: int, device="cpu") -> float:
    """Mean masked BCE over every example of ``datasets`` (eval mode); NaN when there are none.
    ``datasets`` may be lists of rendered items (what ``train_phase`` passes, rendering them once)."""
    model.eval()
    total, count = 0.0, 0
    for ds in datasets:
        for start in range(0, len(ds), batch_size):
            items = [ds[i] for i in range(start, min(start + batch_size, len(ds)))]
            total += batch_loss(model, collate(items), device).item() * len(items)
            count += len(items)
    return total / count if count else float("nan")


def run_key(model_cfg: PacerModelParams, train_cfg: PacerTrainParams, *, seed: int, phase: str, epochs: int,
            sizes: Sequence[int], init_from: Path | None, code: str, inputs: Any = None) -> str:
    """What a checkpoint must match to be resumed: code, parameters (the device and the thread count too: each
    sums a convolution's terms in its own order, so a run resumed under another trains weights no uninterrupted
    run would; not the worker count, which renders the same seeded items), epochs, dataset sizes, inputs and
    the initial weights."""
    train = {k: v for k, v in dataclasses.asdict(train_cfg).items() if k not in ("workers", "epochs")}
    init = sha256_file(init_from) if init_from is not None else None
    return sha256_json({"code": code, "model": dataclasses.asdict(model_cfg), "train": train, "seed": seed,
                        "phase": phase, "epochs": epochs, "sizes": list(sizes), "init": init, "inputs": inputs})


def windows_fingerprint(windows: Sequence[MapWindow]) -> str:
    """sha256 of the selection windows' images, labels, orderings, contexts and pairs (they are part of what
    a run is: the street maps they are cut from are not in the terrain inputs)."""
    digest = hashlib.sha256()
    for w in windows:
        for array in (w.image, w.labels, w.ordering, w.context, w.pairs):
            digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


def training_code(datasets: Sequence[Dataset]) -> str:
    """Fingerprint of this module and the navlab modules that define ``datasets`` (they render the examples)."""
    modules = {type(ds).__module__ for ds in datasets}
    modules |= {type(ds.dataset).__module__ for ds in datasets if hasattr(ds, "dataset")}  # torch Subset
    return code_fingerprint(__name__, *sorted(m for m in modules if m.startswith("navlab.")))


COST_FILE = "training_cost.json"  # beside summary.json; .dvcignore keeps it out of the folder's hash


def training_cost(epoch_seconds: dict[int, float], train_cfg: PacerTrainParams) -> dict:
    """What the phase cost (issue 24's budget): wall seconds summed over its epochs (``epoch_seconds``: a resumed
    run counts the epochs it resumed, each timed where it ran: training, validation and selection), the peak
    resident memory of this process and of its item-rendering workers, and the threads and workers it ran with.
    Kept out of ``summary.json`` and the checkpoint: a timing in a hashed file makes every rebuild a new output."""
    peak_kib = max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
    return {"train_seconds": round(sum(epoch_seconds.values()), 1), "peak_rss_mib": round(peak_kib / 1024),
            "threads": train_cfg.threads, "workers": train_cfg.workers}


def _epoch_seconds(out_dir: Path, key: str) -> dict[int, float]:
    """The epoch times an interrupted run of the same ``key`` recorded in ``out_dir`` (none for another run)."""
    path = out_dir / COST_FILE
    try:
        saved = json.loads(path.read_text())
    except (OSError, ValueError):
        return {}
    return {int(e): float(s) for e, s in saved.get("epoch_seconds", {}).items()} if saved.get("key") == key else {}


def _write_cost(out_dir: Path, key: str, epoch_seconds: dict[int, float], train_cfg: PacerTrainParams) -> None:
    write_json(out_dir / COST_FILE, {"key": key, **training_cost(epoch_seconds, train_cfg),
                                     "epoch_seconds": {str(e): round(s, 2) for e, s in sorted(epoch_seconds.items())}})


def _write_log(rows: list[dict], path: Path) -> None:
    lines = ["epoch\ttrain_loss\tval_loss\tselect_score"] + [
        f"{r['epoch']}\t{r['train_loss']:.6f}\t{r['val_loss']:.6f}\t{r.get('select_score', float('nan')):.6f}"
        for r in rows]
    write_text(path, "\n".join(lines) + "\n")


def load_model(path: str | Path, device: str | torch.device = "cpu") -> PacerNet:
    """A trained network from a phase's ``model.pt`` (its architecture is stored beside the weights)."""
    path = Path(path)
    # models saved before ``match_channels`` existed have no texture matcher, before ``match_dilated`` a pooled one,
    # before ``match_luminance`` a colour tower alone, before ``match_features`` towers trained from scratch
    old = {"match_channels": (), "match_dilated": False, "match_luminance": False, "match_features": "scratch"}
    return load_network(path, lambda saved: build_model(PacerModelParams(**{**old, **saved["model_config"]}),
                                                        context_pairs=saved["context_pairs"],
                                                        patch_size=saved.get("patch_size")),
                        rebuild_stage(path), device)


def rebuild_stage(path: Path) -> str:
    """The DVC stage that writes a phase's ``model.pt``: ``pacer_<phase>`` for the main model, the variant's stage
    (``pacer_seeds``, ``pacer_paper_architecture``) for a model under ``artifacts/pacer/variants/<variant>/``."""
    parts = path.parts
    if "variants" in parts[:-1] and parts.index("variants") + 1 < len(parts) - 1:
        return f"pacer_{parts[parts.index('variants') + 1]}"
    return f"pacer_{path.parent.name}"


def resolve_device(name: str) -> torch.device:
    """``pacer.train.device`` as a torch device; asking for CUDA where torch sees no GPU is one clear error
    (a paper-size run never falls back to hours of CPU training unannounced)."""
    device = torch.device(name)
    if device.type == "cuda" and not torch.cuda.is_available():
        raise ValueError(f"pacer.train.device = {name!r} but torch {torch.__version__} sees no CUDA GPU on this "
                         "machine; run the `gpu`/`paper` profiles on a CUDA machine, or use the `default` profile "
                         "(CPU)")
    return device


class _Drawn(Dataset):
    """One epoch's drawn (dataset, example) pairs as a Dataset, so a DataLoader's workers can render them."""

    def __init__(self, datasets: Sequence[Dataset], draws: Sequence[tuple[int, int]]):
        self.datasets, self.draws = datasets, draws

    def __len__(self) -> int:
        return len(self.draws)

    def __getitem__(self, k: int):
        d, i = self.draws[k]
        return self.datasets[d][i]


def epoch_batches(datasets: Sequence[Dataset], draws: Sequence[tuple[int, int]], batch_size: int, workers: int):
    """The epoch's batches in draw order; ``workers`` > 0 renders items in that many processes (the
    same items, since every item is seeded by its index and epoch, whoever renders it)."""
    return DataLoader(_Drawn(datasets, draws), batch_size=batch_size, shuffle=False, collate_fn=collate,
                      num_workers=workers, persistent_workers=False)


def improves(select_on: str, row: dict, best: dict) -> bool:
    """Whether an epoch's log ``row`` beats the ``best`` one so far: on ``val_loss`` by the validation loss
    alone; on ``map_windows`` by ``select_score`` (map-window selection score, higher is better; NaN when not
    measured), a tie (or a NaN score, where no window shows two terrains) falling back to the loss."""
    if select_on not in SELECT_ON:
        raise ValueError(f"pacer.train.select_on = {select_on!r}: allowed values are {', '.join(SELECT_ON)}")
    score, best_score = row["select_score"], best["select_score"]
    if select_on == "map_windows" and not (np.isnan(score) and np.isnan(best_score)) and score != best_score:
        return bool(np.nan_to_num(score, nan=-np.inf) > np.nan_to_num(best_score, nan=-np.inf))
    return row["val_loss"] < best["val_loss"]


@dataclasses.dataclass(frozen=True)
class PhaseRun:
    """Which phase ``train_phase`` trains: its name (it keys the epoch draws and the checkpoint), the most
    epochs, the seed (of phase 1's initialisation and of every draw), the context's pair count and the
    weights it starts from (the previous phase's ``model.pt``; None: fresh), and the patch side."""

    phase: str
    epochs: int
    seed: int
    context_pairs: int = 3
    init_from: str | Path | None = None
    patch_size: int | None = None  # the context patches' side (the model refuses any other)


@dataclasses.dataclass(frozen=True)
class Selection:
    """What ``pacer.train.select_on: map_windows`` scores each epoch on: fixed validation map windows, at
    the planner's ``cost_scale`` (per-metre cost 1 + cost_scale x c)."""

    windows: Sequence[MapWindow] = ()
    cost_scale: float = 10.0


def train_phase(
    model_cfg: PacerModelParams,
    train_cfg: PacerTrainParams,
    train_sets: Sequence[Dataset],
    val_sets: Sequence[Dataset],
    out_dir: str | Path,
    run: PhaseRun,
    *,
    inputs: Any = None,
    progress: bool = True,
    selection: Selection = Selection(),
) -> Path:
    """Train one phase into ``out_dir`` (resuming its checkpoint if it matches) and return ``model.pt``.

    Up to ``run.epochs`` epochs with the learning rate decayed by a cosine over all of them; after every
    epoch the validation loss (and, with ``train_cfg.select_on`` map_windows, the selection score on
    ``selection``'s windows at the planner's cost scale) is measured and the best weights (``improves``)
    are kept; training stops early once they have not improved for ``train_cfg.patience`` epochs. ``model.pt`` holds the best
    weights, ``summary.json`` the best epoch, its validation loss and the entropy floor of the
    validation targets (the lowest loss any model can reach, :func:`navlab.pacer.loss.entropy_floor`).
    ``inputs``: a fingerprint of the files the datasets read (part of the run key).
    """
    out_dir = Path(out_dir)
    phase, epochs, seed, context_pairs = run.phase, run.epochs, run.seed, run.context_pairs
    select_windows, cost_scale = selection.windows, selection.cost_scale
    if train_cfg.select_on not in SELECT_ON:
        raise ValueError(f"pacer.train.select_on = {train_cfg.select_on!r}: allowed values are {', '.join(SELECT_ON)}")
    if train_cfg.select_on == "map_windows" and not select_windows:
        raise ValueError(f"{phase}: pacer.train.select_on = 'map_windows' needs validation map windows "
                         "(selection=Selection(windows), navlab.pacer.map_windows.map_windows); or select on val_loss")
    if train_cfg.match_loss_weight > 0 and not model_cfg.match_channels:
        raise ValueError(f"{phase}: pacer.train.match_loss_weight = {train_cfg.match_loss_weight} trains a texture "
                         "matcher, but pacer.model.match_channels is [] (no matcher); set the weight to 0 or give "
                         "the matcher channels")
    device = resolve_device(train_cfg.device)
    torch.set_num_threads(train_cfg.threads)
    init_from = Path(run.init_from) if run.init_from is not None else None
    initial = load_model(init_from, device) if init_from is not None else None  # missing/corrupt: says so first
    sizes = [len(ds) for ds in train_sets]
    select = train_cfg.select_on == "map_windows"
    key = run_key(model_cfg, train_cfg, seed=seed, phase=phase, epochs=epochs, sizes=sizes, init_from=init_from,
                  code=training_code([*train_sets, *val_sets]),
                  inputs={"files": inputs, "cost_scale": cost_scale if select else None,
                          "select_windows": windows_fingerprint(select_windows) if select else None})
    steps_per_epoch = -(-train_cfg.examples_per_epoch // train_cfg.batch_size)

    # the validation items are the same every epoch (no ``set_epoch``): render them once, not per epoch
    val_items = [[ds[i] for i in tqdm(range(len(ds)), desc=f"PACER {phase}: rendering validation items",
                                      leave=False, disable=not progress)] for ds in val_sets]

    torch.manual_seed(seed)  # layer initialisation of phase 1
    model = build_model(model_cfg, context_pairs=context_pairs, patch_size=run.patch_size,
                        device=device).to(memory_format=torch.channels_last)
    if initial is not None:  # a resumed checkpoint replaces these weights
        model.load_state_dict(initial.state_dict())
    optimiser = torch.optim.Adam(model.parameters(), lr=train_cfg.lr)
    schedule = cosine_schedule(optimiser, epochs * steps_per_epoch, train_cfg.lr_final_fraction)

    extra = ExtraLosses.of(train_cfg)
    epoch_seconds = _epoch_seconds(out_dir, key)

    def train_epoch(epoch: int) -> dict[str, float]:
        started = time.perf_counter()
        for ds in train_sets:  # fresh renders per epoch where a dataset can make them (seeded by epoch)
            if hasattr(ds, "set_epoch"):
                ds.set_epoch(epoch)
        draws = epoch_draws(sizes, train_cfg.examples_per_epoch, seed, phase, epoch)
        losses = []
        for batch in tqdm(epoch_batches(train_sets, draws, train_cfg.batch_size, train_cfg.workers),
                          desc=f"PACER {phase} epoch {epoch + 1}", total=steps_per_epoch, unit="step", leave=False,
                          disable=not progress):
            loss = batch_loss(model, batch, device, extra)
            descend(loss, optimiser, schedule)
            losses.append(loss.item())
        val = validation_loss(model, val_items, train_cfg.batch_size, device)
        score = (selection_score(model, select_windows, cost_scale, batch=train_cfg.batch_size, device=device)
                 if select else float("nan"))
        epoch_seconds[epoch + 1] = time.perf_counter() - started  # the log's epochs count from 1
        return {"train_loss": float(np.mean(losses)), "val_loss": val, "select_score": score}

    def on_epoch(rows: list[dict]) -> None:
        _write_log(rows, out_dir / "val_loss.tsv")
        _write_cost(out_dir, key, epoch_seconds, train_cfg)

    fitted = fit(model, optimiser, TrainingRun(out_dir / "checkpoint.pt", key, epochs, train_cfg.patience,
                                               f"PACER {phase}", progress),
                 train_epoch, lambda row, best: improves(train_cfg.select_on, row, best), scheduler=schedule,
                 device=device, on_epoch=on_epoch)
    rows, best = fitted.log, fitted.best
    _write_log(rows, out_dir / "val_loss.tsv")
    write_json(out_dir / "summary.json", {
        "phase": phase, "epochs_run": len(rows), "max_epochs": epochs, "stopped_early": len(rows) < epochs,
        "best_epoch": fitted.best_epoch, "best_val_loss": best["val_loss"] if best is not None else None,
        "select_on": train_cfg.select_on,
        "best_select_score": best["select_score"] if select and best is not None else None,
        "entropy_floor": entropy_floor(val_items), "steps": len(rows) * steps_per_epoch,
    })
    _write_cost(out_dir, key, {e: s for e, s in epoch_seconds.items() if e <= len(rows)}, train_cfg)
    model_path = out_dir / "model.pt"
    save_torch(model_path, {"model_config": dataclasses.asdict(model_cfg), "context_pairs": context_pairs,
                            "patch_size": run.patch_size,
                            "weights": {k: v.contiguous() for k, v in model.state_dict().items()}, "phase": phase, "epochs": len(rows),
                            "best_epoch": fitted.best_epoch})
    return model_path

