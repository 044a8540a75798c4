"""params.yaml `pacer`: parameters of the pacer track."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from navlab.core.params.fields import between


@dataclass(frozen=True)
class PacerModelParams:
    """The costmap network (pacer/model.py): a U-Net over the BEV image, a context encoder, a fusion."""

    image_channels: tuple[int, ...] = between(1)  # U-Net encoder widths, one max-pool after each
    bottleneck_channels: int = between(1)
    context_encoder: Literal["cnn", "resnet50"]
    context_channels: tuple[int, ...] = between(1)  # widths of the small CNN (unused by resnet50)
    context_dim: int = between(1)  # the preference embedding
    fusion: Literal["film", "concat_mlp"]  # film: every decoder stage; concat_mlp: the released code's


@dataclass(frozen=True)
class PacerPhaseEpochs:
    phase1: int = between(1)  # D_real
    phase2: int = between(1)  # D_real + D_shuffled
    phase3: int = between(1)  # D_real + D_shuffled + D_synthetic


@dataclass(frozen=True)
class PacerTrainParams:
    device: str  # "cpu" or "cuda"
    epochs: PacerPhaseEpochs
    examples_per_epoch: int = between(1)  # drawn uniformly over the phase's datasets (Sec. V-C)
    batch_size: int = between(1)
    lr: float = between(1e-7, 1.0)
    threads: int = between(1, 64)


@dataclass(frozen=True)
class PacerSterlingParams:
    embed_dim: int = between(2)
    channels: tuple[int, ...] = between(1)
    epochs: int = between(1)
    patches_per_epoch: int = between(2)
    batch_size: int = between(2)
    lr: float = between(1e-7, 1.0)
    vicreg_weights: tuple[float, ...] = between(0.0, length=3)  # invariance, variance, covariance
    utility_steps: int = between(1)  # gradient steps fitting the utility to one context's pairs


@dataclass(frozen=True)
class PacerClassifierParams:
    channels: tuple[int, ...] = between(1)
    epochs: int = between(1)
    patches_per_epoch: int = between(1)
    batch_size: int = between(1)
    lr: float = between(1e-7, 1.0)


@dataclass(frozen=True)
class PacerBaselineParams:
    patch_size: int = between(4)  # side of the square patches both baselines score
    sterling: PacerSterlingParams
    classifier: PacerClassifierParams


@dataclass(frozen=True)
class PacerEvalParams:
    heldout_examples: int = between(1)  # per evaluation set
    margin_points: int = between(2)  # points sampled per costmap for the margin ranking error
    cost_scale: float = between(0.0)  # A* cost per metre = 1 + cost_scale * predicted cost


@dataclass(frozen=True)
class PacerParams:
    seed: int = between(0)
    model: PacerModelParams
    train: PacerTrainParams
    baselines: PacerBaselineParams
    evaluation: PacerEvalParams
