"""Two test-time re-readings of the committed PACER matcher, on the tables' own maps (issue 24).

Why: Tables III/IV put PACER's shortfall on recognition of the maps' terrains, not on reading the pairs. Two
cheap ways around the matcher's present form are measured here on the committed phase-3 model, without
retraining (benchmarks/README.md, "keys at every position of a context patch" and "the context-limited oracle's
order rule inside the matcher"):

1. *Key forms.* The matcher names a map pixel by the nearest *mean* feature of a context patch. Each patch keeps
   instead every position's feature, and a patch is scored by the max, a top-k mean or the mean of its position
   cosines, by 4 x 4-pooled positions, or by the mean of its inner positions (furthest from the zero padding).
   Scored like ``pacer.recognition.recognition``: the share of named map cells whose best patch shows their terrain.
2. *Order rules.* The matcher places the context's patches by a Copeland score over the pairs' transitive closure
   (``TextureMatcher.patch_ranks``); the context-limited oracle costs each terrain at its mean rank over the orderings
   the pairs allow (``preferences.context_limited_costs``). Rows: the model as committed; the model with the oracle's
   rule over its patches (grouped where the matcher's own same-terrain weight exceeds 1/2); and, with no network, each
   pixel costed by its nearest patch's terrain under the oracle's rule. Each as the share of the uniform-to-window-
   oracle gap it closes (``claims.gap_closed``), both references recomputed on the same maps.

Needs ``data/`` and ``artifacts/pacer/phase3`` (`dvc repro pacer_phase3`). ~16 min at `default` on the 2-core
machine (4 min of key forms, 3 per set of navigation rows).

    .venv/bin/python benchmarks/pacer_matcher_readouts.py [--maps 20] [--out benchmarks/results/pacer_matcher_readouts.json]
"""

from __future__ import annotations

import argparse
import json
import types
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F
from scipy.sparse.csgraph import connected_components

from navlab.core.params import load_params
from navlab.pacer.aerial import aerial_maps
from navlab.pacer.claims import gap_closed
from navlab.pacer.experiments import (
    map_context,
    navigation_rows,
    pacer_method,
    terrain_costmap,
    uniform_method,
    window_oracle_method,
)
from navlab.pacer.model import TextureMatcher
from navlab.pacer.preferences import context_limited_costs
from navlab.pacer.recognition import patch_cosines, recognition
from navlab.pacer.terrain import load_terrain_bank
from navlab.pacer.train import load_model

KEY_FORMS = ("mean key (committed)", "max over positions", "top-8 positions", "top-32 positions",
             "mean cosine over positions", "max over 4x4-pooled positions", "inner-crop mean key")
UNIFORM, ORACLE = "Uniform costmap (chance)", "Window oracle (ceiling)"
COPELAND, MEAN_RANK, HARD = "model (Copeland places)", "model (mean-rank places)", "nearest patch, mean-rank costs"


