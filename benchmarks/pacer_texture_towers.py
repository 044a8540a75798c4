"""Which texture features let a context patch find its terrain on the evaluation maps? (issue 24)

Why: PACER's costs follow its texture matcher (``pacer.recognition``), and the matcher's nearest context
patch is right for about 0.78 of seen-map cells; split by where the cell lies, it is right for ~0.93 of
cells whose 9 x 9-pixel neighbourhood is one terrain but ~0.62 of the rest, and on the street-window maps
about half of all cells lie within 4 px of another terrain (sidewalks, strips, kerbs). The matcher's tower
pools twice (stride 4, then a 3 x 3 mean): a 1-3 px strip's features are mostly its neighbours'.

This trains texture towers outside PACER with one objective, a per-pixel prototypical matching loss (each
pixel's softmax over the context's 2n patch keys, -log of the mass on the patches of its own terrain, which
the training items know), on D_synthetic items (recoloured as ``pacer.data.recolour`` says, or ``--recolour``)
of which half are SuReNav training-split street windows, and
scores each on the tables' own maps with one read-out that isolates recognition: every pixel takes the
terrain of its most similar context patch, costed at that terrain's mean rank over the orderings the
context's pairs allow (the context-limited oracle's rule, so that oracle, with perfect recognition, is this
read-out's ceiling). Towers:

* ``pooled``: the matcher's own architecture (``TextureMatcher``: conv pairs, 2 x 2 mean pool per stage,
  3 x 3 local mean, cosines upsampled);
* ``dilated``: the same convolutions without pooling, dilations 1, 2, 4 (receptive field 29 px, stride 1);
* ``luminance``: ``dilated`` fed each image and patch in grey (its channel mean): texture and grey level only, to
  ask whether a tower blind to colour separates same-coloured terrains better than one that sees it;
* ``both``: ``dilated`` and ``luminance`` side by side, their features concatenated before centring and
  normalising, one cosine over both (PACER's matcher with ``pacer.model.match_luminance``);
* ``balanced``: ``both`` with each tower centred and normalised apart, the cosine the mean of theirs, so that
  colour cannot outweigh texture by the size of its features;
* ``supervised``: ``both`` trained with a matching loss on each tower's own cosines beside the joint one;
* ``hypercolumn``: ``both`` whose features are every stage's output side by side (receptive fields 5, 13 and
  29 px), projected together: a 4-px sidewalk keeps features of its own beside the wide ones, which near a
  boundary mostly describe the neighbours;
* ``pretrained``: ImageNet-trained EfficientNet-Lite0 (``pacer.pretrained``, frozen) in place of the tower: its
  stride-4 and stride-8 features side by side (the latter upsampled), a trained 1 x 1 projection (issue 61);
* ``pretrained-raw``: the same features with no training at all (the projection the identity);
* ``pretrained-2x``: ``pretrained`` fed every image and patch upsampled twice (the BEV shows a photograph at a
  half to a quarter of its pixels; ImageNet's textures were learnt at 224 px per object);
* ``committed``: the committed phase-3 model's matcher as it is (no training here).

Prints per tower and map group: pixel recognition over named cells (all, interior, boundary) and, per
preference, the low-tier share with the share of the uniform-to-window-oracle gap closed (bootstrap 95%
interval over maps, ``claims.gap_closed``). Needs ``data/`` and ``artifacts/pacer/phase3`` (`dvc repro`);
~8 min per trained tower (2,000 steps of 16 items) on one thread.

``--hold-out NAME ...`` asks whether a third terrain group could select the matcher's training length without
touching the unseen group: those synthetic textures leave D_synthetic and become a *validation* group, painted
on maps like the unseen ones (and once more in grey, where only texture tells them apart); ``--eval-every N``
prints recognition per group (and per terrain) every N steps.

    .venv/bin/python benchmarks/pacer_texture_towers.py [--towers pooled dilated committed] [--steps 2000] [--recolour 0]
        [--hold-out box_tree roughcast stone_wall grey_tile --eval-every 500]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import time
from pathlib import Path

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F
from torch.utils.data import DataLoader

from navlab.core.params import load_params
from navlab.pacer.aerial import aerial_maps
from navlab.pacer.claims import gap_closed
from navlab.pacer.datasets import pacer_dataset
from navlab.pacer.experiments import (
    context_limited_oracle_method,
    map_context,
    navigation_rows,
    uniform_method,
    window_oracle_method,
)
from navlab.pacer.loss import matching_loss
from navlab.pacer.model import TextureMatcher
from navlab.pacer.preferences import context_limited_costs
from navlab.pacer.terrain import load_terrain_bank
from navlab.pacer.train import load_model

ROOT = Path(__file__).resolve().parents[1]
INTERIOR_PX = 9  # a cell is interior when its 9 x 9-pixel neighbourhood shows one terrain


class LuminanceMatcher(TextureMatcher):
    """The dilated tower seeing every input in grey (its channel mean in all three channels)."""

    def embed(self, x: torch.Tensor) -> torch.Tensor:
        return super().embed(x.mean(dim=1, keepdim=True).expand_as(x))


class BalancedMatcher(TextureMatcher):
    """PACER's two-tower matcher with each tower centred and normalised apart: the cosine the mean of theirs."""

    def unit(self, features: torch.Tensor, centre: torch.Tensor) -> torch.Tensor:
        parts = (features - centre).chunk(2, dim=1)
        return torch.cat([F.normalize(part, dim=1) for part in parts], dim=1) / 2**0.5


