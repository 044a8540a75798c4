"""Trained PACER networks and training checkpoints on disk: byte-deterministic, atomic, keyed on the code.

One format for the PACER phases and both baselines, so every loader names the DVC stage that builds
a missing or unreadable file in the same way. Files are serialised in memory and then written
atomically, so the temporary file's name never ends up inside the archive (torch.save names the
archive after the file it writes) and re-saving the same weights gives the same bytes.

A checkpoint carries the ``key`` of the run that wrote it (code fingerprint + parameters + inputs,
see ``navlab.core.fingerprint``); ``resume_checkpoint`` returns it only to a run with the same key, so
a finished run is never continued under other code or parameters (DESIGN.md, "Caches"). ``read_summary`` reads the training summary written beside them.
"""

from __future__ import annotations

import io
import json
import pickle
import warnings
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import torch
from torch import nn

from navlab.core.io import DataError, write_bytes


def save_torch(path: str | Path, obj: Any) -> None:
    """``torch.save`` through memory: equal objects give equal bytes, written atomically."""
    buf = io.BytesIO()
    torch.save(obj, buf)
    write_bytes(path, buf.getvalue())


def _load_torch(path: Path, device) -> Any:
    """The object saved at ``path``; DataError (naming the file) when it cannot be read."""
    try:
        return torch.load(path, map_location=device, weights_only=False)
    except (OSError, RuntimeError, EOFError, ValueError, KeyError, zipfile.BadZipFile,
            pickle.UnpicklingError) as err:
        raise DataError(f"{path} is unreadable ({str(err).splitlines()[0] if str(err) else type(err).__name__})") \
            from None


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
        saved = _load_torch(path, device)
    except DataError as err:
        raise DataError(f"{err}; {fix}") from None
    try:
        model = build(saved).to(device)
        model.load_state_dict(saved["weights"])
    except (KeyError, TypeError, RuntimeError, ValueError) as err:
        raise DataError(f"{path} does not hold a network this code can load ({type(err).__name__}: "
                        f"{str(err).splitlines()[0][:200]}); {fix}") from None
    return model.eval()


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
        checkpoint = _load_torch(path, device)
        if not isinstance(checkpoint, dict) or "key" not in checkpoint:
            raise DataError(f"{path} has no run key (written by older code)")
    except DataError as err:
        warn(f"{err}; discarded it, training starts over")
        path.unlink(missing_ok=True)
        return None
    return checkpoint if checkpoint["key"] == key else None


def read_summary(folder: str | Path) -> dict[str, Any]:
    """A trained network's ``summary.json`` (phases: best epoch, its validation loss, the entropy floor;
    classifier: best epoch and held-out accuracy), written beside it by its DVC stage."""
    path = Path(folder) / "summary.json"
    if not path.is_file():
        raise DataError(f"{path} is missing; build it with `python -m navlab artifacts build --only "
                        f"pacer_{Path(folder).name}` (or `dvc repro`)")
    return json.loads(path.read_text())
