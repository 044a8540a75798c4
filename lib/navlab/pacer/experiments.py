"""The measurements behind PACER's Tables I-V, as functions the notebooks call.

- Navigation (Tables I-IV): on each rendered aerial map, every method costs the map under one
  preference (realistic or inverted), A* plans from the map's start to its goal, and the path is
  scored by the share of its cells on low / medium / high tiers of the hidden ordering.
  Each method receives the preference in its own form (Sec. VI): PACER and STERLING a preference
  context of terrain patches, the classifier a label → cost table, ground truth the ordering itself.
- Margin ranking error (Table V) and the held-out preference agreement on BEV test items.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Literal

import numpy as np
import torch
from torch.utils.data import Dataset

from navlab.core.params.pacer import PacerDataParams
from navlab.core.seeding import rng
from navlab.metrics.cost_tiers import TIER_NAMES, cost_tier_proportions
from navlab.metrics.margin_ranking import margin_ranking_error
from navlab.pacer.aerial import AerialMap
from navlab.pacer.baselines.semantic_classifier import SemanticClassifier
from navlab.pacer.baselines.sterling import SterlingEncoder
from navlab.pacer.bev import fov_mask
from navlab.pacer.context import preference_context, uninformative_context
from navlab.pacer.evaluate import context_pair_agreement, costmap_over_map, crossing_queries, plan_on_costmap
from navlab.pacer.preferences import order_terrains, rank_costs, target_costmap
from navlab.pacer.terrain import TerrainBank

Preference = Literal["realistic", "inverted"]
# A method: (map, ordering of its terrains, context) -> costmap in [0, 1], or None when it cannot take
# the preference at all (the classifier on unseen terrain).
Method = Callable[[AerialMap, np.ndarray, np.ndarray], np.ndarray | None]


def map_context(bank: TerrainBank, data: PacerDataParams, amap: AerialMap, preference: Preference,
                informative: bool, seed: int, index: int) -> tuple[np.ndarray, np.ndarray]:
    """(ordering of the map's terrains, preference context) for one map and preference.

    Informative: the context's pairs come from the map's own terrains. Uninformative (questions 1b/2b):
    from terrains of the other group (seen ↔ unseen), so it says nothing about this map.
    """
    gen = rng(seed, "pacer.navigation.context", preference, informative, index)
    ordering = order_terrains(amap.terrains, preference, bank, gen)
    if informative:
        context, _ = preference_context(bank, ordering, gen, data)
    else:
        group = bank.terrains[int(amap.terrains[0])].group
        context, _ = uninformative_context(bank, group, preference, gen, data)
    return ordering, context


def pacer_method(model: torch.nn.Module, data: PacerDataParams, device: str = "cpu") -> Method:
    mask = fov_mask(data.image_size, data.camera.near_width)
    return lambda amap, ordering, context: costmap_over_map(
        model, torch.as_tensor(amap.image), torch.as_tensor(context), mask, device=device).numpy()


def sterling_method(encoder: SterlingEncoder, steps: int) -> Method:
    def cost(amap, ordering, context):
        utility = encoder.fit_utility(torch.as_tensor(context), steps)
        return encoder.costmap(torch.as_tensor(amap.image), utility).numpy()
    return cost


def classifier_method(classifier: SemanticClassifier, bank: TerrainBank, preference: Preference) -> Method:
    """Costs from a label table: the preference ranks the classifier's own (seen) labels; None elsewhere."""
    known = np.asarray(classifier.labels)
    ordering = order_terrains(known, preference, bank, rng(0, "pacer.classifier"))  # fixed orderings draw nothing
    table = dict(zip(ordering.tolist(), rank_costs(ordering).tolist()))

    def cost(amap, _ordering, _context):
        if not np.isin(amap.terrains, known).all():
            return None
        return classifier.costmap(torch.as_tensor(amap.image), table).numpy()
    return cost


def ground_truth_method() -> Method:
    return lambda amap, ordering, context: target_costmap(amap.labels, ordering)


def navigation_rows(maps: Sequence[AerialMap], methods: Mapping[str, tuple[Method, bool]], bank: TerrainBank,
                    data: PacerDataParams, preference: Preference, tiers: np.ndarray, cost_scale: float,
                    seed: int, queries_per_map: int = 1) -> tuple[list[dict], dict[str, list[np.ndarray]]]:
    """One row per method: mean tier shares of its A* paths over ``maps``; also each method's first path per map.

    Each map is costed once per method and crossed ``queries_per_map`` times: its own start-goal pair,
    then extra crossings drawn the same way (seeded by map index). ``methods`` maps a name to (method,
    informative context?). A method that returns None on any map gets a row of None (it cannot
    express this preference).
    """
    queries = [[(amap.start, amap.goal)] + crossing_queries(amap.labels.shape[0], queries_per_map - 1,
                                                            rng(seed, "pacer.navigation.queries", index))
               for index, amap in enumerate(maps)]
    rows, paths = [], {}
    for name, (method, informative) in methods.items():
        shares, paths[name] = [], []
        for index, amap in enumerate(maps):
            ordering, context = map_context(bank, data, amap, preference, informative, seed, index)
            costmap = method(amap, ordering, context)
            if costmap is None:
                shares = None
                break
            for k, (start, goal) in enumerate(queries[index]):
                path = plan_on_costmap(costmap, start, goal, cost_scale)
                if k == 0:
                    paths[name].append(path.cells)
                shares.append(cost_tier_proportions(path.cells, amap.labels, tiers))
        row = {"method": name}
        for tier in TIER_NAMES:
            row[tier] = None if shares is None else float(np.mean([s[tier] for s in shares]))
        rows.append(row)
    return rows, paths


@torch.no_grad()
def preference_agreement(model: torch.nn.Module, dataset: Dataset, count: int, device: str = "cpu") -> tuple[float, int]:
    """(fraction, pairs): over ``count`` items, how often the terrain a context pair prefers gets the lower
    mean predicted cost (pairs with both terrains in view)."""
    model.eval()
    agree = compared = 0
    for i in range(min(count, len(dataset))):
        item = dataset[i]
        pred = model.costmap(item["image"][None].to(device), item["context"][None].to(device))[0].cpu().numpy()
        a, c = context_pair_agreement(pred, np.asarray(item["labels"]), np.asarray(item["fov_mask"]),
                                      np.asarray(item["pairs"]))
        agree, compared = agree + a, compared + c
    return (agree / compared if compared else float("nan")), compared


@torch.no_grad()
def mean_margin_ranking_error(model: torch.nn.Module, dataset: Dataset, count: int, points: int, seed: int,
                              device: str = "cpu") -> float:
    """Table V: margin ranking error of ``points`` sampled pixels per costmap, mean over ``count`` items."""
    model.eval()
    errors = []
    for i in range(min(count, len(dataset))):
        item = dataset[i]
        pred = model.costmap(item["image"][None].to(device), item["context"][None].to(device))[0].cpu().numpy()
        errors.append(margin_ranking_error(pred, np.asarray(item["labels"]), np.asarray(item["ordering"]), points,
                                           rng=rng(seed, "pacer.margin_ranking", i)))
    return float(np.mean(errors))