class DeeplySupervisedMatcher(TextureMatcher):
    """``both`` whose training also asks each tower alone to recognise (a matching loss on each tower's own
    cosines beside the joint one), so that the grey tower keeps what it learns alone while colour is at hand."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.centred: list[torch.Tensor] = []

    def unit(self, features: torch.Tensor, centre: torch.Tensor) -> torch.Tensor:
        if self.training:  # keys (B, d, 2n), then the image's (B, d, H, W)
            self.centred.append(features - centre)
        return super().unit(features, centre)

    def tower_cosines(self) -> list[torch.Tensor]:
        """Each tower's own (B, 2n, H, W) cosines from the last ``keys`` and ``cosines`` calls' features."""
        keys, feats = self.centred[-2:]
        return [torch.einsum("bdk,bdhw->bkhw", F.normalize(k, dim=1), F.normalize(f, dim=1))
                for k, f in zip(keys.chunk(2, dim=1), feats.chunk(2, dim=1))]


class HypercolumnMatcher(TextureMatcher):
    """``both`` with each tower's stage outputs (after each conv pair) concatenated before the projection."""

    def __init__(self, channels: tuple[int, ...], **kwargs):
        super().__init__(channels, **kwargs)
        width = sum(channels)
        self.project = nn.Conv2d(width, width, 1)
        self.grey_project = nn.Conv2d(width, width, 1) if self.grey_features is not None else None

    @staticmethod
    def stages(tower: nn.Sequential, x: torch.Tensor) -> torch.Tensor:
        outputs = []
        for index, layer in enumerate(tower):
            x = layer(x)
            if index % 4 == 3:  # conv, ReLU, conv, ReLU per stage (dilated: no pooling)
                outputs.append(x)
        return torch.cat(outputs, dim=1)

    def embed(self, x: torch.Tensor) -> torch.Tensor:
        colour = self.project(self.stages(self.features, x - 0.5))
        if self.grey_features is None:
            return colour
        grey = self.grey_project(self.stages(self.grey_features, x.mean(dim=1, keepdim=True) - 0.5))
        return torch.cat([colour, grey], dim=1)


class PretrainedMatcher(TextureMatcher):
    """PACER's matcher on frozen ImageNet features (``match_features="imagenet"``: EfficientNet-Lite0's strides 4
    and 8, a trained 1 x 1 projection, identity at the start, so ``pretrained-raw`` is this untrained);
    ``upsample`` enlarges every input first."""

    def __init__(self, upsample: int = 1):
        super().__init__((8,), features="imagenet")
        self.upsample = upsample

    def backbone_features(self, x: torch.Tensor) -> torch.Tensor:
        """The frozen part: stride-4 features beside the stride-8 ones upsampled to them, of images in [0, 1]."""
        if self.upsample > 1:
            x = F.interpolate(x, scale_factor=self.upsample, mode="bilinear", align_corners=False)
        return self.features(x)

    def embed(self, x: torch.Tensor) -> torch.Tensor:
        return self.project(self.backbone_features(x))


def pixel_cosines(matcher: TextureMatcher, image: torch.Tensor, context: torch.Tensor) -> torch.Tensor:
    """(B, 2n, H, W): every pixel's cosine with each context patch (preferred patches first); a pooled
    matcher's cells upsampled bilinearly."""
    cos = matcher.cosines(image, *matcher.keys(context))
    if cos.shape[-2:] == image.shape[-2:]:
        return cos
    return F.interpolate(cos, size=image.shape[-2:], mode="bilinear", align_corners=False)


