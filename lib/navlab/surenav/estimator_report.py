"""How well the trained estimators reproduce the expert's relaxations on the graph (validation vs test).

Per variant (GPS, and the MPNN-only ablation) and training seed: the relaxation IoU of the plan that
exact graph A* makes under the predicted Psi (``train.evaluate``), averaged over the validation
(procedural maps) and the test (real tiles) demonstrations. The gap between the two is the
procedural-to-real generalisation gap the issue asks to report; the spread is over training seeds.
This is the graph-level quantity the training optimises; Table I's IoU comes from full episodes.
The floor beside them: Psi = 0, the shortest graph path through any soft region.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import torch
from torch import nn

from navlab.core.params.surenav_model import TrainParams
from navlab.metrics.tables import Table
from navlab.surenav.artifacts import VARIANTS, model_path
from navlab.surenav.train import evaluate, load_estimator
from navlab.surenav.training_data import Sample

NAMES = {"gps": "SuReNav estimator (GPS)", "mpnn": "MPNN only (no attention, ablation)"}
FLOOR = "Psi = 0 (shortest graph path, floor)"
NOTES = ("Relaxation IoU of the exact graph A* plan under the predicted Psi (path regions in R_soft) vs the expert's "
         "relaxed superpixels, on the demonstration's own region graph cut to the query window; mean and standard "
         "deviation over training seeds. val = procedural validation maps, test = the real test tiles (all static and "
         "semi-static test demonstrations); test_minus_val is the procedural-to-real gap. The Psi = 0 row is the "
         "floor: the shortest graph path. model.pt holds each seed's epoch of best validation IoU (early stopping). "
         "The paper prints no such number.")
COLUMNS = ("method", "val_iou", "val_iou_sd", "test_iou", "test_iou_sd", "test_minus_val", "seeds")


class ZeroCost(nn.Module):
    """Psi = 0 on every node: graph A* then plans the shortest path through any soft region (the floor)."""

    def forward(self, data) -> torch.Tensor:
        return torch.zeros(data.num_nodes)


def estimator_rows(artifacts_dir: str | Path, seeds: Mapping[str, Sequence[int]], samples: Mapping[str, Sequence[Sample]],
                   train: TrainParams) -> list[dict]:
    """One row per variant: mean and standard deviation over its ``seeds[variant]`` of the plan IoU on each split
    of ``samples`` (keys ``val`` and ``test``)."""
    rows = []
    for variant in VARIANTS:
        per_split: dict[str, list[float]] = {split: [] for split in samples}
        for seed in seeds[variant]:
            model = load_estimator(model_path(artifacts_dir, variant, seed))
            for split, chosen in samples.items():
                per_split[split].append(evaluate(model, chosen, train)[1])
        row = {"method": NAMES[variant], "seeds": len(seeds[variant])}
        for split, values in per_split.items():
            row[f"{split}_iou"] = float(np.mean(values))
            row[f"{split}_iou_sd"] = float(np.std(values, ddof=1)) if len(values) > 1 else None
        rows.append(row)
    rows.append({"method": FLOOR, "seeds": None, **{f"{split}_iou_sd": None for split in samples},
                 **{f"{split}_iou": evaluate(ZeroCost(), chosen, train)[1] for split, chosen in samples.items()}})
    for row in rows:
        if "val_iou" in row and "test_iou" in row:
            row["test_minus_val"] = row["test_iou"] - row["val_iou"]
    return rows


def estimator_table(rows: list[dict]) -> Table:
    """``estimator_rows`` as a report (the paper prints no such number, so no paper rows and no claim)."""
    return Table("estimator_relaxation_iou", "SuReNav Sec. IV-D (no printed figure)", list(COLUMNS), rows, [], NOTES)
