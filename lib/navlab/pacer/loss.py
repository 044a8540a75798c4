"""Eq. 3 of PACER: per-pixel binary cross-entropy, averaged over the camera's field of view only; and the
texture matcher's matching loss (ours, issue 24).

``entropy_floor`` is the loss a perfect model would reach (the targets are soft costs in [0, 1]),
the yardstick a final validation loss is read against.

Pixels outside the trapezoid field-of-view mask were never seen by the camera; their target cost is
meaningless, so they contribute neither to the loss nor to its gradient.

The matching loss teaches the matcher (``model.TextureMatcher``) to *recognise*: Eq. 3 alone trains it only
through the costs, and a full-resolution tower trained that way never learned to tell the maps' terrains
apart (benchmarks/README.md, "where the matcher loses the maps' terrains"). Each pixel's softmax over the
context's 2n patches (at the attention's own temperature) should put its mass on the patches of the
pixel's own terrain, which every training item knows: a per-pixel prototypical loss (Snell et al., NeurIPS
2017) with the context patches as prototypes.
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


@torch.no_grad()
def entropy_floor(datasets) -> float:
    """The lowest mean masked BCE any model can reach on ``datasets``: the mean binary entropy of the
    soft targets in view, H(y) = -y log y - (1-y) log(1-y), since BCE(p, y) = H(y) + KL(y || p)."""
    total, pixels = 0.0, 0
    for ds in datasets:
        for i in range(len(ds)):
            item = ds[i]
            y = torch.as_tensor(item["costmap"], dtype=torch.float64).clamp(1e-12, 1 - 1e-12)
            mask = torch.as_tensor(item["fov_mask"], dtype=torch.bool)
            entropy = -(y * y.log() + (1 - y) * (1 - y).log())
            total += float(entropy[mask].sum())
            pixels += int(mask.sum())
    return total / pixels if pixels else float("nan")


def matching_loss(cosines: torch.Tensor, temperature: torch.Tensor, labels: torch.Tensor,
                  patch_terrains: torch.Tensor) -> torch.Tensor:
    """Mean over pixels whose terrain the context shows of -log(softmax mass on that terrain's patches).

    cosines (B, 2n, h, w) at any stride (upsampled bilinearly to the labels' size), labels (B, H, W) terrain ids
    (negative: not in view), patch_terrains (B, 2n) the terrain of each patch in the cosines' order; 0 where no
    pixel of the batch shows a terrain of its context (nothing to match)."""
    if cosines.shape[-2:] != labels.shape[-2:]:
        cosines = F.interpolate(cosines, size=labels.shape[-2:], mode="bilinear", align_corners=False)
    own = patch_terrains[:, :, None, None] == labels[:, None]
    shown = own.any(dim=1)
    if not bool(shown.any()):
        return cosines.sum() * 0.0
    log_p = torch.log_softmax(cosines * temperature, dim=1).movedim(1, -1)[shown]  # (pixels shown, 2n)
    return -torch.logsumexp(log_p.masked_fill(~own.movedim(1, -1)[shown], -torch.inf), dim=1).mean()


def contrast_loss(logits: torch.Tensor, target: torch.Tensor, labels: torch.Tensor,
                  margin: float = 1.0) -> torch.Tensor:
    """Mean over in-view pixels p (terrain a) and the other terrains b their item orders against a of
    relu(margin |t_b - t_a| - sign(t_b - t_a) (ĉ_b - c_p)).

    c_p = sigmoid(logit) is the pixel's predicted cost, ĉ_b terrain b's mean predicted cost over its pixels in
    view, t a terrain's target cost (issue 24, item 4: full-contrast cost levels). Eq. 3 alone is minimised by
    hedged costs wherever recognition is uncertain, which compresses the rest:low cost ratio the planner sees;
    this hinge asks every pixel to sit at least ``margin`` x the target difference away from each terrain its
    item orders against its own, on the right side. Per pixel rather than per terrain mean: a path follows
    pixels, and a terrain whose mean is right but whose pixels spread across the other's level still hands
    the planner cheap cells in costly terrain (on the evaluation maps, replacing the per-mean hinge model's
    pixels by their terrain's mean closed +0.10 / 0 / +0.15 / 0 more of the gap on the four sets). The hinge
    is flat (no push either way) for a pair whose order the image and context cannot tell, whose two signs
    cancel. logits, target (B, H, W), labels (B, H, W) terrain ids, negative out of view; 0 with zero
    gradient when no item orders two terrains."""
    view = labels >= 0
    if not bool(view.any()):
        return logits.sum() * 0.0
    b, n = logits.shape[0], int(labels.max()) + 1
    item = torch.arange(b, device=labels.device)[:, None, None].expand_as(labels)[view]
    # each item's terrains in view as slots 0..k-1 (k: the most any item shows), not every terrain id
    cells, slot_of_pixel = torch.unique(item * n + labels[view], return_inverse=True)
    cell_item = cells // n
    slot = torch.arange(len(cells), device=cells.device) - torch.searchsorted(cells, cell_item * n)
    k = int(slot.max()) + 1
    flat = cell_item * k + slot  # (cells,) index into (B, k)
    pixel_slot = flat[slot_of_pixel]
    cost = torch.sigmoid(logits)[view]
    count = torch.zeros(b * k, dtype=cost.dtype, device=cost.device).index_add(0, pixel_slot, torch.ones_like(cost))
    predicted = (torch.zeros_like(count).index_add(0, pixel_slot, cost) / count.clamp_min(1)).reshape(b, k)
    wanted = torch.zeros_like(count).index_add(0, pixel_slot, target[view].to(cost.dtype))
    wanted = (wanted / count.clamp_min(1)).reshape(b, k)
    present = (count > 0).reshape(b, k)
    gap = wanted[item] - wanted.reshape(-1)[pixel_slot][:, None]  # (pixels, k): t_b - t_a
    ordered = present[item] & (gap.abs() > 1e-6)
    if not bool(ordered.any()):
        return logits.sum() * 0.0
    apart = torch.sign(gap) * (predicted[item] - cost[:, None])
    return torch.relu(margin * gap.abs() - apart)[ordered].mean()
