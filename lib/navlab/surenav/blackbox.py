"""Eq. (12)-(14) through the exact graph A*, with blackbox-differentiation gradients (Vlastelica et al. 2020).

Why: the paper trains Psi through Neural A*'s straight-through selection softmax (``search.diff_astar``).
On the context demonstrations that gradient stalls (the Eq. 13 loss stops falling after two epochs, at
any temperature, and the estimator fits its training demonstrations no better than its validation ones;
``benchmarks/surenav_estimator_fit.py``). Here the plan is the exact A*'s and the gradient comes from a
second exact A* at perturbed costs. The plan's relaxed regions y(Psi) (path ⊙ R_soft) minimise a path cost
that is linear in Psi (distance + sum of Psi over the entered regions, Eq. 9), so for a loss L(y) the
interpolated loss of "Differentiation of Blackbox Combinatorial Solvers" (ICLR 2020, Eq. 6 / Alg. 1) has

    dL/dPsi = -(y(Psi) - y(Psi'))/lambda,   Psi' = max(0, Psi + lambda dL/dy)

with ``lambda`` in metres of Psi: how far the costs move to let the plan change. L is Eq. (12) with both
terms on the plan's relaxed regions (what Table I scores); Eq. (14)'s weight scales each sample's gradient.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch
from torch import Tensor
from torch_geometric.data import Batch
from torch_geometric.utils import to_dense_batch

from navlab.core.params.surenav_model import TrainParams
from navlab.search.diff_astar import GraphBatch, batch_graphs, diff_astar
from navlab.surenav.loss import relaxation_loss, sample_weights
from navlab.surenav.model.estimator import RelaxationCostEstimator
from navlab.surenav.training_data import Sample


def _relaxed(graphs: GraphBatch, psi: Tensor, soft: Tensor) -> Tensor:
    """(B, N) 0/1: the soft nodes on each graph's exact A* path at entry costs ``psi``."""
    with torch.no_grad():
        return diff_astar(graphs, psi, temperature=1.0).path.detach() * soft  # forward only: no temperature used


def blackbox_loss(psi: Tensor, graphs: GraphBatch, soft: Tensor, target: Tensor, train: TrainParams,
                  lambda_m: float) -> tuple[Tensor, float]:
    """(surrogate whose gradient in ``psi`` (B, N) is the blackbox gradient of Eq. 13, Eq. 13's value).

    ``soft``: (B, N) 0/1 soft-node masks; ``target``: (B, N) the demonstrations' relaxed regions."""
    if lambda_m <= 0:
        raise ValueError(f"blackbox lambda_m = {lambda_m}: it must be > 0 (metres of Psi; params.yaml "
                         "surenav.demos.context.estimator.lambda_m)")
    soft, target = soft.to(psi.dtype), target.to(psi.dtype)
    y = _relaxed(graphs, psi.detach(), soft).requires_grad_(True)
    per_sample = relaxation_loss(y, target, train.w_fp, train.w_fn)
    weights = sample_weights(y, target, train.gamma, train.weight_w_fp, train.weight_w_fn)
    (dl_dy,) = torch.autograd.grad(per_sample.sum(), y)
    perturbed = _relaxed(graphs, (psi.detach() + lambda_m * dl_dy * soft).clamp_min(0.0), soft)
    grad = weights[:, None] * (perturbed - y.detach()) / lambda_m
    value = float((weights * per_sample.detach()).mean())
    return (grad * psi).sum() / len(psi), value


def estimator_blackbox_loss(model: RelaxationCostEstimator, samples: Sequence[Sample], train: TrainParams,
                            lambda_m: float) -> tuple[Tensor, float]:
    """``blackbox_loss`` of the estimator's Psi on a batch of training samples."""
    data = Batch.from_data_list([s.data for s in samples])
    psi, _ = to_dense_batch(model(data), data.batch)
    soft, _ = to_dense_batch(data.soft, data.batch)
    graphs = batch_graphs([s.search for s in samples], starts=[s.start for s in samples],
                          goals=[s.goal for s in samples], dtype=psi.dtype)
    target = torch.zeros(psi.shape, dtype=torch.bool)
    for i, s in enumerate(samples):
        target[i, :len(s.target)] = torch.from_numpy(s.target)
    return blackbox_loss(psi, graphs, soft, target, train, lambda_m)
