"""The measurements behind PACER's Tables I-V, as functions the notebooks call.

- Navigation (Tables I-IV): on each rendered aerial map, every method costs the map under one
  preference (realistic or inverted), A* plans from the map's start to its goal, and the path is
  scored by the share of its cells on low / medium / high tiers of the hidden ordering of that map's
  own terrains (``preferences.environment_tiers``), averaged over maps with a bootstrap 95% interval.
  Two reference rows bracket every table: a uniform costmap (chance: the plain shortest path) and
  the window oracle (the ceiling of the stitched-window protocol).
  Each method receives the preference in its own form (Sec. VI): PACER and STERLING a preference
  context of terrain patches, the classifier a label → cost table, ground truth the ordering itself.
- Margin ranking error (Table V) and the held-out preference agreement on BEV test items.
- The figures' runs (Figs. 1, 3, 4, 5): one map or BEV item costed under several contexts.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
import torch
from torch.utils.data import Dataset

from navlab.core.params import Params
from navlab.core.params.pacer import PacerDataParams
from navlab.core.seeding import rng
from navlab.metrics import crossed
from navlab.metrics.cost_tiers import TIER_NAMES, cost_tier_proportions
from navlab.metrics.intervals import bootstrap_mean_ci, bootstrap_ratio_ci
from navlab.pacer.aerial import AerialMap
from navlab.pacer.baselines.semantic_classifier import SemanticClassifier
from navlab.pacer.baselines.sterling import SterlingEncoder
from navlab.pacer.bev import fov_mask
from navlab.pacer.context import chain_pairs, pair_context, preference_context, uninformative_context
from navlab.pacer.evaluate import (
    context_pair_agreement,
    costmap_over_map,
    crossing_queries,
    plan_on_costmap,
    window_oracle_costmap,
)
from navlab.pacer.map_windows import METRICS, MapWindow, window_scores
from navlab.pacer.margin_ranking import margin_ranking_error
from navlab.pacer.preferences import (
    context_limited_costs,
    environment_tiers,
    order_terrains,
    rank_costs,
    target_costmap,
)
from navlab.pacer.terrain import TerrainBank

Preference = Literal["realistic", "inverted"]
# Figs. 1/4 (a seen map) and Fig. 5 (an unseen map, "several paths ... and their corresponding preference
# contexts"): the realistic ordering, its inversion, and two random orderings of the map's terrains.
FIGURE_PREFERENCES: tuple[str, ...] = ("realistic", "inverted", "random", "random")
# The context a method is given (``map_context``): True informative, "chain", False uninformative.
ContextKind = bool | Literal["chain"]
# A method: (map, ordering of its terrains, context, the context's (preferred, other) terrain pairs) ->
# costmap in [0, 1], or None when it cannot take the preference at all (the classifier on unseen terrain).
Method = Callable[[AerialMap, np.ndarray, np.ndarray, np.ndarray], np.ndarray | None]


@dataclass(frozen=True)
class NavigationResult:
    """Tables I-IV for one set of maps and one preference: ``rows`` (mean tier shares over maps with
    bootstrap 95% intervals, ``<tier>_ci``), ``shares[method]`` (maps, 3) per-map mean shares of
    (low, medium, high), or None for a method that cannot take the preference, and ``paths[method]``
    each map's first A* path."""

    rows: list[dict]
    shares: dict[str, np.ndarray | None]
    paths: dict[str, list[np.ndarray]]


@dataclass(frozen=True)
class ContextRun:
    """One preference on one map: its context, the method's costmap and the A* path it plans (None where
    the goal cannot be reached)."""

    preference: str
    ordering: np.ndarray
    context: np.ndarray
    cost: np.ndarray
    path: np.ndarray | None


