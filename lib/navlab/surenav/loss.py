"""SuReNav's training loss (Sec. IV-D): false-relaxation loss Eq. (12) with per-sample weights Eq. (13)-(14).

v_rlx is the planner's relaxed-region mask (the differentiable A*'s closed set intersected with R_soft),
v*_rlx the demonstration's. False relaxations are penalised as

    L_rlx(v, v*) = (w_fp v^T (1 - v*) + w_fn (1 - v)^T v*) / (1 + ||v*||_1)              (12)

and a mini-batch averages them with weights w_i = min(1, L_rlx(v_i, v*_i; w_fp', w_fn')^gamma)
(13)-(14), computed with their own weights (the paper: w_fp' = w_fn' = 0.5) and held constant in the
gradient — a weight that scales a sample's loss, not a second objective: hard samples (large loss)
keep weight 1, nearly-solved ones fade out.

``planned`` (optional) is the mask the false positives are counted on. The paper counts both terms on
the closed set (v = c ⊙ R_soft). Passing the plan's relaxed regions (path ⊙ R_soft, a subset of v)
counts as false positives only the soft regions the plan actually crosses, while the false negatives
stay on the closed set (a demonstrated region the search never closed gets its gradient through the
selection softmax; on the hard path mask it would get none). Why: see ``surenav.train``.
"""

from __future__ import annotations

import torch
from torch import Tensor

from navlab.core.params.surenav_model import TrainParams


def relaxation_loss(v: Tensor, target: Tensor, w_fp: float, w_fn: float, planned: Tensor | None = None) -> Tensor:
    """Eq. (12) per sample: ``v`` and ``target`` are (B, N) masks (0/1, ``v`` differentiable); false
    positives are counted on ``planned`` (default ``v``, the paper's choice)."""
    planned = v if planned is None else planned
    if v.shape != target.shape or planned.shape != v.shape:
        raise ValueError(f"relaxed masks {tuple(v.shape)}, {tuple(planned.shape)} and target {tuple(target.shape)} "
                         "must have one shape (B, N)")
    target = target.to(v.dtype)
    false_pos = (planned * (1 - target)).sum(-1)
    false_neg = ((1 - v) * target).sum(-1)
    return (w_fp * false_pos + w_fn * false_neg) / (1 + target.sum(-1))


def sample_weights(v: Tensor, target: Tensor, gamma: float, w_fp: float = 0.5, w_fn: float = 0.5,
                   planned: Tensor | None = None) -> Tensor:
    """Eq. (14): w_i = min(1, L_rlx(v_i, v*_i)^gamma) with the weight's own (w_fp, w_fn); no gradient."""
    with torch.no_grad():
        planned = None if planned is None else planned.detach()
        return torch.clamp(relaxation_loss(v.detach(), target, w_fp, w_fn, planned) ** gamma, max=1.0)


def batch_loss(v: Tensor, target: Tensor, train: TrainParams, planned: Tensor | None = None) -> Tensor:
    """Eq. (13): the mean over the batch of w_i L_rlx(v_i, v*_i)."""
    per_sample = relaxation_loss(v, target, train.w_fp, train.w_fn, planned)
    weights = sample_weights(v, target, train.gamma, train.weight_w_fp, train.weight_w_fn, planned)
    return (weights * per_sample).mean()
