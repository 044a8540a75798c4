"""Training shared by PACER and SuReNav: checkpoint files, the cosine schedule, one descent step and a
resumable epoch loop (``fit``).

Checkpoint files are serialised in memory and then written atomically, so the temporary file's name
never ends up inside the archive (torch.save names the archive after the file it writes) and re-saving
the same weights gives the same bytes. A checkpoint carries the ``key`` of the run that wrote it (code
fingerprint + parameters + inputs, see ``navlab.core.fingerprint``); ``resume_checkpoint`` returns it only
to a run with the same key, so a finished run is never continued under other code or parameters
(docs/design.md, "Caches").

``fit`` checkpoints after every epoch the weights, the optimiser, the scheduler, torch's RNG state, the
log and the best epoch's weights; a run killed and started again therefore ends at the weights of an
uninterrupted run, provided the epoch itself draws its order from seeds keyed by the epoch (both
callers do).
"""

from __future__ import annotations

import dataclasses
import io
import math
import pickle
import warnings
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import torch
from tqdm.auto import tqdm

from navlab.core.io import DataError, write_bytes


def save_torch(path: str | Path, obj: Any) -> None:
    """``torch.save`` through memory: equal objects give equal bytes, written atomically."""
    buf = io.BytesIO()
    torch.save(obj, buf)
    write_bytes(path, buf.getvalue())


def load_torch(path: str | Path, device: str | torch.device = "cpu") -> Any:
    """The object saved at ``path``; DataError (naming the file) when it cannot be read."""
    try:
        return torch.load(path, map_location=device, weights_only=False)
    except (OSError, RuntimeError, EOFError, ValueError, KeyError, zipfile.BadZipFile,
            pickle.UnpicklingError) as err:
        raise DataError(f"{path} is unreadable ({str(err).splitlines()[0] if str(err) else type(err).__name__})") \
            from None


def resume_checkpoint(path: str | Path, key: str, device: str | torch.device = "cpu",
                      warn: Callable[[str], None] = warnings.warn) -> dict[str, Any] | None:
    """The checkpoint at ``path`` if the run that wrote it had the same ``key``, else None (start over).

    Only an interrupted or finished run of exactly this key is resumed; a checkpoint of other code,
    parameters or inputs is ignored (training starts from scratch and overwrites it). A corrupt,
    empty or key-less checkpoint is discarded with a warning naming it.
    """
    path = Path(path)
    if not path.is_file():
        return None
    try:
        checkpoint = load_torch(path, device)
        if not isinstance(checkpoint, dict) or "key" not in checkpoint:
            raise DataError(f"{path} has no run key (written by older code)")
    except DataError as err:
        warn(f"{err}; discarded it, training starts over")
        path.unlink(missing_ok=True)
        return None
    return checkpoint if checkpoint["key"] == key else None


def cosine_factor(step: int, total: int, final_fraction: float = 0.0, *, pi_first: bool = False) -> float:
    """The learning rate's factor at ``step``: a cosine from 1 at step 0 to ``final_fraction`` at ``total``
    (Loshchilov and Hutter, SGDR, ICLR 2017, without restarts).

    ``pi_first`` takes the angle as (π·step)/total with ``math.cos`` (the semantic classifier's schedule),
    else as π·(step/total) with ``np.cos`` (PACER's phases): the two round differently in the last bit,
    and each reproduces the weights its stage was trained with.
    """
    if pi_first:
        cosine = math.cos(math.pi * step / total)
    else:
        cosine = np.cos(np.pi * (min(step, total) / max(total, 1)))
    return final_fraction + (1.0 - final_fraction) * 0.5 * (1.0 + cosine)


def cosine_schedule(optimiser: torch.optim.Optimizer, total_steps: int, final_fraction: float = 0.0, *,
                    pi_first: bool = False) -> torch.optim.lr_scheduler.LambdaLR:
    """Cosine decay of every group's learning rate over ``total_steps`` optimiser steps (``cosine_factor``);
    a closed form per step, so a resumed schedule (``state_dict``) gives the very rates of an unbroken one."""
    return torch.optim.lr_scheduler.LambdaLR(
        optimiser, lambda step: cosine_factor(step, total_steps, final_fraction, pi_first=pi_first))


