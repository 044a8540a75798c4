"""Semantics-based costing: a terrain patch classifier plus a user's label → cost table.

The paradigm PACER compares against (Sec. I; e.g. RELLIS-3D, Jiang et al., ICRA 2021; GA-Nav, Guan et
al., RA-L 2022): classify every patch into one of the L *seen* terrain labels, then look its cost up in
a table written from the operator's ordering, cost (l−1)/(L−1) for the label at rank l. A preference
can only name labels the classifier knows, so over unseen terrain this baseline has no way to take the
operator's preference at all (Table II omits it for that reason).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import torch
from torch.nn import functional as F
from torch.utils.data import Dataset

from navlab.core.params.pacer import PacerClassifierParams
from navlab.core.seeding import torch_generator
from navlab.core.training import TrainingRun, cosine_schedule, descend, fit
from navlab.pacer.baselines.patches import baseline_key, dense_scores, patch_cnn, sample_patches
from navlab.pacer.checkpoints import load_network, save_network


class SemanticClassifier(torch.nn.Module):
    """Patch → one of the seen labels; ``labels[k]`` is the terrain label id of output k."""

    def __init__(self, labels: Sequence[int], channels: Sequence[int], patch_size: int):
        super().__init__()
        self.labels = tuple(int(v) for v in labels)
        self.patch_size = patch_size
        self.channels = tuple(channels)
        self.net = patch_cnn(channels, len(self.labels))

    def forward(self, patches: torch.Tensor) -> torch.Tensor:
        return self.net(patches)

    @torch.no_grad()
    def label_map(self, image: torch.Tensor) -> torch.Tensor:
        """Dense (H,W) predicted terrain label ids (majority of the overlapping patches' votes)."""
        self.eval()
        image = torch.as_tensor(image, dtype=torch.float32)
        votes = dense_scores(image, self.patch_size, lambda p: F.softmax(self(p), dim=1))
        return torch.as_tensor(self.labels)[votes.argmax(0)]

    def costmap(self, image: torch.Tensor, label_cost: Mapping[int, float]) -> torch.Tensor:
        """Costs in [0,1] from the label → cost table; every seen label needs a cost."""
        missing = [lab for lab in self.labels if lab not in label_cost]
        if missing:
            raise ValueError(f"label_cost lacks seen labels {missing}: a classifier can only cost labels it "
                             f"knows, and needs a cost for each of {list(self.labels)}")
        table = torch.tensor([float(label_cost[lab]) for lab in self.labels])
        lookup = {lab: i for i, lab in enumerate(self.labels)}
        index = torch.tensor([lookup[int(v)] for v in self.label_map(image).flatten()]).reshape(image.shape[-2:])
        return table[index]


def train_classifier(datasets: Sequence[Dataset], cfg: PacerClassifierParams, patch_size: int, seed: int,
                     checkpoint: str | Path, device: str = "cpu", progress: bool = True,
                     val_datasets: Sequence[Dataset] = ()) -> tuple[SemanticClassifier, dict]:
    """Fit the patch classifier on centre-labelled patches of the seen-terrain datasets (cross-entropy).

    Every epoch draws ``patches_per_epoch`` fresh patches; the learning rate decays by a cosine over the
    epochs. With ``val_datasets`` the weights of the epoch with the best held-out patch accuracy are
    kept (the classifier is a baseline of its paradigm only if it is trained as well as it can be); without,
    the last epoch's. Epochs run through ``core.training.fit``: ``checkpoint`` is written after every epoch
    and a killed run resumes from it to the weights of an uninterrupted one (each epoch shuffles with a
    generator of its own). The classes are the labels of the first epoch's and the validation patches (a
    label first seen later is skipped). Returns (model, {"best_epoch", "val_accuracy", "epochs"}).
    """
    torch.manual_seed(seed)
    val = sample_patches(val_datasets, cfg.val_patches, patch_size, seed, "classifier", "val") if val_datasets else None
    first = sample_patches(datasets, cfg.patches_per_epoch, patch_size, seed, "classifier", 0)
    known = sorted(set(first[1].tolist()) | (set(val[1].tolist()) if val is not None else set()))
    lookup = {lab: k for k, lab in enumerate(known)}
    model = SemanticClassifier(known, cfg.channels, patch_size).to(device)
    optimiser = torch.optim.Adam(model.parameters(), lr=cfg.lr)
    schedule = cosine_schedule(optimiser, cfg.epochs * -(-cfg.patches_per_epoch // cfg.batch_size), pi_first=True)

    def train_epoch(epoch: int) -> dict[str, float]:
        x, labels = first if epoch == 0 else sample_patches(datasets, cfg.patches_per_epoch, patch_size, seed,
                                                             "classifier", epoch)
        y = torch.as_tensor([lookup.get(int(v), -100) for v in labels])
        order = torch.randperm(len(x), generator=torch_generator(seed, "pacer.classifier.batches", epoch))
        losses = []
        for start in range(0, len(x), cfg.batch_size):
            idx = order[start:start + cfg.batch_size]
            loss = F.cross_entropy(model(x[idx].to(device)), y[idx].to(device), ignore_index=-100)
            descend(loss, optimiser, schedule)
            losses.append(loss.item())
        accuracy = patch_accuracy(model, *val, device=device) if val is not None else float("nan")
        return {"train_loss": float(np.mean(losses)), "val_accuracy": accuracy}

    key = baseline_key(__name__, cfg, patch_size=patch_size, seed=seed, device=device,
                       patches=[first[0], *(val if val is not None else ())])
    fitted = fit(model, optimiser, TrainingRun(Path(checkpoint), key, cfg.epochs, name="classifier", progress=progress),
                 train_epoch, lambda row, best: val is None or row["val_accuracy"] > best["val_accuracy"],
                 scheduler=schedule, device=device)
    accuracy = fitted.best["val_accuracy"] if val is not None and fitted.best is not None else None
    return model.eval(), {"best_epoch": fitted.best_epoch, "val_accuracy": accuracy, "epochs": cfg.epochs}


@torch.no_grad()
def patch_accuracy(model: SemanticClassifier, patches: torch.Tensor, labels: torch.Tensor, device: str = "cpu") -> float:
    """Fraction of ``patches`` whose centre label the classifier names."""
    model.eval()
    predicted = torch.cat([model(patches[k:k + 512].to(device)).argmax(1).cpu() for k in range(0, len(patches), 512)])
    return float((torch.as_tensor(model.labels)[predicted] == labels).float().mean())


def save_classifier(model: SemanticClassifier, path: str | Path) -> None:
    save_network(path, {"labels": model.labels, "channels": model.channels, "patch_size": model.patch_size}, model)


def load_classifier(path: str | Path, device: str = "cpu") -> SemanticClassifier:
    return load_network(path, lambda saved: SemanticClassifier(saved["labels"], saved["channels"], saved["patch_size"]),
                        "pacer_classifier", device)
