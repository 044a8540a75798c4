"""Map windows: BEV windows of evaluation-style maps built from training geography, and how well a
costmap model orders the terrains in them (issue 24, "a selection metric that tracks navigation").

Named-pair agreement on BEV items (``experiments.preference_agreement``) does not predict navigation:
the robot plans on windows of street maps (thin sidewalks and strips, 3-5 terrains per map, a context
written for the whole map), and is hurt by every terrain pair in view, not only those the context
names. A *map window* is one such window, made exactly as an evaluation map's window is (a window of a
SuReNav street map, each semantic label one of the map's 3-5 terrains, rendered top-down like the
aerial maps, masked by the field of view) but cut from SuReNav's train/val maps
(``datasets.STREET_SPLIT``), never the test tiles the evaluation maps come from. Its context is the
map's: ``n_pairs`` pairs over all the map's terrains, as ``experiments.map_context`` draws it.

Metrics (:func:`window_scores`), each a ratio of per-window sums with a bootstrap 95% interval over
windows (``bootstrap_ratio_ci``):

- ``all_pairs``: every pair of distinct terrains in view ordered right by their mean predicted cost,
  split into ``decided`` (the context's pairs imply the order by transitivity,
  ``preferences.implied_pairs``) and ``open`` (it does not: only a learned prior can order them);
- ``auc``: pixel-pair AUC, the chance that a random pixel of the preferred terrain of a pair in view is
  cheaper than one of the other (ties count one half), averaged over the pairs the full ordering decides
  (every pair in view);
- ``tier_ratio``: mean predicted cost of the medium and high tiers over that of the low tier
  (``preferences.environment_tiers`` of the map's ordering) in the planner's units, cost per metre
  1 + cost_scale · c (``evaluate.plan_on_costmap``): pooled over windows that show both.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import torch
from scipy.stats import rankdata

from navlab.core.params import Params
from navlab.core.params.pacer import PacerDataParams
from navlab.core.seeding import rng as seeded_rng
from navlab.maps.dataset import load_maps
from navlab.maps.semantic_map import SemanticMap
from navlab.metrics.intervals import bootstrap_ratio_ci
from navlab.pacer.aerial import semantic_map_regions
from navlab.pacer.bev import fov_mask, render_aerial
from navlab.pacer.context import preference_context
from navlab.pacer.datasets import STREET_SPLIT, Split
from navlab.pacer.preferences import IGNORE, environment_tiers, implied_pairs, order_terrains
from navlab.pacer.terrain import TerrainBank, load_terrain_bank

METRICS = ("all_pairs", "decided", "open", "auc", "tier_ratio")
# what checkpoint selection maximises (pacer.train.select_on: map_windows), see ``selection_score``
SELECTION_METRIC = "auc"


@dataclass(frozen=True, eq=False)
class MapWindow:
    image: np.ndarray  # float32 (3, S, S) in [0, 1], zero outside the field of view
    labels: np.ndarray  # int64 (S, S) terrain ids, IGNORE outside the field of view
    ordering: np.ndarray  # int64 (L,): the map's terrains (not only those in view), most preferred first
    context: np.ndarray  # float32 (3n, 2h, w): the map's preference context
    pairs: np.ndarray  # int64 (n, 2): its (preferred, other) terrain pairs


def map_window(bank: TerrainBank, data: PacerDataParams, street_maps: Sequence[SemanticMap],
               terrains: Literal["seen", "unseen"], preference: Literal["realistic", "inverted"],
               rng: np.random.Generator) -> MapWindow:
    """One window, drawn as ``aerial.aerial_map`` draws a map (its terrain count and label painting) at the
    BEV size, rendered by ``render_aerial`` and masked by the field of view, with the map's context."""
    regions = semantic_map_regions(street_maps, data.image_size, rng, data.layout.street_zoom)
    group = bank.ids(terrains)
    count = int(rng.integers(data.aerial.terrains[0], min(data.aerial.terrains[1], len(group)) + 1))
    chosen = rng.choice(group, size=count, replace=False)
    n_regions = int(regions.max()) + 1
    region_terrains = np.concatenate([rng.permutation(chosen), rng.choice(chosen, size=max(0, n_regions - count))])
    terrain_map = region_terrains[:n_regions][regions]
    mask = fov_mask(data.image_size, data.camera.near_width)
    image = render_aerial(terrain_map, bank, rng, data) * mask[:, :, None]
    ordering = order_terrains(chosen, preference, bank, rng)
    context, pairs = preference_context(bank, ordering, rng, data)
    return MapWindow(np.ascontiguousarray(image.transpose(2, 0, 1)), np.where(mask, terrain_map, IGNORE).astype(np.int64),
                     ordering, context, pairs)


def map_windows(params: Params, data_dir: str | Path, split: Split, terrains: Literal["seen", "unseen"],
                preferences: Sequence[Literal["realistic", "inverted"]], count: int,
                bank: TerrainBank | None = None) -> list[MapWindow]:
    """``count`` windows of the ``split`` geography (``STREET_SPLIT``: train/val maps only), the
    preferences taking turns; window k is seeded by (seed, "pacer.map_windows", split, terrains, k), so a
    set is the same on every machine and epoch (checkpoint selection uses ``val``, reports ``test``)."""
    data = params.pacer.data
    bank = bank if bank is not None else load_terrain_bank(data_dir, data)
    street_maps = load_maps(data_dir, STREET_SPLIT[split])
    return [map_window(bank, data, street_maps, terrains, preferences[k % len(preferences)],
                       seeded_rng(params.pacer.seed, "pacer.map_windows", split, terrains, k))
            for k in range(count)]


