"""Can each map teach the matcher its own terrains? A per-map refinement of the committed matcher (issue 24).

Why: Tables III/IV put PACER's shortfall on recognising the maps' terrains, most of it within 4 px of another
terrain (benchmarks/README.md, "what recognition costs the robot, and where"), and the maps' lighting moves
every terrain's colour away from its context patches' (colour matched against the patches recognises only about
half the pixels). A map's own pixels carry its lighting: fitted on the pixels the matcher names confidently, a
per-map model could rename the uncertain ones, and one with a small receptive field keeps a thin strip's own
colour where the matcher's 29-px features mix it with its neighbours'. Test time only, on the committed phase-3
model; nothing is trained across maps.

Each map, under its own realistic 3-pair context (as Tables I-IV draw it): the matcher's cosines give each context
terrain a score (its best patch) and each pixel a terrain; the *confident* pixels are those whose (2r + 1)-square
neighbourhood the matcher gives one terrain (r = ``--erode``). On them, per terrain, a Gaussian is fitted to
pixel features, and every pixel takes the terrain of highest ``log softmax(t * score) + beta * log p(terrain |
features)`` (t the matcher's temperature; a terrain with too few confident pixels keeps the matcher's evidence
alone). Feature forms:

* ``colour``: CIELAB, its 3 x 3 mean and standard deviation (9 numbers, receptive field 3 px), a full
  covariance per terrain;
* ``matcher+colour``: those beside the matcher's own unit features (its tower, as it names pixels), a covariance
  shared by the terrains (linear discriminant analysis), so the map's lighting re-weighs the matcher's features.

Prints, per map group, the share of named pixels right (all, and within ``INTERIOR_PX`` of another terrain, as
``pacer_texture_towers.near_boundary`` counts them) for the matcher's nearest patch (``pacer.recognition``'s rate,
reproduced) and each form and beta. Needs ``data/`` and ``artifacts/pacer/phase3`` (`dvc repro pacer_phase3`);
~9 min at `default` on the 2-core machine.

    .venv/bin/python benchmarks/pacer_transductive_labels.py [--maps 20] [--out benchmarks/results/pacer_transductive_labels.json]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import cv2
import numpy as np
import torch
from scipy import ndimage
from scipy.special import log_softmax

from navlab.pacer.aerial import AerialMap, aerial_maps
from navlab.pacer.experiments import map_context
from navlab.pacer.model import TextureMatcher
from navlab.pacer.recognition import patch_cosines
from pacer_matcher_readouts import committed_matcher_run
from pacer_texture_towers import near_boundary

FORMS = ("colour", "matcher+colour")
MIN_PIXELS = 200  # a terrain with fewer confident pixels is not modelled (its Gaussian would be noise)
MAX_PIXELS = 20_000  # confident pixels per terrain fitted (evenly spaced): enough for 9-137 numbers


def colour_features(image: np.ndarray) -> np.ndarray:
    """(H, W, 9): CIELAB scaled to about [-1, 1], its 3 x 3 mean and standard deviation; image (3, H, W)."""
    lab = cv2.cvtColor(np.ascontiguousarray(image.transpose(1, 2, 0)), cv2.COLOR_RGB2Lab)
    lab = lab / np.array([100.0, 128.0, 128.0], dtype=np.float32)
    mean = cv2.blur(lab, (3, 3))
    std = np.sqrt(np.maximum(cv2.blur(lab * lab, (3, 3)) - mean * mean, 0.0))
    return np.concatenate([lab, mean, std], axis=2).astype(np.float64)


@torch.no_grad()
def matcher_features(matcher: TextureMatcher, image: np.ndarray) -> np.ndarray:
    """(H, W, d): the matcher's unit pixel features (uncentred: a Gaussian model is blind to the shift); a
    strided matcher's (the ImageNet features' stride 4) read at every pixel by bilinear interpolation."""
    embedded = matcher.embed(torch.as_tensor(image)[None])
    embedded = torch.nn.functional.interpolate(embedded, size=image.shape[1:], mode="bilinear", align_corners=False)
    return matcher.unit(embedded, torch.zeros(()))[0].numpy().transpose(1, 2, 0)


def gaussian_log_posterior(features: np.ndarray, named: np.ndarray, confident: np.ndarray,
                           shared: bool) -> np.ndarray:
    """(k, H, W) log p(terrain | features) from a Gaussian per terrain fitted on its confident pixels (``named``
    (H, W) index into the k terrains); NaN rows for terrains with under MIN_PIXELS of them."""
    k = int(named.max()) + 1
    samples = {}
    for i in range(k):
        x = features[confident & (named == i)]
        if len(x) >= MIN_PIXELS:
            samples[i] = x[np.linspace(0, len(x) - 1, min(len(x), MAX_PIXELS)).astype(int)]
    log_post = np.full((k, *named.shape), np.nan)
    if len(samples) < 2:
        return log_post
    eye = 1e-4 * np.eye(features.shape[-1])
    pooled = np.cov(np.concatenate([x - x.mean(0) for x in samples.values()]).T) + eye if shared else None
    counts = np.array([len(x) for x in samples.values()], dtype=float)
    for (i, x), prior in zip(samples.items(), np.log(counts / counts.sum()), strict=True):
        cov = pooled if shared else np.cov(x.T) + eye
        d = features - x.mean(0)
        log_post[i] = (-0.5 * np.einsum("hwi,ij,hwj->hw", d, np.linalg.inv(cov), d)
                       - 0.5 * np.linalg.slogdet(cov)[1] + prior)
    modelled = ~np.isnan(log_post[:, 0, 0])
    log_post[modelled] = log_softmax(log_post[modelled], axis=0)
    return log_post


def refined_labels(scores: np.ndarray, temperature: float, log_post: np.ndarray, beta: float) -> np.ndarray:
    """(H, W) index into the k terrains: the matcher's log softmax plus beta x the per-map posterior (a terrain
    without one takes, at each pixel, the median of the others': neither favoured nor ruled out)."""
    evidence = log_softmax(temperature * scores, axis=0)
    modelled = ~np.isnan(log_post[:, 0, 0])
    if modelled.sum() >= 2:
        post = np.where(modelled[:, None, None], log_post, np.median(log_post[modelled], axis=0))
        evidence = evidence + beta * post
    return evidence.argmax(axis=0)


