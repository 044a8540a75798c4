"""PACER's rows beside the main model (issue 61): more training seeds of the main recipe and the paper's own
architecture, each trained through the three phases exactly as the main model is (``artifacts.phase_step``: the
same datasets, selection windows, budget and checkpoint resumption).

Why: one training seed cannot tell a method's effect from its seed's luck (three seeds of one recipe differed
by up to 0.14 in one set's gap closed, benchmarks/README.md), and a reader cannot see what our additions buy
without the released design trained beside them on the same data and budget.

* ``seeds`` (``pacer.variants.seeds``): the main recipe again under each seed, which keys phase 1's
  initialisation and every epoch's draws; the main model (``pacer.seed``) is the first of the tables' seeds.
* ``paper_architecture``: the released design at this profile's size: concat-MLP fusion, Eq. 3 alone (no
  matching or contrast loss), no texture matcher; everything else (the image U-Net's and the context encoder's
  widths, the data, epochs and selection) as the main model's, so the row measures the design, not the budget.
* ``scratch_matcher``: the main recipe with the texture matcher's towers trained from scratch on the seen
  photographs (``pacer.model.match_features: scratch``: a colour and a grey tower, the design before issue 61)
  instead of EfficientNet-Lite0's frozen ImageNet features, so the row measures what the pretrained features buy.
  The towers are pooled to the ImageNet features' stride (4: the first two stages of ``match_channels``), so the
  matcher compares features on the grid the main model's does. Why not the dilated full-resolution towers of
  ``match_dilated``: they made each epoch 3.2-3.6x the main model's (the row alone was 58 of PACER's ~127
  minutes, against issue 61's 60), and they also changed the grid the matcher sees, so the row measured two
  things at once (benchmarks/README.md, "The from-scratch matcher at the ImageNet features' stride").

Each variant's folder is an artefacts tree of its own (``<variant root>/pacer/phase1`` ... ``phase3``), laid
out as ``artifacts/`` is, so the main model's loaders read it with the same paths.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from pathlib import Path

from navlab.core.params import Params
from navlab.core.params.pacer import PacerParams
from navlab.pacer.artifacts import artifact_steps as main_steps
from navlab.pacer.artifacts import phase_step
from navlab.pacer.pretrained import ImageNetFeatures
from navlab.pacer.train import PHASES

FOLDER = ("pacer", "variants")  # under artifacts/
SEEDS, PAPER_ARCHITECTURE, SCRATCH_MATCHER = "seeds", "paper_architecture", "scratch_matcher"
PAPER_ARCHITECTURE_ROW = "PACER, paper architecture (concat-MLP, Eq. 3 alone, no matcher)"  # its tables' row
SCRATCH_MATCHER_ROW = "PACER, matcher trained from scratch (no ImageNet features)"


def variant_root(artifacts_dir: str | Path, variant: str, seed: int | None = None) -> Path:
    """The artefacts tree of one variant (of one extra seed for ``seeds``)."""
    root = Path(artifacts_dir).joinpath(*FOLDER, variant)
    return root / f"seed{seed}" if seed is not None else root


def phase_model(artifacts_dir: str | Path, variant: str, phase: str = "phase3", seed: int | None = None) -> Path:
    return variant_root(artifacts_dir, variant, seed) / "pacer" / phase / "model.pt"


def training_seeds(pacer: PacerParams) -> tuple[int, ...]:
    """The main recipe's training seeds, the main model's (``pacer.seed``) first."""
    return (pacer.seed, *pacer.variants.seeds)


def seed_models(artifacts_dir: str | Path, pacer: PacerParams, phase: str = "phase3") -> dict[int, Path]:
    """``model.pt`` of the main recipe after ``phase`` under each training seed: ``pacer.seed``'s from the
    main stages (artifacts/pacer/<phase>), the others' from ``pacer_seeds``."""
    return {seed: (Path(artifacts_dir) / "pacer" / phase / "model.pt" if seed == pacer.seed else
                   phase_model(artifacts_dir, SEEDS, phase, seed)) for seed in training_seeds(pacer)}


def with_seed(params: Params, seed: int) -> Params:
    return dataclasses.replace(params, pacer=dataclasses.replace(params.pacer, seed=seed))


def paper_architecture(params: Params) -> Params:
    """The released design at this profile's size (module docstring)."""
    p = params.pacer
    model = dataclasses.replace(p.model, fusion="concat_mlp", match_channels=())
    train = dataclasses.replace(p.train, match_loss_weight=0.0, contrast_loss_weight=0.0)
    return dataclasses.replace(params, pacer=dataclasses.replace(p, model=model, train=train))


def scratch_matcher(params: Params) -> Params:
    """The main recipe with the matcher's towers learnt from the seen photographs alone, pooled to the ImageNet
    features' stride (module docstring)."""
    p = params.pacer
    stages = int(math.log2(min(ImageNetFeatures.STRIDES)))  # a pooled tower halves the grid once per stage
    model = dataclasses.replace(p.model, match_features="scratch", match_dilated=False,
                                match_channels=tuple(p.model.match_channels[:stages]))
    return dataclasses.replace(params, pacer=dataclasses.replace(p, model=model))


def train_three_phases(params: Params, data_dir: Path, root: Path) -> None:
    """Phases 1-3 into the artefacts tree ``root``, each resuming its own checkpoint (a killed stage resumes)."""
    for phase in PHASES:
        phase_step(phase)(params, data_dir, root)


def _variant(make: Callable[[Params], Params], variant: str):
    def step(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
        train_three_phases(make(params), data_dir, variant_root(artifacts_dir, variant))
    return step


def build_seeds(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
    """The main recipe under each of ``pacer.variants.seeds`` (none may repeat ``pacer.seed``)."""
    for seed in params.pacer.variants.seeds:
        train_three_phases(with_seed(params, seed), data_dir, variant_root(artifacts_dir, SEEDS, seed))


def artifact_steps() -> list:
    """The main model's and baselines' steps (``pacer.artifacts``), then the variants'."""
    return [*main_steps(), (f"pacer_{SEEDS}", build_seeds),
            (f"pacer_{PAPER_ARCHITECTURE}", _variant(paper_architecture, PAPER_ARCHITECTURE)),
            (f"pacer_{SCRATCH_MATCHER}", _variant(scratch_matcher, SCRATCH_MATCHER))]
