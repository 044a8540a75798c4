"""PACER's notebook runs: which trained model makes each row of Tables I-V and each figure, and the runs.

Why a module: which models a row is made of (the main recipe under every training seed, the labelled variants,
the baselines, the reference rows) is part of the experiment, not of its display, so the notebooks
``pacer/01_costmaps``, ``pacer/02_navigation`` and ``pacer/03_phase_ablation`` call one function each and draw or
show what it returns. The
measurements themselves are ``navlab.pacer.experiments`` (navigation, agreement, margin ranking) and
``navlab.pacer.recognition``; every model is read from the DVC stages' artefacts (``navlab.pacer.variants``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from navlab.core.params import Params
from navlab.core.params.pacer import PacerParams
from navlab.pacer.aerial import AerialMap, aerial_maps
from navlab.pacer.baselines.semantic_classifier import load_classifier
from navlab.pacer.baselines.sterling import load_sterling
from navlab.pacer.checkpoints import read_summary
from navlab.pacer.datasets import CONTEXT_DRAWS, evaluation_dataset, pacer_dataset
from navlab.pacer.experiments import (
    FIGURE_PREFERENCES,
    Agreement,
    ContextKind,
    ContextRun,
    Method,
    NavigationResult,
    bev_context_costmaps,
    chain_context_rows,
    classifier_method,
    context_following_rows,
    context_limited_oracle_method,
    context_runs,
    ground_truth_method,
    heldout_bev_params,
    margin_ranking_errors,
    merge_seeds,
    navigation_rows,
    pacer_method,
    seed_member,
    sterling_method,
    uniform_method,
    window_oracle_method,
)
from navlab.pacer.feature_memo import FeatureMemo, share_features
from navlab.pacer.map_windows import map_windows
from navlab.pacer.recognition import recognition_rows, true_terrain_method, true_terrains_name
from navlab.pacer.terrain import TerrainBank
from navlab.pacer.train import PHASES, load_model
from navlab.pacer.variants import (
    PAPER_ARCHITECTURE,
    PAPER_ARCHITECTURE_ROW,
    SCRATCH_MATCHER,
    SCRATCH_MATCHER_ROW,
    phase_model,
    seed_models,
    training_seeds,
)

ENVIRONMENTS = ("seen", "unseen")
PREFERENCES = ("realistic", "inverted")
PHASE_NAMES = {"phase1": "D_real", "phase2": "D_shuffled", "phase3": "D_synthetic"}  # Tables III-V's rows
VARIANTS = ((PAPER_ARCHITECTURE, PAPER_ARCHITECTURE_ROW), (SCRATCH_MATCHER, SCRATCH_MATCHER_ROW))
# the frozen ImageNet features one run keeps for its models to share (``feature_memo``): one map group's
# windows under every model of a table are about 0.5 GB at the default size
FEATURE_MEMO_BYTES = 1 << 30


def variant_models(params: Params, artifacts_dir: str | Path, memo: FeatureMemo) -> dict[str, torch.nn.Module]:
    """The labelled variant rows' phase-3 models (one seed each): the paper's architecture and the from-scratch
    matcher (``navlab.pacer.variants``)."""
    device = params.pacer.train.device
    return {row: share_features(load_model(phase_model(artifacts_dir, variant), device), memo)
            for variant, row in VARIANTS}


def training_summaries(pacer: PacerParams, artifacts_dir: str | Path) -> dict[str, list[dict]]:
    """Every PACER network this profile trains, by row (each training seed of the main recipe, then the variant
    rows): its phases' ``summary.json`` with the training cost where this machine trained it (issue 61's budget)."""
    rows = {f"seed {seed}": [read_summary(seed_models(artifacts_dir, pacer, phase)[seed].parent) for phase in PHASES]
            for seed in training_seeds(pacer)}
    return rows | {row: [read_summary(phase_model(artifacts_dir, variant, phase).parent) for phase in PHASES]
                   for variant, row in VARIANTS}


def _reference_methods(params: Params) -> dict[str, tuple[Method, ContextKind]]:
    """The rows that bracket every table: the window oracle (the protocol's ceiling), the context-limited oracle
    (a perfect context-follower with no prior) and the uniform costmap (chance)."""
    return {"Window oracle (ceiling)": (window_oracle_method(params.pacer.data), True),
            "Context-limited oracle": (context_limited_oracle_method(), True),
            "Uniform costmap (chance)": (uniform_method(), True)}


@dataclass(frozen=True)
class Navigation:
    """Tables I (seen) and II (unseen) under the realistic preference: each environment's maps and result."""

    maps: dict[str, list[AerialMap]]
    results: dict[str, NavigationResult]
    classifier: dict


def navigation_runs(params: Params, data_dir: str | Path, artifacts_dir: str | Path, bank: TerrainBank) -> Navigation:
    """Every method of Tables I-II on the seen and unseen aerial maps: PACER (informative and uninformative
    context) under each training seed, merged into one row each; PACER given the true terrains; the variants;
    STERLING-style and the semantic classifier; ground truth and the reference rows."""
    P = params.pacer
    device, artifacts = P.train.device, Path(artifacts_dir) / "pacer"
    memo = FeatureMemo(FEATURE_MEMO_BYTES)
    models = {seed: share_features(load_model(path, device), memo) for seed, path in seed_models(artifacts_dir, P).items()}
    seeded = {"PACER": True, "PACER (uninformative context)": False}
    methods = {seed_member(name, seed): (pacer_method(model, P.data, device), informative)
               for name, informative in seeded.items() for seed, model in models.items()}
    methods |= {true_terrains_name("PACER"): (true_terrain_method(models[P.seed].matcher), True)}
    methods |= {row: (pacer_method(model, P.data, device), True)
                for row, model in variant_models(params, artifacts_dir, memo).items()}
    methods |= {
        "STERLING-style": (sterling_method(load_sterling(artifacts / "sterling" / "encoder.pt"),
                                           P.baselines.sterling.utility_steps), True),
        "Classifier": (classifier_method(load_classifier(artifacts / "classifier" / "classifier.pt"), bank,
                                         "realistic"), True),
        "Ground truth": (ground_truth_method(), True),
        **_reference_methods(params),
    }
    maps = {env: aerial_maps(params, data_dir, env, bank) for env in ENVIRONMENTS}
    results = {env: merge_seeds(navigation_rows(maps[env], methods, bank, P.data, "realistic", P.evaluation.cost_scale,
                                                P.seed, P.evaluation.queries_per_map),
                                {name: list(models) for name in seeded}, P.seed, "realistic")
               for env in ENVIRONMENTS}
    return Navigation(maps, results, read_summary(artifacts / "classifier"))


@dataclass(frozen=True)
class PhaseAblation:
    """Tables III-V and ``context_following``: navigation by (environment, preference), held-out agreement by
    (model, environment, preference, context draw) with its report rows, margin ranking errors by model then
    test set, the phases' training summaries, the main seed's model names (the agreement figure's) and the summaries
    of every network trained for the tables."""

    results: dict[tuple[str, str], NavigationResult]
    agreement: dict[tuple[str, str, str, str], Agreement]
    agreement_rows: list[dict]
    margin_errors: dict[str, dict[str, np.ndarray]]
    summaries: dict[str, dict]
    models: tuple[str, ...]
    training: dict[str, list[dict]]  # every trained network's phase summaries by row (``training_summaries``)


def phase_ablation_runs(params: Params, data_dir: str | Path, artifacts_dir: str | Path,
                        bank: TerrainBank) -> PhaseAblation:
    """Every phase's model under each training seed on both map groups under both preferences (Tables III-IV:
    the mean over seeds), the variants and the reference rows beside them; the main seed's phases alone for the
    diagnostics (held-out agreement, the chained context, recognition beside the other seeds' and the
    from-scratch matcher's phase-3 matchers, Table V's margin ranking)."""
    P = params.pacer
    device, artifacts = P.train.device, Path(artifacts_dir) / "pacer"
    memo = FeatureMemo(FEATURE_MEMO_BYTES)
    by_seed = {PHASE_NAMES[p]: {seed: share_features(load_model(path, device), memo)
                                for seed, path in seed_models(artifacts_dir, P, p).items()}
               for p in PHASES}
    models = {name: seeds[P.seed] for name, seeds in by_seed.items()}
    variants = variant_models(params, artifacts_dir, memo)
    summaries = {PHASE_NAMES[p]: read_summary(artifacts / p) for p in PHASES}
    methods = {seed_member(name, seed): (pacer_method(m, P.data, device), True)
               for name, seeds in by_seed.items() for seed, m in seeds.items()}
    methods |= {row: (pacer_method(model, P.data, device), True) for row, model in variants.items()}
    reference = _reference_methods(params)
    methods |= {name: reference[name] for name in ("Window oracle (ceiling)", "Context-limited oracle")}
    methods |= {true_terrains_name("D_synthetic"): (true_terrain_method(models["D_synthetic"].matcher), True),
                "Uniform costmap (chance)": reference["Uniform costmap (chance)"]}
    maps = {env: aerial_maps(params, data_dir, env, bank) for env in ENVIRONMENTS}
    results = {(env, pref): merge_seeds(navigation_rows(maps[env], methods, bank, P.data, pref, P.evaluation.cost_scale,
                                                        P.seed, P.evaluation.queries_per_map),
                                        {name: list(seeds) for name, seeds in by_seed.items()}, P.seed, pref)
               for env in ENVIRONMENTS for pref in PREFERENCES}

    sets = {(env, pref, context): evaluation_dataset(heldout_bev_params(params), data_dir, env, pref, bank=bank,
                                                     context=context)
            for env in ENVIRONMENTS for pref in PREFERENCES for context in CONTEXT_DRAWS}
    windows = {(env, pref): map_windows(params, data_dir, "test", env, (pref,), P.evaluation.heldout_examples, bank)
               for env in ENVIRONMENTS for pref in PREFERENCES}
    agreement_rows, agreement = context_following_rows(models, sets, summaries, P.evaluation.heldout_examples, P.seed,
                                                       device, windows=windows, cost_scale=P.evaluation.cost_scale)
    main = seed_member("D_synthetic", P.seed)
    agreement_rows += chain_context_rows(main, maps, methods[main][0], bank, P.data, P.evaluation, P.seed, results)
    matchers = {**models, **{seed_member("D_synthetic", seed): m for seed, m in by_seed["D_synthetic"].items()
                             if seed != P.seed}, SCRATCH_MATCHER_ROW: variants[SCRATCH_MATCHER_ROW]}
    agreement_rows += recognition_rows(matchers, maps, bank, P.data, P.seed, device)

    test_sets = {name: pacer_dataset(params, data_dir, name, "test", bank) for name in ("real", "shuffled", "synthetic")}
    margin_errors = {name: {set_name: margin_ranking_errors(model, ds, P.evaluation.heldout_examples,
                                                            P.evaluation.margin_points, P.seed, device)
                            for set_name, ds in test_sets.items()}
                     for name, model in models.items()}
    return PhaseAblation(results, agreement, agreement_rows, margin_errors, summaries, tuple(models),
                         training_summaries(P, artifacts_dir))


# Figs. 1/4 on the first seen map under the realistic and the inverted context, Fig. 5 on the first unseen map
# under those and two random orderings
FIGURE_MAPS = (("seen", FIGURE_PREFERENCES[:2]), ("unseen", FIGURE_PREFERENCES))


@dataclass(frozen=True)
class CostmapFigures:
    """Fig. 3's (preference, BEV item, costmap) under each context, and per map group (``FIGURE_MAPS``) the
    first aerial map with its runs, one per preference context."""

    bev: list[tuple[str, dict, np.ndarray]]
    maps: dict[str, tuple[AerialMap, list[ContextRun]]]


def costmap_figure_runs(params: Params, data_dir: str | Path, artifacts_dir: str | Path,
                        bank: TerrainBank) -> CostmapFigures:
    """The phase-3 model (``pacer.seed``'s) on one held-out BEV image under the realistic and the inverted
    context, and on the first seen and unseen aerial maps under ``FIGURE_MAPS``' contexts."""
    P = params.pacer
    device = P.train.device
    model = load_model(Path(artifacts_dir) / "pacer" / "phase3" / "model.pt", device)
    pacer = pacer_method(model, P.data, device)
    bev = {pref: evaluation_dataset(heldout_bev_params(params), data_dir, "seen", pref, bank=bank)
           for pref in PREFERENCES}
    maps = {}
    for env, preferences in FIGURE_MAPS:
        amap = aerial_maps(params, data_dir, env, bank)[0]
        maps[env] = (amap, context_runs(pacer, amap, bank, P.data, preferences, P.seed, P.evaluation.cost_scale))
    return CostmapFigures(bev_context_costmaps(model, bev, device=device), maps)
