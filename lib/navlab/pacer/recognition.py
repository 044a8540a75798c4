"""Does the texture matcher recognise the evaluation maps' terrains? (issue 24's diagnosis, measured every run)

PACER's costs follow its matcher: a costmap made from the matcher's preference evidence alone closes as much
of the uniform-to-oracle gap as the whole network, and neither a transitive reading of the pairs nor a
matching loss moved it (benchmarks/README.md, "PACER variants"). What the robot's path then depends on is
whether the matcher's attention, at each map location, peaks on a context patch of the terrain that is
really there. This module measures exactly that on the held-out aerial maps, beside the score of always
naming the map's commonest context terrain (what a matcher that tells nothing apart can reach): a
recognition rate near that baseline means the context cannot steer the costmap, whatever the pairs say.

The cosines are the matcher's own (``TextureMatcher.embed``, centred on the context's patch features and
L2-normalised; a pooled tower's image features locally averaged over 3 x 3 cells), recomputed here because the network
returns only the maps it derives from them; ``tests/test_pacer_recognition.py`` checks that they give the
network's own preference map S back.

``true_terrain_method`` gives the other half of the chain its own row in Tables I-IV: the same model's order
inference (its matcher's patch places) costing every pixel by the terrain really there: the distance from that
row down to the model's own is what misrecognition costs the robot (measured on the 2026-11-28 model in
benchmarks/README.md, "what recognition costs the robot, and where": the pairs were read well enough, recognition,
mostly within 4 px of another terrain, was short).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import torch

from navlab.core.params.pacer import PacerDataParams
from navlab.core.seeding import rng
from navlab.metrics.intervals import bootstrap_mean_ci
from navlab.pacer.aerial import AerialMap
from navlab.pacer.experiments import Method, map_context, rounded, terrain_costmap
from navlab.pacer.model import TextureMatcher
from navlab.pacer.preferences import Preference
from navlab.pacer.terrain import TerrainBank


@torch.no_grad()
def patch_cosines(matcher: TextureMatcher, image: torch.Tensor, context: torch.Tensor) -> torch.Tensor:
    """(2n, h, w): cosine of every image cell (every pixel for a dilated matcher, else stride
    ``2 ** len(match_channels)``) with each of the context's
    2n patches (the n preferred first, then the n others), as the matcher computes them; image (3, H, W),
    context (3n, 2p, p)."""
    keys, centre = matcher.keys(context[None])
    return matcher.cosines(image[None], keys, centre)[0]


def recognition(cosines: np.ndarray, labels: np.ndarray, patch_terrains: np.ndarray) -> tuple[float, float] | None:
    """(share of cells whose best-matching patch shows the cell's terrain, share of the commonest named
    terrain) over the cells whose terrain the context names; cosines (2n, h, w), labels (H, W) sampled at
    each cell's centre, patch_terrains (2n,). None when no cell's terrain is named."""
    h, w = cosines.shape[1:]
    sy, sx = labels.shape[0] // h, labels.shape[1] // w
    cells = labels[sy // 2 :: sy, sx // 2 :: sx][:h, :w]
    named = np.isin(cells, patch_terrains)
    if not named.any():
        return None
    picked = np.asarray(patch_terrains)[cosines.argmax(axis=0)]
    _, counts = np.unique(cells[named], return_counts=True)
    return float((picked[named] == cells[named]).mean()), float(counts.max() / counts.sum())


@dataclass(frozen=True)
class Recognition:
    """Per map (same order as the maps): the matcher's recognition rate and the commonest-terrain baseline."""

    rate: np.ndarray
    baseline: np.ndarray


def map_recognition(matcher: TextureMatcher, maps: Sequence[AerialMap], bank: TerrainBank, data: PacerDataParams,
                    preference: Preference, seed: int, device: str = "cpu") -> Recognition:
    """The matcher on every map under the map's own informative context (the one Tables I-IV plan with)."""
    rates, baselines = [], []
    for index, amap in enumerate(maps):
        _, context, pairs = map_context(bank, data, amap, preference, True, seed, index)
        cosines = patch_cosines(matcher, torch.as_tensor(amap.image, device=device),
                                torch.as_tensor(context, device=device)).cpu().numpy()
        found = recognition(cosines, amap.labels, np.concatenate([pairs[:, 0], pairs[:, 1]]))
        if found is not None:
            rates.append(found[0])
            baselines.append(found[1])
    return Recognition(np.asarray(rates), np.asarray(baselines))


