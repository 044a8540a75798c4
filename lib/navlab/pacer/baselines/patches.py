"""Square terrain patches: what both patch-based baselines train on and how they paint a costmap.

Training patches are cut from BEV examples where the whole patch lies in the field of view; each keeps
the label under its centre. A costmap is painted by scoring a grid of overlapping patches (stride half
a patch) and spreading each score over its cells, which is why patch methods give coarser costmaps
than PACER's per-pixel decoder (Sec. VII).
"""

from __future__ import annotations

import dataclasses
import hashlib
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import torch
from torch.nn import functional as F
from torch.utils.data import Dataset

from navlab.core.fingerprint import code_fingerprint
from navlab.core.io import sha256_json
from navlab.core.seeding import rng


def sample_patches(datasets: Sequence[Dataset], count: int, size: int, seed: int, *keys) -> tuple[torch.Tensor, torch.Tensor]:
    """``count`` patches (N,3,size,size) inside the field of view and their centre labels (N,)."""
    gen = rng(seed, "pacer.patches", *keys)
    sizes = [len(ds) for ds in datasets]
    if not sizes or min(sizes) == 0:
        raise ValueError(f"patch sampling needs non-empty datasets (sizes {sizes})")
    patches, labels = [], []
    per_item = 8
    while len(patches) < count:
        d = int(gen.integers(len(datasets)))
        item = datasets[d][int(gen.integers(sizes[d]))]
        image = torch.as_tensor(np.asarray(item["image"]), dtype=torch.float32)
        fov = np.asarray(item["fov_mask"], dtype=bool)
        lab = np.asarray(item["labels"])
        h, w = fov.shape
        if h < size or w < size:
            raise ValueError(f"patch size {size} exceeds the BEV image {h}x{w}; lower pacer.baselines.patch_size")
        # top-left corners whose whole patch is in view: erode the mask by the patch
        inside = F.max_pool2d(torch.as_tensor(~fov, dtype=torch.float32)[None, None], size, stride=1)[0, 0] == 0
        rows, cols = np.nonzero(inside.numpy())
        if rows.size == 0:
            continue
        for k in gen.integers(rows.size, size=per_item):
            r, c = int(rows[k]), int(cols[k])
            patches.append(image[:, r:r + size, c:c + size])
            labels.append(int(lab[r + size // 2, c + size // 2]))
    return torch.stack(patches[:count]), torch.as_tensor(labels[:count])


def baseline_key(module: str, cfg: Any, *, patch_size: int, seed: int, device: str,
                 patches: Sequence[torch.Tensor]) -> str:
    """What a patch baseline's checkpoint must match to be resumed (``core.training.fit``): the code of
    ``module`` and what it imports, the baseline's parameters, patch size, seed, device and torch thread count
    (each sums a convolution's terms in its own order), and the bytes of the patches it trains on (they stand
    for the photographs and the renderer that made them)."""
    digest = hashlib.blake2b(digest_size=16)
    for tensor in patches:
        digest.update(tensor.detach().cpu().contiguous().numpy().tobytes())
    return sha256_json({"code": code_fingerprint(module), "cfg": dataclasses.asdict(cfg), "patch_size": patch_size,
                        "seed": seed, "device": str(device), "threads": torch.get_num_threads(),
                        "patches": digest.hexdigest()})


def dense_scores(image: torch.Tensor, size: int, score: Callable[[torch.Tensor], torch.Tensor]) -> torch.Tensor:
    """Per-pixel scores of every size×size patch at stride size/2, averaged over the patches covering a pixel.

    ``score`` maps patches (N,3,s,s) to (N,) or (N,K); the result is (H,W) or (K,H,W).
    """
    _, h, w = image.shape
    stride = max(1, size // 2)
    cols = F.unfold(image[None], size, stride=stride)[0]  # (3·size², N)
    patches = cols.T.reshape(-1, image.shape[0], size, size)
    values = score(patches).to(image.dtype)
    flat = values.ndim == 1
    values = values[:, None] if flat else values  # (N, K)
    k, n = values.shape[1], values.shape[0]
    spread = values.T[:, None, :].expand(k, size * size, n).reshape(1, k * size * size, n)
    total = F.fold(spread, (h, w), size, stride=stride)[0]
    hits = F.fold(torch.ones(1, size * size, n, dtype=image.dtype), (h, w), size, stride=stride)[0, 0]
    covered = total / hits.clamp_min(1)
    # cells the stride grid misses at the bottom/right edge take the nearest covered row/column
    missing = hits == 0
    if missing.any():
        r_max = int((~missing).any(dim=1).nonzero().max())
        c_max = int((~missing).any(dim=0).nonzero().max())
        covered[:, r_max + 1:, :] = covered[:, r_max:r_max + 1, :]
        covered[:, :, c_max + 1:] = covered[:, :, c_max:c_max + 1]
    return covered[0] if flat else covered


def context_pairs(context: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Split a (3n,2h,w) context (Sec. IV-A) into its preferred (top) and less-preferred patches, each (n,3,h,w)."""
    c, two_h, w = context.shape
    if c % 3 or two_h % 2:
        raise ValueError(f"context of shape {tuple(context.shape)}: expected (3n, 2h, w), pairs stacked vertically")
    pairs = context.float().reshape(c // 3, 3, two_h, w)
    return pairs[:, :, : two_h // 2], pairs[:, :, two_h // 2:]


def patch_cnn(channels: Sequence[int], out_dim: int) -> torch.nn.Sequential:
    """Conv-BN-ReLU-pool stages, global average, linear head: the small patch network of both baselines."""
    layers, c = [], 3
    for width in channels:
        layers += [torch.nn.Conv2d(c, width, 3, padding=1), torch.nn.BatchNorm2d(width), torch.nn.ReLU(inplace=True),
                   torch.nn.MaxPool2d(2)]
        c = width
    layers += [torch.nn.AdaptiveAvgPool2d(1), torch.nn.Flatten(), torch.nn.Linear(c, out_dim)]
    return torch.nn.Sequential(*layers)
