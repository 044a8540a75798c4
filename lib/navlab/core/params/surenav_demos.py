"""params.yaml `surenav.demos`: demonstrators of the SuReNav benchmark beyond data.demos' per-label expert."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from navlab.core.params.fields import between


@dataclass(frozen=True)
class ContextEstimatorParams:
    """How surenav_context_estimator trains (surenav.context.training): the gradient through the A*."""

    gradient: Literal["blackbox", "straight_through"]  # the main row's; the other one is an ablation row
    lambda_m: float = between(1e-6)  # blackbox: how far Psi moves (metres) to let the plan change
    epochs: int = between(1)  # blackbox: epochs of a cosine learning-rate schedule, best validation IoU kept
    lr: float = between(1e-7, 1.0)  # blackbox: AdamW's starting learning rate


@dataclass(frozen=True)
class ContextDemosParams:
    seed: int = between(0)
    test_pairs_per_map: int = between(1)  # semi-static environments per test map (Table I: 5 maps x 20)
    min_context_share: float = between(0.0, 1.0)  # Expert IoU minus the best per-label field's, at least
    min_region_gain: float = between(0.0, 1.0)  # rule-Psi SuReNav IoU minus the best per-label field's, at least
    train_pairs_per_map: int = between(1)  # demonstrations per real training / validation tile (surenav_context_demos)
    val_tiles: int = between(1)  # real non-test tiles held out for validation; the others train
    max_train_tiles: int = between(0)  # training tiles used (0: every eligible one); smoke keeps it small
    node_features: Literal["labels", "context"]  # the context estimator's input: Eq. 7 alone, or + the rules' context
    estimator: ContextEstimatorParams


@dataclass(frozen=True)
class SuReNavDemosParams:
    context: ContextDemosParams  # the context demonstrator (navlab.surenav.context)
