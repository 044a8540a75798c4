"""params.yaml `surenav.demos`: demonstrators of the SuReNav benchmark beyond data.demos' per-label expert."""

from __future__ import annotations

from typing import Annotated, Literal

from navlab.core.params.fields import between, section


@section
class ContextEstimatorParams:
    """How surenav_context_estimator trains (surenav.context.training): the gradient through the A*, and the
    leave-one-city-out runs."""

    gradient: Literal["blackbox", "straight_through"]  # the main row's; the other one is an ablation row
    lambda_m: Annotated[float, between(1e-6)]  # blackbox: how far Psi moves (metres) to let the plan change
    epochs: Annotated[int, between(1)]  # blackbox: epochs of a cosine learning-rate schedule, best validation IoU kept
    lr: Annotated[float, between(1e-7, 1.0)]  # blackbox: AdamW's starting learning rate
    held_out_cities: tuple[Literal["helsinki", "kouvola", "monaco"], ...]  # leave-one-city-out runs, one per city listed


@section
class ContextDemosParams:
    seed: Annotated[int, between(0)]
    test_pairs_per_map: Annotated[int, between(1)]  # semi-static environments per test map (Table I: 5 maps x 20)
    min_context_share: Annotated[float, between(0.0, 1.0)]  # Expert IoU minus the best per-label field's, at least
    min_region_gain: Annotated[float, between(0.0, 1.0)]  # rule-Psi SuReNav IoU minus the best per-label field's, at least
    train_pairs_per_map: Annotated[int, between(1)]  # demonstrations per real training / validation tile (surenav_context_demos)
    val_tiles: Annotated[int, between(1)]  # real non-test tiles held out for validation; the others train
    max_train_tiles: Annotated[int, between(0)]  # training tiles used (0: every eligible one); smoke keeps it small
    node_features: Literal["labels", "context"]  # the context estimator's input: Eq. 7 alone, or + the rules' context
    estimator: ContextEstimatorParams


@section
class SuReNavDemosParams:
    context: ContextDemosParams  # the context demonstrator (navlab.surenav.context)