@torch.no_grad()
def predict_windows(model: torch.nn.Module, windows: Sequence[MapWindow], *, batch: int = 32,
                    device: str | torch.device = "cpu") -> np.ndarray:
    """float32 (N, S, S): the model's costs of every window under its context (eval mode)."""
    model.eval()
    out = []
    for start in range(0, len(windows), batch):
        chunk = windows[start:start + batch]
        image = torch.from_numpy(np.stack([w.image for w in chunk])).to(device)
        context = torch.from_numpy(np.stack([w.context for w in chunk])).to(device)
        out.append(model.costmap(image, context).float().cpu().numpy())
    return np.concatenate(out) if out else np.zeros((0, 0, 0), np.float32)


def window_counts(predicted: np.ndarray, window: MapWindow, cost_scale: float) -> np.ndarray:
    """float64 (10,): one window's (numerator, denominator) of every metric in ``METRICS`` order. The
    denominators count pairs in view (all, decided, open, all again for the AUC); tier_ratio's is
    1 + cost_scale · mean low-tier cost and its numerator that of the other tiers (both 0 unless the
    window shows a low-tier terrain and another)."""
    labels = window.labels
    in_view = set(np.unique(labels[labels != IGNORE]).tolist())
    ordered = [int(t) for t in window.ordering if int(t) in in_view]  # in view, most preferred first
    decided = implied_pairs(np.asarray(ordered, dtype=np.int64), window.pairs)
    pixels = [predicted[labels == t] for t in ordered]
    means = [p.mean() for p in pixels]
    out = np.zeros(10)
    for i in range(len(ordered)):
        for j in range(i + 1, len(ordered)):
            right = float(means[i] < means[j])
            k = 2 if decided[i, j] else 4
            out[[0, 1, k, k + 1]] += (right, 1.0, right, 1.0)
            ranks = rankdata(np.concatenate([pixels[i], pixels[j]]))  # Mann-Whitney U of j's pixels above i's
            n_i, n_j = len(pixels[i]), len(pixels[j])
            out[6] += (ranks[n_i:].sum() - n_j * (n_j + 1) / 2) / (n_i * n_j)
            out[7] += 1.0
    tiers = environment_tiers(window.ordering, int(window.ordering.max()) + 1)
    view = labels != IGNORE
    tier = np.where(view, tiers[np.where(view, labels, 0)], -1)
    low, rest = tier == 0, tier > 0
    if low.any() and rest.any():
        out[8] = 1.0 + cost_scale * float(predicted[rest].mean())
        out[9] = 1.0 + cost_scale * float(predicted[low].mean())
    return out


@dataclass(frozen=True)
class WindowScores:
    """Each metric of ``METRICS`` over a set of windows: ``values[m]`` (None where no window counts),
    ``cis[m]`` its bootstrap 95% interval over windows, ``counts[m]`` how many pairs (tier_ratio: windows)
    it pools; ``per_window`` the (N, 10) counts it came from."""

    values: dict[str, float | None]
    cis: dict[str, tuple[float, float] | None]
    counts: dict[str, int]
    per_window: np.ndarray


def window_scores(model: torch.nn.Module, windows: Sequence[MapWindow], cost_scale: float, seed: int, *,
                  intervals: bool = True, batch: int = 32, device: str | torch.device = "cpu") -> WindowScores:
    """Every metric of ``METRICS`` of ``model`` on ``windows`` (see the module docstring)."""
    predicted = predict_windows(model, windows, batch=batch, device=device)
    per_window = np.asarray([window_counts(p, w, cost_scale) for p, w in zip(predicted, windows)]).reshape(-1, 10)
    values, cis, counts = {}, {}, {}
    for k, name in enumerate(METRICS):
        num, den = per_window[:, 2 * k], per_window[:, 2 * k + 1]
        counts[name] = int((den > 0).sum()) if name == "tier_ratio" else int(den.sum())
        values[name] = float(num.sum() / den.sum()) if den.sum() > 0 else None
        cis[name] = (bootstrap_ratio_ci(num, den, seeded_rng(seed, "pacer.map_windows.ci", name))
                     if intervals and den.sum() > 0 else None)
    return WindowScores(values, cis, counts, per_window)


def selection_score(model: torch.nn.Module, windows: Sequence[MapWindow], cost_scale: float, *,
                    batch: int = 32, device: str | torch.device = "cpu") -> float:
    """What ``pacer.train.select_on: map_windows`` keeps the best checkpoint by: the pixel-pair AUC on the
    validation windows. AUC rather than all-pairs agreement because the planner walks over pixels, not
    terrain means: it rewards costs that separate two terrains pixel by pixel (noise and compressed levels
    lower it, as they lower the low-tier share), it counts the open pairs as well as the decided ones, and
    it is continuous, so epochs seldom tie on it (ties fall back to the validation loss)."""
    value = window_scores(model, windows, cost_scale, 0, intervals=False, batch=batch, device=device).values
    return float("nan") if value[SELECTION_METRIC] is None else value[SELECTION_METRIC]
