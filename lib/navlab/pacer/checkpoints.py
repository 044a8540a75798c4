"""Trained PACER networks on disk: the weights beside what rebuilds the architecture, written atomically.

One format for the PACER phases and both baselines, so every loader names the DVC stage that builds
a missing file in the same way; ``read_summary`` reads the training summary written beside them.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import torch
from torch import nn

from navlab.core.io import DataError, atomic_path


def save_network(path: str | Path, architecture: dict[str, Any], model: nn.Module) -> None:
    """``architecture`` holds what ``load_network``'s ``build`` needs to recreate ``model``."""
    with atomic_path(path) as tmp:
        torch.save({**architecture, "weights": model.state_dict()}, tmp)


def load_network(path: str | Path, build: Callable[[dict[str, Any]], nn.Module], stage: str,
                 device: str | torch.device = "cpu") -> nn.Module:
    """The network saved at ``path``, rebuilt by ``build(saved)``, in eval mode on ``device``."""
    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path} is missing; build it with `python -m navlab artifacts build --only {stage}` "
                        "(or `dvc repro`)")
    saved = torch.load(path, map_location=device, weights_only=False)
    model = build(saved).to(device)
    model.load_state_dict(saved["weights"])
    return model.eval()


def read_summary(folder: str | Path) -> dict[str, Any]:
    """A trained network's ``summary.json`` (phases: best epoch, its validation loss, the entropy floor;
    classifier: best epoch and held-out accuracy), written beside it by its DVC stage."""
    path = Path(folder) / "summary.json"
    if not path.is_file():
        raise DataError(f"{path} is missing; build it with `python -m navlab artifacts build --only "
                        f"pacer_{Path(folder).name}` (or `dvc repro`)")
    return json.loads(path.read_text())