def context_runs(method: Method, amap: AerialMap, bank: TerrainBank, data: PacerDataParams,
                 preferences: Sequence[str], seed: int, cost_scale: float) -> list[ContextRun]:
    """The map costed and crossed (its own start to goal) under each preference's informative context.

    Realistic and inverted are drawn as the tables draw them for the map (``map_context(..., index=0)``, the
    first map's draw); each "random" entry is the next draw whose ordering no earlier entry has (a map of 3
    terrains has 6 orderings: a random one could repeat the realistic one), so the figure shows distinct
    preferences."""
    runs: list[ContextRun] = []
    draw = 0
    for preference in preferences:
        while True:
            index = draw if preference == "random" else 0
            ordering, context, pairs = map_context(bank, data, amap, preference, True, seed, index)
            draw += preference == "random"
            if preference != "random" or all(not np.array_equal(ordering, r.ordering) for r in runs) or draw > 100:
                break
        cost = method(amap, ordering, context, pairs)
        runs.append(ContextRun(preference, ordering, context, cost,
                               plan_on_costmap(cost, amap.start, amap.goal, cost_scale).cells))
    return runs


def bev_context_costmaps(model: torch.nn.Module, datasets: Mapping[str, Dataset], min_terrains: int = 3,
                         device: str = "cpu") -> list[tuple[str, dict, np.ndarray]]:
    """(preference, item, predicted costmap) for the first item index whose field of view shows at least
    ``min_terrains`` terrains, the same index in every dataset (Fig. 3: one image, contexts that differ)."""
    first = next(iter(datasets.values()))
    index = next(i for i, item in enumerate(first)
                 if len(np.unique(item["labels"][item["fov_mask"]])) >= min_terrains)
    out = []
    for name, dataset in datasets.items():
        item = dataset[index]
        cost = model.costmap(item["image"][None].to(device), item["context"][None].to(device))[0].cpu().numpy()
        out.append((name, item, cost))
    return out


def heldout_bev_params(params: Params) -> Params:
    """``params`` with every BEV item procedural (``street_windows`` 0): the held-out BEV sets the pair agreement
    and the figures are drawn from (``datasets.evaluation_dataset``) stay the paper's kind of item, the same
    whatever share of training items are street windows; the street layouts are what the map tables and the
    map windows test."""
    data = params.pacer.data
    data = dataclasses.replace(data, layout=dataclasses.replace(data.layout, street_windows=0.0))
    return dataclasses.replace(params, pacer=dataclasses.replace(params.pacer, data=data))