def map_rates(matcher: TextureMatcher, amap: AerialMap, context: np.ndarray, pairs: np.ndarray, run) -> dict:
    """{reading: (share right over named pixels, over named pixels near another terrain)} for one map."""
    cosines = patch_cosines(matcher, torch.as_tensor(amap.image), torch.as_tensor(context))
    cosines = torch.nn.functional.interpolate(cosines[None], size=amap.labels.shape, mode="bilinear",
                                              align_corners=False)[0].numpy()  # a strided matcher: every pixel
    patch_terrains = np.concatenate([pairs[:, 0], pairs[:, 1]])
    terrains = np.unique(patch_terrains)
    scores = np.stack([cosines[patch_terrains == t].max(axis=0) for t in terrains]).astype(np.float64)
    nearest = scores.argmax(axis=0)
    side = 2 * run.erode + 1
    confident = (ndimage.maximum_filter(nearest, side) == nearest) & (ndimage.minimum_filter(nearest, side) == nearest)
    colour = colour_features(amap.image)
    features = {"colour": colour,
                "matcher+colour": np.concatenate([colour, matcher_features(matcher, amap.image)], axis=2)}
    named = np.isin(amap.labels, terrains)
    near = named & near_boundary(torch.as_tensor(amap.labels)[None])[0].numpy()
    temperature = matcher.log_temperature.detach().exp().item()

    def rates(labels: np.ndarray) -> tuple[float, float]:
        right = terrains[labels] == amap.labels
        return float(right[named].mean()), float(right[near].mean()) if near.any() else float("nan")

    out = {"nearest patch": rates(nearest)}
    for form in FORMS:
        log_post = gaussian_log_posterior(features[form], nearest, confident, shared=form != "colour")
        for beta in run.betas:
            out[f"{form}, beta {beta:g}"] = rates(refined_labels(scores, temperature, log_post, beta))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--betas", type=float, nargs="+", default=[0.25, 1.0])
    parser.add_argument("--erode", type=int, default=2, help="confident: one terrain within this many px")
    run, params, bank, model = committed_matcher_run(parser)
    P = params.pacer
    results: dict = {"profile": run.profile, "erode": run.erode, "recognition (all, near another terrain)": {}}
    for group in ("seen", "unseen"):
        per_map = []
        for index, amap in enumerate(aerial_maps(params, run.data_dir, group, bank)[:run.maps]):
            _, context, pairs = map_context(bank, P.data, amap, "realistic", True, P.seed, index)
            per_map.append(map_rates(model.matcher, amap, context, pairs, run))
        rows = {reading: [round(float(np.nanmean([m[reading][j] for m in per_map])), 4) for j in (0, 1)]
                for reading in per_map[0]}
        results["recognition (all, near another terrain)"][group] = rows
        print(group, json.dumps(rows, indent=1), flush=True)
    if run.out:
        Path(run.out).write_text(json.dumps(results, indent=1) + "\n", encoding="utf8")


if __name__ == "__main__":
    main()