@torch.no_grad()
def key_form_cosines(matcher: TextureMatcher, image: torch.Tensor, context: torch.Tensor) -> dict[str, torch.Tensor]:
    """{key form: (2n, H, W) patch scores} for one map; image (3, H, W), context (3n, 2p, p)."""
    features = matcher.embed(matcher.patches(context[None]))  # (2n, d, p, p)
    centre = features.mean(dim=(2, 3)).mean(dim=0)
    embedded = matcher.embed(image[None])  # a strided matcher (ImageNet's stride 4): each pixel its cell's feature
    embedded = F.interpolate(embedded, size=image.shape[1:], mode="bilinear", align_corners=False)
    pixels = matcher.unit(embedded, centre[None, :, None, None])[0].flatten(1)  # (d, H*W)
    shape = (features.shape[0], *image.shape[1:])

    def by_mean(f: torch.Tensor) -> torch.Tensor:
        return (matcher.unit(f.mean(dim=(2, 3)), centre) @ pixels).reshape(shape)

    def by_position(f: torch.Tensor) -> torch.Tensor:  # (2n, positions, H*W)
        return torch.einsum("kdq,dx->kqx", matcher.unit(f, centre[None, :, None, None]).flatten(2), pixels)

    at = by_position(features)
    crop = max(1, features.shape[-1] // 4)
    forms = {KEY_FORMS[0]: by_mean(features), KEY_FORMS[1]: at.amax(1).reshape(shape),
             KEY_FORMS[2]: at.topk(min(8, at.shape[1]), dim=1).values.mean(1).reshape(shape),
             KEY_FORMS[3]: at.topk(min(32, at.shape[1]), dim=1).values.mean(1).reshape(shape),
             KEY_FORMS[4]: at.mean(1).reshape(shape)}
    del at
    forms[KEY_FORMS[5]] = by_position(F.avg_pool2d(features, min(4, features.shape[-1]))).amax(1).reshape(shape)
    forms[KEY_FORMS[6]] = by_mean(features[:, :, crop:-crop, crop:-crop])
    return forms


def mean_rank_places(matcher: TextureMatcher, keys: torch.Tensor) -> torch.Tensor:
    """(B, 2n) places in [-1, 1] as ``TextureMatcher.patch_ranks`` returns them, but from the context-limited
    oracle's rule: patches joined where the matcher's same-terrain weight exceeds 1/2, each group at 1 - 2 x its
    mean-rank cost over the orderings the pairs allow."""
    n = keys.shape[1] // 2
    same = torch.sigmoid(matcher.log_same_sharpness.exp() * (keys @ keys.transpose(1, 2) - matcher.same_threshold))
    places = []
    for weights in same.detach().cpu().numpy():
        _, group = connected_components(weights > 0.5, directed=False)
        pairs = np.stack([group[:n], group[n:]], axis=1)
        groups = np.unique(group)
        cost = dict(zip(groups.tolist(), context_limited_costs(groups, pairs[pairs[:, 0] != pairs[:, 1]]).tolist()))
        places.append([1.0 - 2.0 * cost[g] for g in group.tolist()])
    return torch.tensor(places, dtype=keys.dtype, device=keys.device)


def nearest_patch_method(matcher: TextureMatcher):
    """No network: each pixel its nearest context patch's terrain, costed at that terrain's mean rank over the
    orderings the context's pairs allow (the context-limited oracle's rule on the matcher's recognition)."""
    def cost(amap, _ordering, context, pairs):
        cosines = patch_cosines(matcher, torch.as_tensor(amap.image), torch.as_tensor(context))
        cosines = F.interpolate(cosines[None], size=amap.labels.shape, mode="bilinear", align_corners=False)[0].numpy()
        named = np.concatenate([pairs[:, 0], pairs[:, 1]])
        terrains = np.unique(named)
        return terrain_costmap(named[cosines.argmax(axis=0)],
                               dict(zip(terrains.tolist(), context_limited_costs(terrains, pairs).tolist())))
    return cost


def key_form_rows(matcher: TextureMatcher, maps, bank, data, seed: int) -> dict[str, float]:
    rates: dict[str, list[float]] = {form: [] for form in KEY_FORMS}
    for index, amap in enumerate(maps):
        _, context, pairs = map_context(bank, data, amap, "realistic", True, seed, index)
        named = np.concatenate([pairs[:, 0], pairs[:, 1]])
        for form, scores in key_form_cosines(matcher, torch.as_tensor(amap.image), torch.as_tensor(context)).items():
            found = recognition(scores.numpy(), amap.labels, named)
            if found is not None:
                rates[form].append(found[0])
    return {form: float(np.mean(r)) for form, r in rates.items()}


def order_rule_rows(model, maps, bank, P, preference: str) -> dict[str, str]:
    matcher = model.matcher
    methods = {UNIFORM: (uniform_method(), True), ORACLE: (window_oracle_method(P.data), True),
               COPELAND: (pacer_method(model, P.data, P.train.device), True)}
    shares = navigation_rows(maps, methods, bank, P.data, preference, P.evaluation.cost_scale, P.seed,
                             P.evaluation.queries_per_map).shares
    matcher.patch_ranks = types.MethodType(mean_rank_places, matcher)  # this instance only
    try:
        shares |= navigation_rows(maps, {MEAN_RANK: (pacer_method(model, P.data, P.train.device), True)}, bank, P.data,
                                  preference, P.evaluation.cost_scale, P.seed, P.evaluation.queries_per_map).shares
    finally:
        del matcher.patch_ranks
    shares |= navigation_rows(maps, {HARD: (nearest_patch_method(matcher), True)}, bank, P.data, preference,
                              P.evaluation.cost_scale, P.seed, P.evaluation.queries_per_map).shares
    return {name: gap_closed(name, shares[name][:, 0], shares[UNIFORM][:, 0], shares[ORACLE][:, 0]).ours
            for name in (COPELAND, MEAN_RANK, HARD)}


def committed_matcher_run(parser: argparse.ArgumentParser):
    """(arguments, params, terrain bank, committed phase-3 model) for a script that re-reads the committed matcher
    on the tables' maps: adds the arguments such scripts share. A strided matcher's (ImageNet features: stride 4)
    are read at every pixel by bilinear interpolation, as the model reads its cosines."""
    parser.add_argument("--profile", default="default")
    parser.add_argument("--maps", type=int, default=None, help="maps per group (default: all the tables use)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--data-dir", default="data")
    parser.add_argument("--artifacts-dir", default="artifacts")
    parser.add_argument("--out", default=None, help="write the results here as JSON")
    run = parser.parse_args()
    torch.set_num_threads(run.threads)
    params = load_params(run.profile)
    bank = load_terrain_bank(run.data_dir, params.pacer.data)
    model = load_model(Path(run.artifacts_dir) / "pacer" / "phase3" / "model.pt", params.pacer.train.device).eval()
    if model.matcher is None:
        raise SystemExit(f"profile {run.profile!r} trains no texture matcher (pacer.model.match_channels is empty): "
                         "nothing to re-read; use a profile with one")
    return run, params, bank, model


def main() -> None:
    run, params, bank, model = committed_matcher_run(argparse.ArgumentParser(description=__doc__.splitlines()[0]))
    P = params.pacer
    results: dict = {"profile": run.profile, "recognition": {}, "gap_closed": {}}
    for group in ("seen", "unseen"):
        maps = aerial_maps(params, run.data_dir, group, bank)[:run.maps]
        results["recognition"][group] = key_form_rows(model.matcher, maps, bank, P.data, P.seed)
        print(group, "recognition:", json.dumps(results["recognition"][group], indent=1), flush=True)
        for preference in ("realistic", "inverted"):
            rows = order_rule_rows(model, maps, bank, P, preference)
            results["gap_closed"][f"{group}/{preference}"] = rows
            print(group, preference, json.dumps(rows, indent=1), flush=True)
    if run.out:
        Path(run.out).write_text(json.dumps(results, indent=1) + "\n", encoding="utf8")


if __name__ == "__main__":
    main()
