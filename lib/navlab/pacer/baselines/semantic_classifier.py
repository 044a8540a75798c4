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

import torch
from torch.nn import functional as F
from torch.utils.data import Dataset
from tqdm.auto import tqdm

from navlab.core.params.pacer import PacerClassifierParams
from navlab.core.seeding import torch_generator
from navlab.pacer.baselines.patches import dense_scores, patch_cnn, sample_patches
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
                     device: str = "cpu", progress: bool = True) -> SemanticClassifier:
    """Fit the patch classifier on centre-labelled patches of the seen-terrain datasets (cross-entropy)."""
    patches, labels = sample_patches(datasets, cfg.patches_per_epoch * cfg.epochs, patch_size, seed, "classifier")
    known = sorted(set(labels.tolist()))
    target = torch.as_tensor([known.index(int(v)) for v in labels])
    torch.manual_seed(seed)
    model = SemanticClassifier(known, cfg.channels, patch_size).to(device)
    optimiser = torch.optim.Adam(model.parameters(), lr=cfg.lr)
    gen = torch_generator(seed, "pacer.classifier.batches")
    model.train()
    for epoch in tqdm(range(cfg.epochs), desc="classifier", disable=not progress):
        chunk = slice(epoch * cfg.patches_per_epoch, (epoch + 1) * cfg.patches_per_epoch)
        x, y = patches[chunk], target[chunk]
        order = torch.randperm(len(x), generator=gen)
        for start in range(0, len(x), cfg.batch_size):
            idx = order[start:start + cfg.batch_size]
            loss = F.cross_entropy(model(x[idx].to(device)), y[idx].to(device))
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
    return model.eval()


def save_classifier(model: SemanticClassifier, path: str | Path) -> None:
    save_network(path, {"labels": model.labels, "channels": model.channels, "patch_size": model.patch_size}, model)


def load_classifier(path: str | Path, device: str = "cpu") -> SemanticClassifier:
    return load_network(path, lambda saved: SemanticClassifier(saved["labels"], saved["channels"], saved["patch_size"]),
                        "pacer_classifier", device)