def near_boundary(labels: torch.Tensor) -> torch.Tensor:
    """(B, H, W) bool: in-view pixels whose INTERIOR_PX-square neighbourhood shows another in-view terrain (labels
    (B, H, W), negative out of view; the image's edge borders nothing)."""
    ids = labels.to(torch.float32)[:, None]
    pad = INTERIOR_PX // 2
    highest = F.max_pool2d(ids, INTERIOR_PX, stride=1, padding=pad)
    lowest = -F.max_pool2d(-torch.where(ids < 0, torch.inf, ids), INTERIOR_PX, stride=1, padding=pad)
    return ((highest != lowest) & (ids >= 0))[:, 0]


def boundary_weighted_loss(cosines: torch.Tensor, temperature: torch.Tensor, labels: torch.Tensor,
                           patch_terrains: torch.Tensor, weight: float) -> torch.Tensor:
    """``matching_loss`` with the pixels within 4 px of another in-view terrain weighing ``weight`` x the rest:
    the weighted mean of the loss over those pixels and over the others (1: ``matching_loss`` itself)."""
    if weight == 1.0:
        return matching_loss(cosines, temperature, labels, patch_terrains)
    near = near_boundary(labels)
    shown = (patch_terrains[:, :, None, None] == labels[:, None]).any(dim=1)
    total, mass = cosines.sum() * 0.0, 0.0
    for part, w in ((near, weight), (~near, 1.0)):
        count = int((part & shown).sum())
        if count:
            total = total + w * count * matching_loss(cosines, temperature, labels.masked_fill(~part, -1),
                                                      patch_terrains)
            mass += w * count
    return total / max(mass, 1.0)


def train_tower(tower: TextureMatcher, params, data_dir: Path, bank, run: argparse.Namespace,
                on_step=lambda step: None) -> list[float]:
    """``run.steps`` Adam steps of the matching loss (boundary pixels weighted ``run.boundary_weight``)."""
    steps, seed = run.steps, run.seed
    data = params.pacer.data
    data = dataclasses.replace(data, layout=dataclasses.replace(data.layout, street_windows=0.5))
    items = pacer_dataset(dataclasses.replace(params, pacer=dataclasses.replace(params.pacer, data=data)),
                          data_dir, "synthetic", "train", bank=bank)
    optimiser = torch.optim.Adam(tower.parameters(), lr=2e-3)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimiser, steps)
    losses, step, epoch = [], 0, 0
    while step < steps:
        items.set_epoch(epoch)
        loader = DataLoader(items, batch_size=16, shuffle=True, generator=torch.Generator().manual_seed(seed + epoch))
        for batch in loader:
            pairs = batch["pairs"]
            patch_terrains = torch.cat([pairs[:, :, 0], pairs[:, :, 1]], dim=1)
            loss = boundary_weighted_loss(pixel_cosines(tower, batch["image"], batch["context"]),
                                          tower.log_temperature.exp(), batch["labels"], patch_terrains,
                                          run.boundary_weight)
            if isinstance(tower, DeeplySupervisedMatcher):
                for cosines in tower.tower_cosines():
                    loss = loss + matching_loss(cosines, tower.log_temperature.exp(), batch["labels"], patch_terrains)
                tower.centred.clear()
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            schedule.step()
            losses.append(loss.item())
            step += 1
            if step % 250 == 0:
                print(f"  step {step}: matching loss {np.mean(losses[-250:]):.3f}", flush=True)
            on_step(step)
            if step == steps:
                break
        epoch += 1
    return losses


