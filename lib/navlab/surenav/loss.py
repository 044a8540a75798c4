"""SuReNav's training loss (Sec. IV-D): false-relaxation loss Eq. (12) with per-sample weights Eq. (13)-(14).

v_rlx is the planner's relaxed-region mask (the differentiable A*'s closed set intersected with R_soft),
v*_rlx the demonstration's. False relaxations are penalised as

    L_rlx(v, v*) = (w_fp v^T (1 - v*) + w_fn (1 - v)^T v*) / (1 + ||v*||_1)              (12)

and a mini-batch averages them with weights w_i = min(1, L_rlx(v_i, v*_i; w_fp', w_fn')^gamma)
(13)-(14), computed with their own weights (the paper: w_fp' = w_fn' = 0.5) and held constant in the
gradient — a weight that scales a sample's loss, not a second objective: hard samples (large loss)
keep weight 1, nearly-solved ones fade out.
"""

from __future__ import annotations

import torch
from torch import Tensor

from navlab.core.params.surenav_model import TrainParams


def relaxation_loss(v: Tensor, target: Tensor, w_fp: float, w_fn: float) -> Tensor:
    """Eq. (12) per sample: ``v`` and ``target`` are (B, N) masks (0/1, ``v`` differentiable)."""
    if v.shape != target.shape:
        raise ValueError(f"relaxed mask {tuple(v.shape)} and target {tuple(target.shape)} must have one shape (B, N)")
    target = target.to(v.dtype)
    false_pos = (v * (1 - target)).sum(-1)
    false_neg = ((1 - v) * target).sum(-1)
    return (w_fp * false_pos + w_fn * false_neg) / (1 + target.sum(-1))


def sample_weights(v: Tensor, target: Tensor, gamma: float, w_fp: float = 0.5, w_fn: float = 0.5) -> Tensor:
    """Eq. (14): w_i = min(1, L_rlx(v_i, v*_i)^gamma) with the weight's own (w_fp, w_fn); no gradient."""
    with torch.no_grad():
        return torch.clamp(relaxation_loss(v.detach(), target, w_fp, w_fn) ** gamma, max=1.0)


def batch_loss(v: Tensor, target: Tensor, train: TrainParams) -> Tensor:
    """Eq. (13): the mean over the batch of w_i L_rlx(v_i, v*_i)."""
    per_sample = relaxation_loss(v, target, train.w_fp, train.w_fn)
    weights = sample_weights(v, target, train.gamma, train.weight_w_fp, train.weight_w_fn)
    return (weights * per_sample).mean()
