"""params.yaml `surenav.model`, `surenav.train`, `surenav.planner`: SuReNav's learned relaxation cost
(Sec. IV-C/D) and the planner that uses it (Sec. V)."""

from __future__ import annotations

from typing import Annotated, Literal

from navlab.core.params.fields import between, section


@section
class EstimatorParams:
    """The GNN Psi_G (Sec. IV-C.2): GPS layers (GatedGCN + multi-head attention), node-wise MLP, softplus."""

    channels: Annotated[int, between(4)]  # width of node and edge states
    layers: Annotated[int, between(1)]  # K of Eq. (8)
    heads: Annotated[int, between(1)]  # attention heads (must divide channels)
    walk_steps: Annotated[int, between(0, 64)]  # random-walk structural encoding length (0: none)
    dropout: Annotated[float, between(0.0, 0.9)]
    distance_scale_m: Annotated[float, between(1e-3)]  # edge feature = centroid distance / this
    cost_scale_m: Annotated[float, between(1e-3)]  # Psi = this * softplus(MLP): metres of detour, like g and h
    window_margin_m: Annotated[float, between(0.0)]  # the query window: start-goal box grown by this (the expert's margin)


@section
class TrainParams:
    """End-to-end training through the differentiable graph A* (Sec. IV-D, Eq. 12-14)."""

    seeds: Annotated[tuple[int, ...], between(0)]  # one model per seed; the reports give mean and spread
    ablation_seeds: Annotated[int, between(1)]  # the MPNN-only ablation: the first this many seeds
    epochs: Annotated[int, between(1)]  # the most; early stopping may end sooner
    patience: Annotated[int, between(0)]  # stop after this many epochs without a better validation IoU (0: never)
    batch_size: Annotated[int, between(1)]
    lr: Annotated[float, between(1e-7, 1.0)]  # AdamW
    weight_decay: Annotated[float, between(0.0, 1.0)]
    w_fp: Annotated[float, between(0.0)]  # Eq. (12) false-positive weight
    w_fn: Annotated[float, between(0.0)]  # Eq. (12) false-negative weight (the paper: w_fn > w_fp)
    gamma: Annotated[float, between(1e-6)]  # Eq. (14) exponent
    weight_w_fp: Annotated[float, between(0.0)]  # Eq. (14): the per-sample weight's own w_fp (paper 0.5)
    weight_w_fn: Annotated[float, between(0.0)]  # Eq. (14): the per-sample weight's own w_fn (paper 0.5)
    temperature: Annotated[float, between(1e-6)]  # lambda of Eq. (10), the selection softmax temperature
    false_positives_on: Literal["closed", "path"]  # Eq. (12)'s FP term on the closed set (paper) or the plan
    max_demos: Annotated[int, between(0)]  # training demonstrations used per split (0: all)
    device: str  # "cpu" or "cuda"
    threads: Annotated[int, between(1, 64)]  # torch CPU threads


@section
class PlannerParams:
    """Algorithm 1's low-level plan (Sec. V)."""

    mode: Literal["free_union", "within", "graph"]  # X in X_G ∪ R_free (paper) / within X_G / centroid graph plan
    rcr_scale_m: Annotated[float, between(1e-3)]  # ablation: Psi = this x RCR's score (metres per unit of score)