RECOGNITION_COLUMNS = ("recognition", "recognition_ci", "commonest_terrain", "commonest_terrain_ci",
                       "above_commonest", "above_commonest_ci")  # beside model, set, context and maps
RECOGNITION_CONTEXT = "matcher's nearest patch"


def recognition_rows(models: Mapping[str, torch.nn.Module], maps: Mapping[str, Sequence[AerialMap]], bank: TerrainBank,
                     data: PacerDataParams, seed: int, device: str = "cpu") -> list[dict]:
    """One row per (model with a matcher, map group): mean recognition rate and baseline over the maps under
    the realistic preference (the matcher reads appearance only, so the preference changes nothing but
    which pairs are drawn), with bootstrap intervals over maps and the paired difference."""
    rows = []
    for name, model in models.items():
        if getattr(model, "matcher", None) is None:
            continue
        for terrains, group in maps.items():
            found = map_recognition(model.matcher.eval(), group, bank, data, "realistic", seed, device)
            diff = found.rate - found.baseline
            rows.append({"model": name, "set": f"{terrains} maps", "context": RECOGNITION_CONTEXT,
                         "maps": len(found.rate), "recognition": float(found.rate.mean()),
                         "recognition_ci": rounded(bootstrap_mean_ci(found.rate, rng(seed, "pacer.recognition", name,
                                                                                    terrains))),
                         "commonest_terrain": float(found.baseline.mean()),
                         "commonest_terrain_ci": rounded(bootstrap_mean_ci(found.baseline,
                                                                           rng(seed, "pacer.recognition.base", terrains))),
                         "above_commonest": float(diff.mean()),
                         "above_commonest_ci": rounded(bootstrap_mean_ci(diff, rng(seed, "pacer.recognition.diff", name,
                                                                                   terrains)))})
    return rows


def recognition_note(data: PacerDataParams) -> str:
    """What the recognition rows of ``context_following`` measure, for the report's notes."""
    return (f"Rows '{RECOGNITION_CONTEXT}' (navlab.pacer.recognition): on the tables' held-out aerial maps, each with "
            f"its own {data.n_pairs}-pair context (realistic preference), the share of map cells whose most similar "
            "context patch (the texture matcher's own cosines, the attention's peak) shows the terrain really there, "
            "over the cells whose terrain the context names; commonest_terrain: the share of the commonest named "
            "terrain, what a matcher that tells nothing apart scores; above_commonest: the paired difference; "
            "intervals: bootstrap over maps. The costmap's preference evidence is a function of these cosines, so "
            "a rate near the baseline means the context cannot steer the costmap, however well the pairs are read.")


def true_terrains_name(model: str) -> str:
    """The Tables I-IV row of ``model`` given every pixel's true terrain (``true_terrain_method``)."""
    return f"{model} on true terrains"


def true_terrain_method(matcher: TextureMatcher | None) -> Method:
    """Diagnostic row: the model's own order inference with perfect recognition. Each pixel costs (1 - place) / 2
    of the context patches showing its true terrain (their mean place, ``TextureMatcher.patch_ranks``: the cost
    the preference map S gives a location whose attention rests on those patches alone); a terrain the context
    does not show costs 0.5, the middle. Between this row and the model's own lies what misrecognition costs the
    robot, between it and the window oracle what the context's pairs and the order inference leave open. A model
    without a matcher (``paper``'s concat-MLP network) has no order inference to read: a row of None."""
    if matcher is None:
        return lambda *_: None

    @torch.no_grad()
    def cost(amap: AerialMap, _ordering, context: np.ndarray, pairs: np.ndarray) -> np.ndarray:
        device = matcher.log_temperature.device
        keys, _ = matcher.keys(torch.as_tensor(context, dtype=torch.float32, device=device)[None])
        cost_of_patch = ((1.0 - matcher.patch_ranks(keys)[0]) / 2).cpu().numpy()
        patch_terrains = np.concatenate([pairs[:, 0], pairs[:, 1]])
        return terrain_costmap(amap.labels, {int(t): float(cost_of_patch[patch_terrains == t].mean())
                                             if (patch_terrains == t).any() else 0.5 for t in np.unique(amap.labels)})
    return cost
