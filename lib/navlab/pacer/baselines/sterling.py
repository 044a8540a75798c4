"""STERLING-style terrain costing: self-supervised patch representations plus a fitted utility.

Karnan et al., "STERLING: Self-Supervised Terrain Representation Learning from Unconstrained Robot
Experience", CoRL 2023, with the VICReg objective of Bardes, Ponce and LeCun, "VICReg:
Variance-Invariance-Covariance Regularization for Self-Supervised Learning", ICLR 2022.

1. A small patch encoder is trained without labels: two randomly augmented views of the same patch
   (flips, quarter turns, brightness/contrast jitter, a random crop resized back, noise) must map to
   nearby embeddings (invariance), every embedding dimension must keep a spread of at least 1 across
   the batch (variance), and dimensions must be decorrelated (covariance).
2. At deployment the operator's preference context — n pairs "top patch ≻ bottom patch" — fits a
   linear utility on the frozen embeddings (a logistic ranking loss over the pairs and their sub-crops);
   the cost of a BEV pixel is the sigmoid of the utility of the patches that cover it. Every new
   preference means fitting the utility again, the limitation PACER removes (Sec. I).

STERLING proper pairs views of one terrain seen from different robot poses; our BEV renders have no
robot trajectory, so augmentation stands in for the viewpoint change.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import torch
from torch.nn import functional as F
from torch.utils.data import Dataset

from navlab.core.params.pacer import PacerSterlingParams
from navlab.core.seeding import torch_generator
from navlab.core.training import TrainingRun, descend, fit
from navlab.pacer.baselines.patches import (
    baseline_key,
    context_pairs,
    dense_scores,
    patch_cnn,
    sample_patches,
)
from navlab.pacer.checkpoints import load_network, save_network


def augment(patches: torch.Tensor, gen: torch.Generator) -> torch.Tensor:
    """One random view of each patch (N,3,s,s); every draw comes from ``gen``."""
    n, _, s, _ = patches.shape
    x = patches
    flip = torch.rand(n, generator=gen) < 0.5
    x = torch.where(flip[:, None, None, None], x.flip(-1), x)
    turns = torch.randint(0, 4, (n,), generator=gen)
    x = torch.stack([torch.rot90(v, int(k), dims=(-2, -1)) for v, k in zip(x, turns)])
    # random crop of 60-100 % of the side, resized back (a change of scale and position)
    side = (s * (0.6 + 0.4 * torch.rand(n, generator=gen))).long().clamp(2, s)
    offset = ((s - side) * torch.rand(2, n, generator=gen)).long()
    x = torch.stack([F.interpolate(v[None, :, r:r + k, c:c + k], size=(s, s), mode="bilinear",
                                   align_corners=False)[0]
                     for v, k, r, c in zip(x, side, offset[0], offset[1])])
    gain = 0.7 + 0.6 * torch.rand(n, 1, 1, 1, generator=gen)
    bias = 0.2 * (torch.rand(n, 1, 1, 1, generator=gen) - 0.5)
    noise = 0.02 * torch.randn(x.shape, generator=gen)
    return ((x - 0.5) * gain + 0.5 + bias + noise).clamp(0, 1)


def vicreg_loss(z1: torch.Tensor, z2: torch.Tensor, weights: Sequence[float]) -> torch.Tensor:
    """VICReg: λ·invariance + μ·variance + ν·covariance of two batches of embeddings (N,D)."""
    lam, mu, nu = weights
    invariance = F.mse_loss(z1, z2)
    variance, covariance = 0.0, 0.0
    for z in (z1, z2):
        z = z - z.mean(dim=0)
        std = torch.sqrt(z.var(dim=0) + 1e-4)
        variance = variance + F.relu(1 - std).mean()
        cov = (z.T @ z) / (len(z) - 1)
        off = cov - torch.diag(torch.diag(cov))
        covariance = covariance + off.pow(2).sum() / z.shape[1]
    return lam * invariance + mu * variance + nu * covariance


class SterlingEncoder(torch.nn.Module):
    """Patch (N,3,s,s) → embedding (N,D), with a utility head fitted per preference context."""

    def __init__(self, channels: Sequence[int], embed_dim: int, patch_size: int):
        super().__init__()
        self.channels, self.embed_dim, self.patch_size = tuple(channels), embed_dim, patch_size
        self.net = patch_cnn(channels, embed_dim)

    def forward(self, patches: torch.Tensor) -> torch.Tensor:
        return self.net(patches)

    def fit_utility(self, context: torch.Tensor, steps: int, lr: float = 0.05) -> torch.nn.Linear:
        """A linear utility on frozen embeddings ranking each pair's top patch cheaper than its bottom one."""
        self.eval()
        better, worse = self._context_views(torch.as_tensor(context, dtype=torch.float32))
        with torch.no_grad():
            zb, zw = self(better), self(worse)
            scale = torch.cat([zb, zw]).std(dim=0).clamp_min(1e-3)
        utility = torch.nn.Linear(self.embed_dim, 1)
        torch.nn.init.zeros_(utility.weight)
        torch.nn.init.zeros_(utility.bias)
        optimiser = torch.optim.Adam(utility.parameters(), lr=lr)
        for _ in range(steps):
            margin = utility(zw / scale) - utility(zb / scale)  # cost(worse) − cost(better), want > 0
            descend(F.softplus(-margin).mean() + 1e-3 * utility.weight.pow(2).sum(), optimiser)
        with torch.no_grad():
            utility.weight /= scale
        return utility

    def _context_views(self, context: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Each pair's patches whole and as four 3/4-size corner crops, resized to the encoder's patch size."""
        better, worse = context_pairs(context)
        h, w = better.shape[-2:]
        kh, kw = max(1, 3 * h // 4), max(1, 3 * w // 4)
        boxes = [(0, 0, h, w)] + [(r, c, kh, kw) for r in (0, h - kh) for c in (0, w - kw)]

        def views(x: torch.Tensor) -> torch.Tensor:
            return torch.cat([F.interpolate(x[:, :, r:r + a, c:c + b], size=(self.patch_size,) * 2,
                                            mode="bilinear", align_corners=False) for r, c, a, b in boxes])

        return views(better), views(worse)

    @torch.no_grad()
    def costmap(self, image: torch.Tensor, utility: torch.nn.Linear) -> torch.Tensor:
        """Per-pixel costs in [0,1]: sigmoid of the utility of the patches covering each pixel."""
        self.eval()
        image = torch.as_tensor(image, dtype=torch.float32)
        return torch.sigmoid(dense_scores(image, self.patch_size, lambda p: utility(self(p))[:, 0]))


def train_sterling(datasets: Sequence[Dataset], cfg: PacerSterlingParams, patch_size: int, seed: int,
                   checkpoint: str | Path, device: str = "cpu", progress: bool = True) -> SterlingEncoder:
    """Self-supervised VICReg training on unlabelled patches of the seen-terrain datasets, epoch by epoch
    through ``core.training.fit``: ``checkpoint`` is written after every epoch, and a killed run resumes from
    it to the weights of an uninterrupted one (each epoch draws its views from a generator of its own). The
    last epoch's weights are kept: VICReg has no held-out score to select an epoch on."""
    patches, _ = sample_patches(datasets, cfg.patches_per_epoch * cfg.epochs, patch_size, seed, "sterling")
    torch.manual_seed(seed)
    model = SterlingEncoder(cfg.channels, cfg.embed_dim, patch_size).to(device)
    optimiser = torch.optim.Adam(model.parameters(), lr=cfg.lr)

    def train_epoch(epoch: int) -> dict[str, float]:
        gen = torch_generator(seed, "pacer.sterling.views", epoch)
        x = patches[epoch * cfg.patches_per_epoch:(epoch + 1) * cfg.patches_per_epoch]
        order = torch.randperm(len(x), generator=gen)
        losses = []
        for start in range(0, len(x) - 1, cfg.batch_size):
            batch = x[order[start:start + cfg.batch_size]]
            if len(batch) < 2:
                continue
            v1, v2 = augment(batch, gen).to(device), augment(batch, gen).to(device)
            loss = vicreg_loss(model(v1), model(v2), cfg.vicreg_weights)
            descend(loss, optimiser)
            losses.append(loss.item())
        return {"train_loss": float(np.mean(losses)) if losses else float("nan")}

    key = baseline_key(__name__, cfg, patch_size=patch_size, seed=seed, device=device, patches=[patches])
    fit(model, optimiser, TrainingRun(Path(checkpoint), key, cfg.epochs, name="STERLING", progress=progress),
        train_epoch, lambda row, best: True, device=device)
    return model.eval()


def save_sterling(model: SterlingEncoder, path: str | Path) -> None:
    save_network(path, {"channels": model.channels, "embed_dim": model.embed_dim, "patch_size": model.patch_size},
                 model)


def load_sterling(path: str | Path, device: str = "cpu") -> SterlingEncoder:
    return load_network(path, lambda saved: SterlingEncoder(saved["channels"], saved["embed_dim"], saved["patch_size"]),
                        "pacer_sterling", device)