def map_context(bank: TerrainBank, data: PacerDataParams, amap: AerialMap, preference: Preference,
                informative: ContextKind, seed: int, index: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(hidden ordering of the map's terrains, preference context, its terrain pairs) for one map and
    preference.

    Informative (True): the operator's pairs cover every terrain of the map where ``n_pairs`` allows (a
    superset of whatever a BEV window shows). ``"chain"``: a chain t1 > t2 > ... of consecutive terrains
    of the ordering (``context.chain_pairs``), which decides more pairs. Uninformative (False, questions
    1b/2b): terrains of the other group (seen ↔ unseen) only, so it says nothing about this map.
    """
    gen = rng(seed, "pacer.navigation.context", preference, informative, index)
    ordering = order_terrains(amap.terrains, preference, bank, gen)
    if informative == "chain":
        pairs = chain_pairs(ordering, data.n_pairs, gen)
        context = pair_context(bank, pairs, gen, data)
    elif informative:
        context, pairs = preference_context(bank, ordering, gen, data)
    else:
        group = bank.terrains[int(amap.terrains[0])].group
        context, pairs = uninformative_context(bank, group, preference, gen, data)
    return ordering, context, pairs


def pacer_method(model: torch.nn.Module, data: PacerDataParams, device: str = "cpu") -> Method:
    mask = fov_mask(data.image_size, data.camera.near_width)
    return lambda amap, ordering, context, pairs: costmap_over_map(
        model, torch.as_tensor(amap.image), torch.as_tensor(context), mask, device=device).numpy()


def window_oracle_method(data: PacerDataParams) -> Method:
    """Reference row (ceiling): every BEV window costed exactly as its training target, stitched as PACER's."""
    mask = fov_mask(data.image_size, data.camera.near_width)
    return lambda amap, ordering, context, pairs: window_oracle_costmap(amap.labels, ordering, mask,
                                                                 target=data.train_target).numpy()


def uniform_method() -> Method:
    """Reference row (chance): the same cost everywhere, i.e. the plain shortest path."""
    return lambda amap, ordering, context, pairs: np.zeros(amap.labels.shape, dtype=np.float32)


def sterling_method(encoder: SterlingEncoder, steps: int) -> Method:
    def cost(amap, ordering, context, pairs):
        utility = encoder.fit_utility(torch.as_tensor(context), steps)
        return encoder.costmap(torch.as_tensor(amap.image), utility).numpy()
    return cost


def classifier_method(classifier: SemanticClassifier, bank: TerrainBank, preference: Preference) -> Method:
    """Costs from a label table: the preference ranks the classifier's own (seen) labels; None elsewhere."""
    known = np.asarray(classifier.labels)
    ordering = order_terrains(known, preference, bank, rng(0, "pacer.classifier"))  # fixed orderings draw nothing
    table = dict(zip(ordering.tolist(), rank_costs(ordering).tolist()))

    def cost(amap, _ordering, _context, _pairs):
        if not np.isin(amap.terrains, known).all():
            return None
        return classifier.costmap(torch.as_tensor(amap.image), table).numpy()
    return cost


def terrain_costmap(labels: np.ndarray, cost_of: Mapping[int, float]) -> np.ndarray:
    """float32 costs of the shape of ``labels``: each pixel its terrain's entry of ``cost_of`` (the reference rows
    that cost a map terrain by terrain). One look-up per distinct terrain, not per pixel."""
    terrains, index = np.unique(labels, return_inverse=True)
    missing = [t for t in terrains.tolist() if t not in cost_of]
    if missing:
        raise ValueError(f"labels hold terrains {missing} that have no cost (priced: {sorted(cost_of)}); "
                         "give every terrain of the map a cost")
    return np.asarray([cost_of[t] for t in terrains.tolist()], dtype=np.float32)[index].reshape(labels.shape)


def context_limited_oracle_method() -> Method:
    """Reference row: what a perfect follower of the context with no prior can reach. Each terrain of the
    map costs its mean rank over every ordering of the map's terrains consistent with the context's
    pairs (``preferences.context_limited_costs``); pairs the context leaves open average out."""
    def cost(amap, _ordering, _context, pairs):
        terrains = np.asarray(amap.terrains, dtype=np.int64)
        return terrain_costmap(amap.labels, dict(zip(terrains.tolist(), context_limited_costs(terrains, pairs).tolist())))
    return cost


def ground_truth_method() -> Method:
    return lambda amap, ordering, context, pairs: target_costmap(amap.labels, ordering)


def navigation_rows(maps: Sequence[AerialMap], methods: Mapping[str, tuple[Method, ContextKind]], bank: TerrainBank,
                    data: PacerDataParams, preference: Preference, cost_scale: float, seed: int,
                    queries_per_map: int = 1) -> NavigationResult:
    """Tables I-IV: each method's A* paths on ``maps`` scored by the tiers of each map's own ordering.

    Each map is costed once per method and crossed ``queries_per_map`` times: its own start-goal pair,
    then extra crossings drawn the same way (seeded by map index). A map's share is the mean over its
    crossings; a row is the mean over maps with a bootstrap 95% interval over maps. ``methods`` maps a
    name to (method, context kind: True informative, "chain", False uninformative; ``map_context``). A method that returns None on any map gets a row of None
    (it cannot express this preference).
    """
    queries = [[(amap.start, amap.goal)] + crossing_queries(amap.labels.shape[0], queries_per_map - 1,
                                                            rng(seed, "pacer.navigation.queries", index))
               for index, amap in enumerate(maps)]
    rows, shares, paths = [], {}, {}
    for name, (method, informative) in methods.items():
        per_map, paths[name] = [], []
        for index, amap in enumerate(maps):
            ordering, context, pairs = map_context(bank, data, amap, preference, informative, seed, index)
            costmap = method(amap, ordering, context, pairs)
            if costmap is None:
                per_map = None
                break
            tiers = environment_tiers(ordering, len(bank))
            crossings = []
            for k, (start, goal) in enumerate(queries[index]):
                path = plan_on_costmap(costmap, start, goal, cost_scale)
                if k == 0:
                    paths[name].append(path.cells)
                found = cost_tier_proportions(path.cells, amap.labels, tiers)
                crossings.append([found[t] for t in TIER_NAMES])
            per_map.append(np.mean(crossings, axis=0))
        shares[name] = None if per_map is None else np.asarray(per_map)
        rows.append(tier_row(name, shares[name], rng(seed, "pacer.navigation.ci", name, preference)))
    return NavigationResult(rows, shares, paths)


def rounded(ci: tuple[float, float] | None) -> list[float] | None:
    """An interval as report rows store it: [lo, hi] to 4 decimals (None stays None)."""
    return None if ci is None else [round(float(v), 4) for v in ci]


def tier_row(name: str, per_map: np.ndarray | None, gen: np.random.Generator) -> dict:
    """{"method", low, medium, high, low_ci, ...}: means over maps and their bootstrap 95% intervals;
    ``per_map`` (maps, 3), or (seeds, maps, 3) for a model trained under several seeds: the mean over seeds and
    maps with the crossed seeds x maps interval (``metrics.crossed``)."""
    row: dict = {"method": name}
    for k, tier in enumerate(TIER_NAMES):
        row[tier] = None if per_map is None else float(per_map[..., k].mean())
    for k, tier in enumerate(TIER_NAMES):
        row[f"{tier}_ci"] = (None if per_map is None else
                             rounded(crossed.interval(per_map[..., k], gen) if per_map.ndim == 3 else
                                     bootstrap_mean_ci(per_map[:, k], gen)))
    return row


def seed_member(name: str, seed: int) -> str:
    """The method name of one training seed's model, before ``merge_seeds`` joins them into ``name``."""
    return f"{name} [seed {seed}]"


def merge_seeds(result: NavigationResult, models: Mapping[str, Sequence[int]], seed: int,
                preference: Preference) -> NavigationResult:
    """Each model of ``models`` (name -> its training seeds, each run as the method ``seed_member(name, s)``) as
    one row: shares (seeds, maps, 3), the mean over seeds and maps with the crossed interval, the first seed's
    paths (the main model's). Each seed's own shares stay under its member name (one seed's diagnostics read
    them). ``seed``: the evaluation seed keying the intervals, as ``navigation_rows``."""
    shares, paths = dict(result.shares), dict(result.paths)
    rows = {row["method"]: row for row in result.rows}
    for name, seeds in models.items():
        members = [seed_member(name, s) for s in seeds]
        shares[name] = np.stack([shares[m] for m in members])
        paths[name] = paths.pop(members[0])
        for m in members[1:]:
            paths.pop(m)
        rows[members[0]] = tier_row(name, shares[name], rng(seed, "pacer.navigation.ci", name, preference))
        for m in members[1:]:
            rows.pop(m)
    return NavigationResult(list(rows.values()), shares, paths)


@dataclass(frozen=True)
class Agreement:
    """Held-out pair agreement: ``fraction`` of ``pairs`` context pairs (both terrains in view) whose
    preferred terrain gets the lower mean predicted cost, with a bootstrap 95% interval over items."""

    fraction: float
    pairs: int
    ci: tuple[float, float] | None


@torch.no_grad()
def preference_agreement(model: torch.nn.Module, dataset: Dataset, count: int, seed: int,
                         device: str = "cpu") -> Agreement:
    """How often, over ``count`` items, the terrain a context pair prefers gets the lower mean predicted
    cost. The interval resamples items (the pairs of one image are not independent)."""
    model.eval()
    per_item = []
    for i in range(min(count, len(dataset))):
        item = dataset[i]
        pred = model.costmap(item["image"][None].to(device), item["context"][None].to(device))[0].cpu().numpy()
        per_item.append(context_pair_agreement(pred, np.asarray(item["labels"]), np.asarray(item["fov_mask"]),
                                               np.asarray(item["pairs"])))
    counts = np.asarray(per_item, dtype=np.float64).reshape(-1, 2)
    compared = int(counts[:, 1].sum())
    if compared == 0:
        return Agreement(float("nan"), 0, None)
    ci = bootstrap_ratio_ci(counts[:, 0], counts[:, 1], rng(seed, "pacer.agreement.ci"))
    return Agreement(float(counts[:, 0].sum() / compared), compared, ci)


@torch.no_grad()
def margin_ranking_errors(model: torch.nn.Module, dataset: Dataset, count: int, points: int, seed: int,
                          device: str = "cpu") -> np.ndarray:
    """Table V's per-item margin ranking errors of ``model`` on the first ``count`` items of ``dataset``,
    ``points`` sampled pixels each, the points of item i seeded by i alone (so every model is scored on the
    same points: the claims pair by item; ``tables.margin_rows`` makes the table's means and intervals)."""
    model.eval()
    errors = []
    for i in range(min(count, len(dataset))):
        item = dataset[i]
        pred = model.costmap(item["image"][None].to(device), item["context"][None].to(device))[0].cpu().numpy()
        errors.append(margin_ranking_error(pred, np.asarray(item["labels"]), np.asarray(item["ordering"]), points,
                                           rng=rng(seed, "pacer.margin_ranking", i)))
    return np.asarray(errors)


NAVIGATION_COLUMNS = ["method", "low", "medium", "high", "low_ci", "medium_ci", "high_ci"]
PHASE_COLUMNS = ["preference", "model", "low", "medium", "high", "low_ci", "medium_ci", "high_ci"]
AGREEMENT_COLUMNS = ["model", "set", "context", "agreement", "agreement_ci", "pairs",
                     *[c for m in METRICS for c in (m, f"{m}_ci")], "windows", "maps", "low_share", "low_share_ci",
                     "best_val_loss", "best_select_score", "select_on", "entropy_floor", "best_epoch", "epochs_run"]


def phase_rows(results: Mapping[Preference, NavigationResult]) -> list[dict]:
    """Tables III-IV: one row per (preference, model) from the per-preference navigation results."""
    return [{"preference": preference, "model": row["method"], **{k: v for k, v in row.items() if k != "method"}}
            for preference, result in results.items() for row in result.rows]


def protocol_note(data: PacerDataParams, evaluation, profile: str) -> str:
    """The navigation protocol in one sentence, for every table's notes."""
    return (f"{data.aerial.maps} rendered {data.aerial.size}x{data.aerial.size}-pixel aerial maps per environment "
            f"group ({evaluation.queries_per_map} start-goal crossings each, averaged per map) instead of drone / "
            f"OpenAerialMap imagery; tiers are the low / medium / high thirds of the hidden ordering of each map's "
            f"own terrains; every cell is a mean over maps with a bootstrap 95% interval over maps (`<tier>_ci`). "
            f"Costmaps are stitched from BEV-window predictions over the whole map and planned once with A* (cost "
            f"per metre 1 + {evaluation.cost_scale:g}·c), not re-planned from each robot pose; the window oracle "
            f"(every window costed exactly as its training target, stitched the same way) is this protocol's "
            f"ceiling, the uniform costmap (plain shortest path) its chance level. Operator contexts name every "
            f"terrain of the map where {data.n_pairs} pairs allow. Models: `{profile}` profile.{recolour_note(data)}")


def recolour_note(data: PacerDataParams) -> str:
    """D_synthetic's recoloured terrains, a training addition of ours (``pacer.recolour``), said where it is on."""
    r = data.recolour
    if r.probability == 0.0:
        return ""
    return (f" D_synthetic adds to the paper's texture replacement (each terrain a synthetic texture with chance "
            f"{data.synthetic_replace:g}) a recolouring of ours: each terrain of an item, with chance {r.probability:g}, "
            f"goes through one random colour map (hue turned about the grey axis, saturation x U{list(r.saturation)}, or "
            f"grey with chance {r.grey:g}), the same on its pixels and its context patches, so that texture rather than a "
            f"photograph's colour ties a patch to its terrain (`navlab.pacer.recolour`).")


def context_following_rows(models: Mapping[str, torch.nn.Module], sets: Mapping[tuple[str, str, str], Dataset],
                           summaries: Mapping[str, dict], count: int, seed: int, device: str = "cpu", *,
                           windows: Mapping[tuple[str, str], Sequence[MapWindow]] | None = None,
                           cost_scale: float = 10.0,
                           ) -> tuple[list[dict], dict[tuple[str, str, str, str], Agreement]]:
    """The ``context_following`` report: held-out pair agreement of every model on every
    (terrains, preference, context draw) set, and one row per model with its best validation loss
    beside the entropy floor of its validation targets (``summaries``: the phases' summary.json) and,
    where it was selected on them, its best map-window score.

    ``windows`` ((terrains, preference) -> map windows of training geography, ``map_windows``): one more
    row per model and set with the map-window metrics (``map_windows.METRICS``: all-pairs agreement,
    decided and open by the context, pixel-pair AUC, tier cost ratio at ``cost_scale``), each with its
    bootstrap 95% interval over windows."""
    rows, found = [], {}
    for name, model in models.items():
        summary = summaries[name]
        rows.append({"model": name, "set": "validation loss", "context": "training draw",
                     "best_val_loss": summary["best_val_loss"], "entropy_floor": summary["entropy_floor"],
                     "best_epoch": summary["best_epoch"], "epochs_run": summary["epochs_run"],
                     "select_on": summary.get("select_on", "val_loss"),
                     "best_select_score": summary.get("best_select_score")})
        for (terrains, preference, context), dataset in sets.items():
            agreement = preference_agreement(model, dataset, count, seed, device)
            found[name, terrains, preference, context] = agreement
            rows.append({"model": name, "set": f"{terrains}/{preference}", "context": context,
                         "agreement": agreement.fraction, "pairs": agreement.pairs,
                         "agreement_ci": rounded(agreement.ci)})
        for (terrains, preference), items in (windows or {}).items():
            scores = window_scores(model, items, cost_scale, seed, device=device)
            row = {"model": name, "set": f"{terrains}/{preference}", "context": "map windows",
                   "windows": len(items), "pairs": scores.counts["all_pairs"]}
            for metric in METRICS:
                ci = scores.cis[metric]
                row |= {metric: scores.values[metric], f"{metric}_ci": rounded(ci)}
            rows.append(row)
    return rows, found


def chain_context_rows(model: str, maps: Mapping[str, Sequence[AerialMap]], method: Method, bank: TerrainBank,
                       data: PacerDataParams, evaluation, seed: int,
                       random: Mapping[tuple[str, Preference], NavigationResult] | None = None) -> list[dict]:
    """``context_following`` rows: on held-out maps (``maps``: terrains -> the evaluation maps), the
    low-tier share of ``method`` (the model named ``model``) given a chain context (t1 > t2, t2 > t3, t3 >
    t4 of the map's ordering, ``context.chain_pairs``) against the random-pair context the tables give it,
    on the same maps, orderings and crossings; three rows per set (random, chain, chain - random with a
    paired bootstrap 95% interval over maps). ``random``: the tables' navigation results, whose
    ``shares[model]`` are reused as the random-pair side (recomputed where absent)."""
    rows = []
    for terrains, env_maps in maps.items():
        for preference in ("realistic", "inverted"):
            methods: dict[str, tuple[Method, ContextKind]] = {"chain": (method, "chain")}
            known = (random or {}).get((terrains, preference))
            if known is None or known.shares.get(model) is None:
                methods["random"] = (method, True)
            result = navigation_rows(env_maps, methods, bank, data, preference, evaluation.cost_scale, seed,
                                     evaluation.queries_per_map)
            low = {"chain": result.shares["chain"][:, 0],
                   "random": (result.shares["random"] if "random" in methods else known.shares[model])[:, 0]}
            difference = low["chain"] - low["random"]
            ci = bootstrap_mean_ci(difference, rng(seed, "pacer.chain_context.ci", terrains, preference))
            for label, values, interval in (
                    ("random pairs (maps)", low["random"], bootstrap_mean_ci(low["random"], rng(seed, "pacer.chain_context.ci", terrains, preference, "random"))),
                    ("chain (maps)", low["chain"], bootstrap_mean_ci(low["chain"], rng(seed, "pacer.chain_context.ci", terrains, preference, "chain"))),
                    ("chain - random pairs (maps)", difference, ci)):
                rows.append({"model": model, "set": f"{terrains}/{preference}", "context": label,
                             "maps": len(values), "low_share": float(np.mean(values)),
                             "low_share_ci": rounded(interval)})
    return rows