def nearest_terrain(tower: TextureMatcher, amap, context: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    with torch.no_grad():
        cos = pixel_cosines(tower, torch.as_tensor(amap.image)[None], torch.as_tensor(context)[None])[0]
    return np.concatenate([pairs[:, 0], pairs[:, 1]])[cos.argmax(0).numpy()]


def read_out(tower: TextureMatcher):
    """A ``pacer.experiments.Method``: each pixel costs its nearest patch's terrain's mean consistent rank."""
    def cost(amap, _ordering, context, pairs):
        terrains = np.unique(pairs)
        costs = context_limited_costs(terrains, pairs)
        found = nearest_terrain(tower, amap, context, pairs)
        return costs[np.searchsorted(terrains, found)].astype(np.float32)
    return cost


def recognition(tower: TextureMatcher, maps, bank, data, seed: int) -> dict[str, float]:
    """Mean over maps of the nearest patch's terrain being right (all named pixels, interior, boundary), the
    maps' share of boundary pixels, and per terrain (``terrain:<name>``, over the maps that name it)."""
    rates = {"all": [], "interior": [], "boundary": [], "boundary_cells": []}
    for index, amap in enumerate(maps):
        _, context, pairs = map_context(bank, data, amap, "realistic", True, seed, index)
        right = nearest_terrain(tower, amap, context, pairs) == amap.labels
        named = np.isin(amap.labels, pairs)
        inner = ~near_boundary(torch.as_tensor(amap.labels)[None])[0].numpy()
        for key, where in (("all", named), ("interior", named & inner), ("boundary", named & ~inner)):
            rates[key].append(float(right[where].mean()))
        rates["boundary_cells"].append(1.0 - float(inner.mean()))
        for terrain in np.unique(pairs):
            where = amap.labels == terrain
            if where.any():
                rates.setdefault(f"terrain:{bank.terrains[terrain].name}", []).append(float(right[where].mean()))
    return {key: float(np.mean(v)) for key, v in rates.items()}


def held_out_params(params, names: list[str]):
    """(training params without the ``names`` synthetic textures, params whose *unseen* group is those
    textures, so ``aerial_maps(..., "unseen")`` paints validation maps of them)."""
    data = params.pacer.data
    unknown = sorted(set(names) - set(data.synthetic))
    if unknown:
        raise SystemExit(f"--hold-out {unknown}: not synthetic terrains; choose from {', '.join(data.synthetic)}")
    rest = {k: v for k, v in data.synthetic.items() if k not in names}
    validation = dataclasses.replace(data, synthetic=rest, unseen={k: data.synthetic[k] for k in names},
                                     realistic_ordering=[n for n in data.realistic_ordering if n in data.seen] + names)
    return tuple(dataclasses.replace(params, pacer=dataclasses.replace(params.pacer, data=d))
                 for d in (dataclasses.replace(data, synthetic=rest), validation))


def grey_bank(bank):
    """``bank`` with every photograph grey (its channel mean in all three channels): maps and contexts drawn
    from it differ between terrains by texture and grey level only."""
    def grey(parts):
        return tuple(tuple(tuple(np.repeat(level.mean(axis=2, keepdims=True), 3, axis=2) for level in pyramid)
                           for pyramid in photos) for photos in parts)
    return dataclasses.replace(bank, image_parts=grey(bank.image_parts), context_parts=grey(bank.context_parts))


def progress_printer(name: str, tower: TextureMatcher, probes: dict, seed: int, every: int, log: list):
    """``train_tower``'s ``on_step``: every ``every`` steps, recognition on each probe group's maps."""
    def on_step(step: int) -> None:
        if every <= 0 or step % every:
            return
        tower.eval()
        row = {"tower": name, "step": step, **{group: recognition(tower, maps, bank, data, seed)
                                for group, (maps, bank, data) in probes.items()}}
        tower.train()
        log.append(row)
        print(f"  step {step}: recognition " + ", ".join(f"{g} {row[g]['all']:.3f}" for g in probes), flush=True)
    return on_step


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--towers", nargs="+", default=["committed", "pooled", "dilated"],
                        choices=["committed", "pooled", "dilated", "luminance", "both", "balanced", "supervised",
                                 "hypercolumn", "pretrained", "pretrained-raw", "pretrained-2x"])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--channels", type=int, nargs=3, default=(16, 32, 32), help="the trained towers' widths")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--recolour", type=float, default=None,
                        help="chance each D_synthetic terrain is recoloured (pacer.recolour; default: params.yaml's)")
    parser.add_argument("--hold-out", nargs="*", default=[],
                        help="synthetic terrains held out of training as a validation group (see the docstring)")
    parser.add_argument("--eval-every", type=int, default=0, help="recognition per group every N training steps")
    parser.add_argument("--profile", default="default")
    parser.add_argument("--data-dir", type=Path, default=ROOT / "data")
    parser.add_argument("--artifacts-dir", type=Path, default=ROOT / "artifacts")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--boundary-weight", type=float, default=1.0,
                        help="weight of pixels within 4 px of another terrain in the matching loss (1: all alike)")
    parser.add_argument("--out", type=Path, default=None, help="also write the results as JSON here")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    params = load_params(args.profile)
    if args.recolour is not None:
        data = params.pacer.data
        data = dataclasses.replace(data, recolour=dataclasses.replace(data.recolour, probability=args.recolour))
        params = dataclasses.replace(params, pacer=dataclasses.replace(params.pacer, data=data))
    probes = {}
    if args.hold_out:
        params, validation = held_out_params(params, args.hold_out)
        validation_bank = load_terrain_bank(args.data_dir, validation.pacer.data)
        probes["validation"] = (aerial_maps(validation, args.data_dir, "unseen", validation_bank), validation_bank,
                                validation.pacer.data)
        greyed = grey_bank(validation_bank)  # the same maps in grey: texture alone must tell the terrains apart
        probes["grey validation"] = (aerial_maps(validation, args.data_dir, "unseen", greyed), greyed,
                                     validation.pacer.data)
    P = params.pacer
    bank = load_terrain_bank(args.data_dir, P.data)
    maps = {group: aerial_maps(params, args.data_dir, group, bank) for group in ("seen", "unseen")}
    probes = {**{group: (group_maps, bank, P.data) for group, group_maps in maps.items()}, **probes}
    found, along = [], []
    for name in args.towers:
        started = time.time()
        torch.manual_seed(args.seed)
        if name == "committed":
            tower = load_model(args.artifacts_dir / "pacer" / "phase3" / "model.pt", "cpu").matcher
            losses = []
        elif name == "pretrained-raw":
            tower, losses = PretrainedMatcher(), []
        else:
            channels = tuple(args.channels)
            kinds = {"dilated": (TextureMatcher, False), "luminance": (LuminanceMatcher, False),  # (class, two towers)
                     "both": (TextureMatcher, True), "balanced": (BalancedMatcher, True),
                     "supervised": (DeeplySupervisedMatcher, True), "hypercolumn": (HypercolumnMatcher, True)}
            if name in kinds:
                kind, two_towers = kinds[name]
                tower = kind(channels, dilated=True, luminance=two_towers)
            elif name.startswith("pretrained"):
                tower = PretrainedMatcher(upsample=2 if name.endswith("2x") else 1)
            else:
                tower = TextureMatcher(channels[:2])
            print(f"{name}: training {args.steps} steps", flush=True)
            losses = train_tower(tower, params, args.data_dir, bank, args,
                                 progress_printer(name, tower, probes, P.seed, args.eval_every, along))
        tower.eval()
        trained = time.time() - started
        for group, group_maps in maps.items():
            rates = recognition(tower, group_maps, bank, P.data, P.seed)
            print(f"{name} / {group}: nearest-patch terrain right for {rates['all']:.3f} of named pixels "
                  f"(interior {rates['interior']:.3f}, boundary {rates['boundary']:.3f}; "
                  f"boundary pixels {rates['boundary_cells']:.2f} of the maps)", flush=True)
            methods = {"uniform": (uniform_method(), True), "oracle": (window_oracle_method(P.data), True),
                       "context-limited oracle": (context_limited_oracle_method(), True), name: (read_out(tower), True)}
            for preference in ("realistic", "inverted"):
                result = navigation_rows(group_maps, methods, bank, P.data, preference, P.evaluation.cost_scale,
                                         P.seed, P.evaluation.queries_per_map)
                low = {k: s[:, 0] for k, s in result.shares.items()}
                claim = gap_closed(name, low[name], low["uniform"], low["oracle"], group, preference)
                ceiling = gap_closed("context-limited oracle", low["context-limited oracle"], low["uniform"],
                                     low["oracle"], group, preference)
                print(f"  {group}/{preference}: {claim.ours}; context-limited oracle {ceiling.ours}", flush=True)
                found.append({"tower": name, "group": group, "preference": preference, "recognition": rates,
                              "gap": claim.ours, "ceiling": ceiling.ours, "train_s": trained,
                              "final_loss": float(np.mean(losses[-250:])) if losses else None})
    if args.out is not None:
        args.out.write_text(json.dumps({"steps": args.steps, "seed": args.seed, "channels": args.channels,
                                        "boundary_weight": args.boundary_weight,
                                        "recolour": dataclasses.asdict(P.data.recolour),
                                        "hold_out": args.hold_out, "along": along, "results": found}, indent=1))
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
