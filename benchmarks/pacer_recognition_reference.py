"""How much of PACER's gap to the window oracle the imagery itself leaves: the recognition reference.

Why (issue 24): Tables III/IV measure PACER's low-tier share between the uniform costmap (chance) and
the window oracle (labels read off the map). A method that follows the ordering perfectly still has to
*recognise* each terrain in the rendered imagery. This trains a terrain segmenter (below) on each
terrain group (seen, and unseen as a check that those terrains can be told apart at all), tells it each
map's true ordering, and scores it on the tables' own maps, crossings and tier scoring
(``experiments.navigation_rows``), beside the uniform and window-oracle rows recomputed on the same maps.
The same segmenter told only the context's pairs (each terrain at its mean rank over the orderings they
allow, no prior) is scored beside the context-limited oracle (the same costs with the true labels): the
ceiling of a method that recognises as well as the segmenter and follows the context perfectly, PACER
D_synthetic's own (issue 24 asks it for 75% of the gap to the window oracle).
PACER's row (D_synthetic) is read from the committed Tables III/IV; the recomputed uniform and oracle
rows are checked against them (the same data must give the same rows).

Prints, per group and preference: the low-tier share of each row with its 95% interval, the share of
the chance-to-oracle gap the reference closes (``claims.gap_closed``, 95% interval over maps) and of the
gap to the ground-truth row (true labels under the reference's own map-level cost rule: what recognition
alone costs it), PACER's gap from the committed table, and the segmenter's pixel accuracy and
per-terrain recall on held-out BEV items. Needs ``data/`` (`python -m navlab data build` or `dvc repro
data`); ~40 min per group (128 epochs) on one thread of the 2-core machine.

    .venv/bin/python benchmarks/pacer_recognition_reference.py [--terrains seen unseen] [--epochs 128] [--width 32]

The segmenter (below) is fully convolutional, trained on the same rendered BEV items PACER learns from to
name every pixel's terrain (cross-entropy inside the field of view), and is then *given* the map's true
ordering. A pixel costs its expected rank cost Σ_l p(l) (l−1)/(L−1) over the map's terrains (the
paper's H(τ_l), Sec. V-A), windows stitched as PACER's. What it reaches is what recognition of this
imagery allows a method that follows the ordering perfectly: a ceiling for PACER that is honest about
the stand-in data, below the label-reading window oracle.

Trained on the seen terrains it is a strong version of the semantic classifier's paradigm (dense, not
patch votes); trained on the unseen terrains (which PACER never sees) it checks that those terrains are
recognisable at all. Neither is a paper row, so the segmenter lives here, beside the one script that uses it.

Told only the context's pairs instead (``segmenter_method(..., told="context")``), each terrain of the map
costs its mean rank over the orderings the pairs allow, as the context-limited oracle's do
(``preferences.context_limited_costs``): what recognition as good as a dedicated segmenter and a perfect
follower of the context *with no prior* can reach, PACER D_synthetic's own ceiling (its phase 3 trains on
random orderings, so it has no prior to fall back on).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F
from tqdm.auto import tqdm

from navlab.core.params import Params, load_params
from navlab.core.seeding import torch_generator
from navlab.core.training import descend
from navlab.maps.dataset import load_maps
from navlab.pacer.aerial import AerialMap, aerial_maps
from navlab.pacer.bev import fov_mask
from navlab.pacer.claims import gap_closed
from navlab.pacer.datasets import STREET_SPLIT, PacerDataset, Recipe, evaluation_dataset
from navlab.pacer.evaluate import stitch_windows, window_cutter
from navlab.pacer.experiments import (
    context_limited_oracle_method,
    ground_truth_method,
    heldout_bev_params,
    navigation_rows,
    uniform_method,
    window_oracle_method,
)
from navlab.pacer.preferences import IGNORE, context_limited_costs, rank_costs
from navlab.pacer.terrain import TerrainBank, load_terrain_bank

ROOT = Path(__file__).resolve().parents[1]
TABLES = {"seen": "table3_phases_seen.json", "unseen": "table4_phases_unseen.json"}
REFERENCE, UNIFORM, ORACLE = "Segmenter told the ordering", "Uniform costmap (chance)", "Window oracle (ceiling)"
TRUTH = "Ground truth (labels, map ordering)"
TOLD_CONTEXT, LIMITED = "Segmenter told the context's pairs", "Context-limited oracle"


Terrains = Literal["seen", "unseen"]


@dataclass(frozen=True)
class SegmenterSettings:
    """How the reference is trained: ``epochs`` of ``examples_per_epoch`` fresh BEV items (Adam, cosine
    learning rate from ``lr``), a fraction ``street_windows`` of them cut from SuReNav's training street
    maps (the evaluation maps' kind of layout) instead of the procedural layouts."""

    epochs: int = 128  # held-out pixel accuracy (seen) 0.834 / 0.919 / 0.937 at 16 / 64 / 128: still rising
    examples_per_epoch: int = 1024
    batch_size: int = 32
    lr: float = 2e-3
    street_windows: float = 0.5
    width: int = 32

    def __post_init__(self):
        if min(self.epochs, self.examples_per_epoch, self.batch_size, self.width) < 1 or self.lr <= 0:
            raise ValueError(f"SegmenterSettings: epochs, examples_per_epoch, batch_size, width must be >= 1 and "
                             f"lr > 0; got {self}")
        if not 0 <= self.street_windows <= 1:
            raise ValueError(f"SegmenterSettings.street_windows = {self.street_windows}: a fraction in [0, 1]")


class TerrainSegmenter(nn.Module):
    """Image (B,3,S,S) -> (B,K,S,S) logits over ``labels`` (terrain ids): two strided blocks, dilated
    context at 1/4 resolution (a few patches wide, as texture needs), upsampled and joined with the
    full-resolution features so that 1-3 px sidewalks keep their own label."""

    def __init__(self, labels: Sequence[int], width: int = 32):
        super().__init__()
        self.labels = tuple(int(v) for v in labels)
        self.width = int(width)

        def block(cin, cout, stride=1, dilation=1):
            return nn.Sequential(nn.Conv2d(cin, cout, 3, stride, padding=dilation, dilation=dilation, bias=False),
                                 nn.BatchNorm2d(cout), nn.ReLU(inplace=True))

        w = self.width
        self.full = nn.Sequential(block(3, w), block(w, w))
        self.down = nn.Sequential(block(w, 2 * w, stride=2), block(2 * w, 2 * w, stride=2),
                                  block(2 * w, 2 * w, dilation=2), block(2 * w, 2 * w, dilation=4))
        self.head = nn.Sequential(block(3 * w, w), nn.Conv2d(w, len(self.labels), 1))

    def forward(self, image: torch.Tensor) -> torch.Tensor:
        full = self.full(image)
        coarse = F.interpolate(self.down(full), size=image.shape[-2:], mode="bilinear", align_corners=False)
        return self.head(torch.cat([full, coarse], dim=1))


def segmenter_dataset(params: Params, data_dir, terrains: Terrains, settings: SegmenterSettings,
                      bank: TerrainBank, split: str = "train") -> PacerDataset:
    """BEV items on ``terrains`` from PACER's renderer, with their own seed stream (never PACER's items),
    street windows from SuReNav's training geography only (``STREET_SPLIT``: never the test tiles)."""
    data = params.pacer.data
    data = dataclasses.replace(data, layout=dataclasses.replace(data.layout, street_windows=settings.street_windows))
    street = load_maps(data_dir, STREET_SPLIT[split]) if settings.street_windows > 0 else ()
    recipe = Recipe(f"segmenter-{terrains}", f"segmenter-{terrains}", terrains, "realistic")
    return PacerDataset(bank, data, recipe, split, settings.examples_per_epoch, params.pacer.seed, street_maps=street)


def _targets(labels: torch.Tensor, known: Sequence[int]) -> torch.Tensor:
    """Terrain ids -> class indices; IGNORE (outside the view) and unknown ids -> -100 (ignored)."""
    lookup = torch.full((max(known) + 2,), -100, dtype=torch.long)
    lookup[torch.as_tensor(known)] = torch.arange(len(known))
    labels = labels.clone()
    labels[(labels == IGNORE) | (labels > max(known))] = max(known) + 1
    return lookup[labels]


def train_segmenter(params: Params, data_dir, terrains: Terrains, bank: TerrainBank,
                    settings: SegmenterSettings = SegmenterSettings(), *, progress: bool = True) -> TerrainSegmenter:
    """Fit the segmenter on fresh items every epoch (``set_epoch``), seeded from ``params.pacer.seed``."""
    seed = params.pacer.seed
    torch.manual_seed(seed)
    known = [int(t) for t in bank.ids(terrains)]
    model = TerrainSegmenter(known, settings.width)
    optimiser = torch.optim.Adam(model.parameters(), lr=settings.lr)
    steps = settings.epochs * -(-settings.examples_per_epoch // settings.batch_size)
    schedule = torch.optim.lr_scheduler.CosineAnnealingLR(optimiser, steps)
    dataset = segmenter_dataset(params, data_dir, terrains, settings, bank)
    gen = torch_generator(seed, "pacer.segmenter.batches", terrains)
    for epoch in tqdm(range(settings.epochs), desc=f"segmenter ({terrains})", disable=not progress):
        dataset.set_epoch(epoch)
        order = torch.randperm(len(dataset), generator=gen).tolist()
        model.train()
        for start in range(0, len(order), settings.batch_size):
            items = [dataset[i] for i in order[start:start + settings.batch_size]]
            images = torch.stack([it["image"] for it in items])
            targets = _targets(torch.stack([it["labels"] for it in items]), known)
            descend(F.cross_entropy(model(images), targets, ignore_index=-100), optimiser, schedule)
    return model.eval()


@torch.no_grad()
def pixel_recall(model: TerrainSegmenter, dataset, count: int) -> tuple[float, dict[int, float]]:
    """(pixel accuracy, recall per terrain id) over the field of view of the first ``count`` items of
    ``dataset``: how well the terrains of this imagery can be told apart."""
    model.eval()
    known = list(model.labels)
    hits = np.zeros(len(known))
    totals = np.zeros(len(known))
    for i in range(min(count, len(dataset))):
        item = dataset[i]
        target = _targets(item["labels"][None], known)[0]
        predicted = model(item["image"][None])[0].argmax(0)
        valid = target >= 0
        np.add.at(totals, target[valid].numpy(), 1)
        np.add.at(hits, target[valid].numpy(), (predicted[valid] == target[valid]).numpy())
    seen = totals > 0
    recall = {known[k]: float(hits[k] / totals[k]) for k in np.flatnonzero(seen)}
    return float(hits.sum() / max(totals.sum(), 1)), recall


def expected_rank_costs(probabilities: torch.Tensor, labels: Sequence[int], ordering: np.ndarray,
                        costs: np.ndarray | None = None) -> torch.Tensor:
    """(N,H,W) expected cost Σ_l p(l) c_l of (N,K,H,W) label ``probabilities``, the probabilities
    renormalised over the terrains of ``ordering`` (the map's own: the reference is told which terrains the
    map has); c_l = ``costs`` (one per terrain of ``ordering``) or, by default, its rank cost (l−1)/(L−1)."""
    ordering = np.asarray(ordering, dtype=np.int64)
    missing = sorted(set(ordering.tolist()) - set(labels))
    if missing:
        raise ValueError(f"ordering names terrains {missing} the segmenter was not trained on (it knows "
                         f"{list(labels)}); train it on this terrain group")
    costs = rank_costs(ordering) if costs is None else np.asarray(costs, dtype=np.float32)
    if costs.shape != ordering.shape:
        raise ValueError(f"costs {costs.shape} must give one cost per terrain of the ordering {ordering.shape}")
    index = torch.as_tensor([list(labels).index(int(t)) for t in ordering])
    p = probabilities[:, index]
    p = p / p.sum(dim=1, keepdim=True).clamp_min(1e-12)
    return torch.einsum("nkhw,k->nhw", p, torch.as_tensor(costs))


def segmenter_method(model: TerrainSegmenter, params: Params, *, told: Literal["ordering", "context"] = "ordering",
                     overlap: int = 2, batch: int = 32):
    """A ``pacer.experiments.Method``: the map costed window by window as the expected cost of its terrains,
    stitched as PACER's costmaps are. ``told`` ordering: each terrain's rank cost under the map's true
    ordering (the context is ignored); context: its mean rank over the orderings of the map's terrains that
    the context's pairs allow, scaled to [0, 1] (the context-limited oracle's costs, with predicted labels)."""
    if told not in ("ordering", "context"):
        raise ValueError(f"told={told!r}: the segmenter is told the map's 'ordering' or the 'context' pairs")
    data = params.pacer.data
    mask = fov_mask(data.image_size, data.camera.near_width)

    @torch.no_grad()
    def cost(amap: AerialMap, ordering: np.ndarray, _context, pairs) -> np.ndarray:
        image = torch.as_tensor(amap.image, dtype=torch.float32)
        cut = window_cutter(image, mask)
        terrains, costs = np.asarray(ordering, dtype=np.int64), None
        if told == "context":
            terrains = np.asarray(amap.terrains, dtype=np.int64)
            costs = context_limited_costs(terrains, pairs)

        def window_costs(corners):
            return expected_rank_costs(torch.softmax(model(cut(corners)), dim=1), model.labels, terrains, costs)

        return stitch_windows(window_costs, tuple(image.shape[1:]), mask, overlap=overlap, batch=batch).numpy()

    return cost


def committed_rows(reports: Path, terrains: str) -> dict[tuple[str, str], dict]:
    table = json.loads((reports / "pacer" / TABLES[terrains]).read_text())
    return {(r["preference"], r["model"]): r for r in table["rows"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--terrains", nargs="+", default=["seen", "unseen"], choices=["seen", "unseen"])
    parser.add_argument("--epochs", type=int, default=SegmenterSettings.epochs)
    parser.add_argument("--examples", type=int, default=SegmenterSettings.examples_per_epoch,
                        help="fresh BEV items per epoch")
    parser.add_argument("--street-windows", type=float, default=SegmenterSettings.street_windows)
    parser.add_argument("--width", type=int, default=SegmenterSettings.width, help="the segmenter's channels")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--data-dir", type=Path, default=ROOT / "data")
    parser.add_argument("--reports-dir", type=Path, default=ROOT / "reports")
    parser.add_argument("--out", type=Path, default=None, help="also write the results as JSON here")
    args = parser.parse_args()
    torch.set_num_threads(args.threads)
    params = load_params(args.profile)
    P = params.pacer
    bank = load_terrain_bank(args.data_dir, P.data)
    settings = SegmenterSettings(epochs=args.epochs, examples_per_epoch=args.examples,
                                 street_windows=args.street_windows, width=args.width)
    print(f"profile {args.profile}; {settings}")
    found = []
    for terrains in args.terrains:
        model = train_segmenter(params, args.data_dir, terrains, bank, settings)
        heldout = evaluation_dataset(heldout_bev_params(params), args.data_dir, terrains, "realistic", bank=bank)
        accuracy, recall = pixel_recall(model, heldout, P.evaluation.heldout_examples)
        names = {t: bank.terrains[t].name for t in recall}
        print(f"\n{terrains}: pixel accuracy {accuracy:.3f} on {P.evaluation.heldout_examples} held-out BEV items; "
              "recall " + ", ".join(f"{names[t]} {r:.2f}" for t, r in sorted(recall.items(), key=lambda x: x[1])))
        maps = aerial_maps(params, args.data_dir, terrains, bank)
        methods = {REFERENCE: (segmenter_method(model, params), True),
                   TOLD_CONTEXT: (segmenter_method(model, params, told="context"), True),
                   LIMITED: (context_limited_oracle_method(), True),
                   TRUTH: (ground_truth_method(), True), ORACLE: (window_oracle_method(P.data), True),
                   UNIFORM: (uniform_method(), True)}
        committed = committed_rows(args.reports_dir, terrains)
        for preference in ("realistic", "inverted"):
            result = navigation_rows(maps, methods, bank, P.data, preference, P.evaluation.cost_scale, P.seed,
                                     P.evaluation.queries_per_map)
            low = {name: shares[:, 0] for name, shares in result.shares.items()}
            for name in (UNIFORM, ORACLE):
                drift = abs(float(low[name].mean()) - committed[preference, name]["low"])
                if drift > 1e-9:
                    print(f"  WARNING: {name} low share {low[name].mean():.4f} differs from the committed table's "
                          f"{committed[preference, name]['low']:.4f}: data/ is not the data the tables were made from")
            claim = gap_closed(REFERENCE, low[REFERENCE], low[UNIFORM], low[ORACLE], terrains, preference)
            # the same cost rule with the true labels: what recognition alone costs the reference
            of_truth = gap_closed(REFERENCE, low[REFERENCE], low[UNIFORM], low[TRUTH], terrains, preference, "truth")
            told_context = gap_closed(TOLD_CONTEXT, low[TOLD_CONTEXT], low[UNIFORM], low[ORACLE], terrains, preference)
            limited = gap_closed(LIMITED, low[LIMITED], low[UNIFORM], low[ORACLE], terrains, preference)
            pacer = committed[preference, "D_synthetic"]["low"]
            chance, ceiling = float(low[UNIFORM].mean()), float(low[ORACLE].mean())
            pacer_gap = (pacer - chance) / (ceiling - chance)
            print(f"  {terrains}/{preference}: " + "; ".join(
                f"{r['method']} {r['low']:.3f} [{r['low_ci'][0]:.3f}, {r['low_ci'][1]:.3f}]" for r in result.rows))
            print(f"    reference: {claim.ours}")
            print(f"    reference against the true labels under its own cost rule: {of_truth.ours}")
            print(f"    segmenter told the context's pairs: {told_context.ours}")
            print(f"    context-limited oracle (true labels, the same costs): {limited.ours}")
            print(f"    PACER D_synthetic (committed table): {pacer:.3f}, {pacer_gap:.2f} of the gap")
            found.append({"terrains": terrains, "preference": preference, "pixel_accuracy": accuracy,
                          "recall": {names[t]: r for t, r in recall.items()}, "rows": result.rows,
                          "reference_gap": claim.ours, "reference_of_truth": of_truth.ours,
                          "told_context_gap": told_context.ours, "context_limited_oracle_gap": limited.ours,
                          "pacer_low": pacer, "pacer_gap": pacer_gap})
    if args.out is not None:
        args.out.write_text(json.dumps({"settings": dataclasses.asdict(settings),
                                        "profile": args.profile, "results": found}, indent=1, default=float))
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
