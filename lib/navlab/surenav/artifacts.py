"""Artefact builder of the SuReNav estimator (DVC stage ``surenav_estimator``): every training seed of
the GPS estimator and the first ``train.ablation_seeds`` of its MPNN-only ablation, from one build of the
demonstration samples.

Folders: ``artifacts/surenav/{gps,mpnn}/seed<k>/`` with ``model.pt``, ``checkpoint.pt`` and ``log.tsv``.
"""

from __future__ import annotations

from pathlib import Path

from navlab.core.params import Params
from navlab.core.params.surenav_model import TrainParams
from navlab.surenav.train import train_estimator
from navlab.surenav.training_data import demo_samples

VARIANTS = {"gps": True, "mpnn": False}  # folder -> global attention on


def variant_seeds(train: TrainParams) -> dict[str, tuple[int, ...]]:
    """The training seeds of each variant: every seed for the GPS estimator, the first
    ``ablation_seeds`` for the MPNN-only ablation."""
    return {"gps": tuple(train.seeds), "mpnn": tuple(train.seeds[:train.ablation_seeds])}


def model_path(artifacts_dir: str | Path, variant: str, seed: int) -> Path:
    if variant not in VARIANTS:
        raise ValueError(f"unknown estimator variant {variant!r}; variants are {', '.join(VARIANTS)}")
    return Path(artifacts_dir) / "surenav" / variant / f"seed{seed}" / "model.pt"


def build_estimators(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
    s = params.surenav
    train = demo_samples(data_dir, "train", s.graph, s.model, s.train.max_demos)
    val = demo_samples(data_dir, "val", s.graph, s.model, s.train.max_demos)
    seeds = variant_seeds(s.train)
    for seed in s.train.seeds:  # seed-major: the first seed of both variants is ready first
        for variant, attention in VARIANTS.items():
            if seed not in seeds[variant]:
                continue
            train_estimator(train, val, s.model, s.train, model_path(artifacts_dir, variant, seed).parent,
                            seed=seed, attention=attention)


def artifact_steps() -> list:
    """(name, fn(params, data_dir, artifacts_dir))."""
    return [("surenav_estimator", build_estimators)]
