"""Trained PACER networks on disk: byte-deterministic and atomic (``core.training.save_torch``).

One format for the PACER phases and both baselines, so every loader names the DVC stage that builds
a missing or unreadable file in the same way. ``read_summary`` reads the training summary written beside them.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import torch
from torch import nn

from navlab.core.io import DataError
from navlab.core.training import load_torch, save_torch


def save_network(path: str | Path, architecture: dict[str, Any], model: nn.Module) -> None:
    """``architecture`` holds what ``load_network``'s ``build`` needs to recreate ``model``."""
    save_torch(path, {**architecture, "weights": model.state_dict()})


def load_network(path: str | Path, build: Callable[[dict[str, Any]], nn.Module], stage: str,
                 device: str | torch.device = "cpu") -> nn.Module:
    """The network saved at ``path``, rebuilt by ``build(saved)``, in eval mode on ``device``.

    A missing, truncated or mismatched file stops with one line naming it and the command that rebuilds it.
    """
    path = Path(path)
    fix = f"rebuild it with `python -m navlab artifacts build --only {stage}` (or `dvc repro {stage}`)"
    if not path.is_file():
        raise DataError(f"{path} is missing; {fix}")
    try:
        saved = load_torch(path, device)
    except DataError as err:
        raise DataError(f"{err}; {fix}") from None
    try:
        model = build(saved).to(device)
        model.load_state_dict(saved["weights"])
    except (KeyError, TypeError, RuntimeError, ValueError) as err:
        raise DataError(f"{path} does not hold a network this code can load ({type(err).__name__}: "
                        f"{str(err).splitlines()[0][:200]}); {fix}") from None
    return model.eval()


def read_summary(folder: str | Path) -> dict[str, Any]:
    """A trained network's ``summary.json`` (phases: best epoch, its validation loss, the entropy floor;
    classifier: best epoch and held-out accuracy), written beside it by its DVC stage, with the training cost
    (``train_seconds``, ``peak_rss_mib``, ``threads``, ``workers``) from ``training_cost.json`` where the folder
    was trained on this machine (that file is no part of the folder's DVC hash, so a checkout has none)."""
    path = Path(folder) / "summary.json"
    if not path.is_file():
        raise DataError(f"{path} is missing; build it with `python -m navlab artifacts build --only "
                        f"pacer_{Path(folder).name}` (or `dvc repro`)")
    summary = json.loads(path.read_text())
    cost = Path(folder) / "training_cost.json"
    if cost.is_file():
        summary |= {k: v for k, v in json.loads(cost.read_text()).items() if k not in ("key", "epoch_seconds")}
    return summary
