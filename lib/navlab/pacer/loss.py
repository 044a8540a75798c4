"""Eq. 3 of PACER: per-pixel binary cross-entropy, averaged over the camera's field of view only.

Pixels outside the trapezoid field-of-view mask were never seen by the camera; their target cost is
meaningless, so they contribute neither to the loss nor to its gradient.
"""

from __future__ import annotations

import torch
from torch.nn import functional as F


def masked_bce(logits: torch.Tensor, target: torch.Tensor, fov_mask: torch.Tensor) -> torch.Tensor:
    """Mean BCE over the pixels where ``fov_mask`` is true; logits, target (costs in [0,1]), mask: (B,H,W)."""
    if logits.shape != target.shape or logits.shape != fov_mask.shape:
        raise ValueError(f"logits {tuple(logits.shape)}, target {tuple(target.shape)} and fov_mask "
                         f"{tuple(fov_mask.shape)} must have the same shape")
    mask = fov_mask.to(torch.bool)
    per_pixel = F.binary_cross_entropy_with_logits(logits, target.to(logits.dtype), reduction="none")
    inside = torch.where(mask, per_pixel, torch.zeros_like(per_pixel))
    return inside.sum() / mask.sum().clamp_min(1)
