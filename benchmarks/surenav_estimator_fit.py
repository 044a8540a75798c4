"""Does SuReNav's context estimator fit what it can express? (issue 25: a learned model below a simpler one)

The context estimator reads, per node, every quantity the context demonstrator's rules decide on
(``surenav.context.features``), so the rule Psi at the personas' mean tolerances is a function of its
input. This script puts three things on the estimator's own graph-level metric (plan relaxation IoU of
``surenav.train.evaluate`` on the stored train / val context demonstrations, default profile):

- ``rule``: the rule Psi itself, no learning (what a per-node function of the input reaches);
- ``regress``: the estimator trained to regress log(1 + rule Psi) (capacity: can the network represent it?);
- ``train``: the estimator trained as ``surenav_context_estimator`` does (Eq. 13 through the
  differentiable A*), with optional overrides of the temperature, gamma, lr and epochs.

Run from the checkout with the default artefacts built (``dvc repro surenav_context_demos``):
    python benchmarks/surenav_estimator_fit.py rule
    python benchmarks/surenav_estimator_fit.py regress --epochs 4 --lr 1e-3
    python benchmarks/surenav_estimator_fit.py train --epochs 10 --temperature 30
One line per epoch: loss, val IoU, train IoU (every 5th training sample), seconds. Results: README.md.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np
import torch
from torch_geometric.data import Batch

from navlab.core.labels import NUM_LABELS
from navlab.core.params import load_params, repo_root
from navlab.core.seeding import rng
from navlab.core.training import descend
from navlab.surenav.context.features import CONTEXT_FEATURES, FEATURE_SETS, ContextEstimator
from navlab.surenav.context.personas import mean_persona
from navlab.surenav.context.regions import RegionContext
from navlab.surenav.context.rules import relaxation_costs
from navlab.surenav.context.training import context_samples
from navlab.surenav.train import TRAIN_IOU_STRIDE, evaluate, plan_batch, training_loss


def rule_psi(x: torch.Tensor, soft: torch.Tensor) -> torch.Tensor:
    """The rules' Psi at the personas' mean tolerances, read back from the estimator's own input columns
    (one-hot label first, the six context columns last: ``features.context_features``)."""
    x = x.numpy()
    ctx = x[:, -len(CONTEXT_FEATURES):]
    context = RegionContext(label=x[:, :NUM_LABELS].argmax(1), area_m2=np.expm1(ctx[:, 0]) * 100.0,
                            patch_m2=np.expm1(ctx[:, 1]) * 100.0, by_sidewalk=ctx[:, 2] > 0.5,
                            crossing_point=ctx[:, 3] > 0.5, on_walkway=ctx[:, 4] > 0.5,
                            beside_obstacle=ctx[:, 5] > 0.5)
    return torch.tensor(relaxation_costs(context, mean_persona()), dtype=torch.float32) * soft.float()


class RulePsi(torch.nn.Module):
    """``rule_psi`` as an estimator (no parameters to learn)."""

    def forward(self, data) -> torch.Tensor:
        return rule_psi(data.x, data.soft)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("variant", choices=("rule", "regress", "train"))
    parser.add_argument("--epochs", type=int, default=8)
    parser.add_argument("--lr", type=float)
    parser.add_argument("--temperature", type=float)
    parser.add_argument("--gamma", type=float)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--profile", default="default")
    parser.add_argument("--artifacts", type=Path, default=Path(repo_root(), "artifacts"))
    args = parser.parse_args()
    torch.set_num_threads(1)
    params = load_params(args.profile).surenav
    overrides = {k: v for k, v in (("lr", args.lr), ("temperature", args.temperature), ("gamma", args.gamma))
                 if v is not None}
    train = dataclasses.replace(params.train, **overrides)
    artifacts, start = args.artifacts, time.perf_counter()
    samples = {split: context_samples(artifacts, split, params.graph, params.model, "context") for split in ("train", "val")}
    print(f"{len(samples['train'])} train / {len(samples['val'])} val demonstrations; overrides {overrides}", flush=True)
    if args.variant == "rule":
        for split in ("val", "train"):
            print(f"rule Psi: {split} IoU {evaluate(RulePsi(), samples[split][::1 if split == 'val' else TRAIN_IOU_STRIDE], train)[1]:.4f}")
        return
    torch.manual_seed(args.seed)
    model = ContextEstimator(params.model, True, FEATURE_SETS["context"])
    optimiser = torch.optim.AdamW(model.parameters(), lr=train.lr, weight_decay=train.weight_decay)
    for epoch in range(args.epochs):
        model.train()
        order = rng(args.seed, "surenav.context.train", epoch).permutation(len(samples["train"]))
        losses = []
        for lo in range(0, len(order), train.batch_size):
            chunk = [samples["train"][i] for i in order[lo:lo + train.batch_size]]
            if args.variant == "regress":
                batch = Batch.from_data_list([s.data for s in chunk])
                soft = batch.soft.bool()
                loss = torch.nn.functional.mse_loss(torch.log1p(model(batch)[soft]),
                                                    torch.log1p(rule_psi(batch.x, batch.soft)[soft]))
            else:
                loss = training_loss(*plan_batch(model, chunk, train.temperature), train)
            descend(loss, optimiser)
            losses.append(float(loss.detach()))
        val = evaluate(model, samples["val"], train)[1]
        fit = evaluate(model, samples["train"][::TRAIN_IOU_STRIDE], train)[1]
        print(f"{args.variant} epoch {epoch + 1}: loss {np.mean(losses):.4f}, val IoU {val:.4f}, train IoU {fit:.4f}, "
              f"{time.perf_counter() - start:.0f} s", flush=True)


if __name__ == "__main__":
    main()