def descend(loss: torch.Tensor, optimiser: torch.optim.Optimizer,
            scheduler: torch.optim.lr_scheduler.LRScheduler | None = None) -> None:
    """One step down ``loss``'s gradient, then the schedule's step: the order every loop here keeps."""
    optimiser.zero_grad()
    loss.backward()
    optimiser.step()
    if scheduler is not None:
        scheduler.step()


@dataclasses.dataclass(frozen=True)
class TrainingRun:
    """What ``fit`` runs: its checkpoint file and key (only a checkpoint of this key resumes), the most
    epochs, the patience (stop after this many epochs without a better one; 0: never stop early), and the
    progress bar's name (``progress`` False: none)."""

    checkpoint: Path
    key: str
    epochs: int
    patience: int = 0
    name: str = "training"
    progress: bool = True


@dataclasses.dataclass(frozen=True)
class Fitted:
    """``fit``'s result: one log row per epoch run (``epoch`` counted from 1, then what the epoch
    measured) and the row of the best epoch (None when no epoch ran)."""

    log: list[dict[str, Any]]
    best: dict[str, Any] | None

    @property
    def best_epoch(self) -> int:
        return self.best["epoch"] if self.best is not None else 0


def fit(model: torch.nn.Module, optimiser: torch.optim.Optimizer, run: TrainingRun,
        train_epoch: Callable[[int], dict[str, Any]], better: Callable[[dict, dict], bool], *,
        scheduler: torch.optim.lr_scheduler.LRScheduler | None = None, device: str | torch.device = "cpu",
        on_epoch: Callable[[list[dict]], None] | None = None) -> Fitted:
    """Train ``model`` epoch by epoch, resuming ``run.checkpoint`` when its key matches; returns the log and
    leaves the best epoch's weights in ``model``.

    ``train_epoch(epoch)`` (0-based, model in train mode) trains one epoch and returns what it measured
    (train and validation scores); ``better(row, best)`` says whether an epoch's row beats the best one so
    far (the first epoch always does). After every epoch the checkpoint is written, then ``on_epoch(log)``
    runs (the caller's log file). Stops early after ``run.patience`` epochs without a better one.
    """
    log: list[dict] = []
    best, best_weights = None, None
    checkpoint = resume_checkpoint(run.checkpoint, run.key, device)
    if checkpoint is not None:
        model.load_state_dict(checkpoint["weights"])
        optimiser.load_state_dict(checkpoint["optimiser"])
        if scheduler is not None:
            scheduler.load_state_dict(checkpoint["scheduler"])
        torch.set_rng_state(checkpoint["rng"])
        log, best, best_weights = checkpoint["log"], checkpoint["best"], checkpoint["best_weights"]
    bar = tqdm(range(len(log), run.epochs), desc=run.name, disable=not run.progress, initial=len(log),
               total=run.epochs)
    for epoch in bar:
        if run.patience and epoch - (best["epoch"] if best is not None else 0) >= run.patience:
            break  # a resumed run that had stopped stops here too
        model.train()
        row = {"epoch": epoch + 1, **train_epoch(epoch)}
        log.append(row)
        if best is None or better(row, best):
            best, best_weights = row, {k: v.detach().clone() for k, v in model.state_dict().items()}
        bar.set_postfix({k: f"{v:.4f}" for k, v in row.items() if k != "epoch"}, best=best["epoch"])
        save_torch(run.checkpoint, {"key": run.key, "weights": model.state_dict(), "optimiser": optimiser.state_dict(),
                                    "scheduler": scheduler.state_dict() if scheduler is not None else None,
                                    "rng": torch.get_rng_state(), "log": log, "best": best,
                                    "best_weights": best_weights})
        if on_epoch is not None:
            on_epoch(log)
    if best_weights is not None:
        model.load_state_dict(best_weights)
    return Fitted(log, best)
