"""PACER training targets and layouts, measured where the robot needs them: the maps' low-tier share.

Fine-tunes the committed phase-3 model (``artifacts/pacer/phase3``) for a few epochs on the phase-3
datasets under each requested ``pacer.data.train_target`` (in_view or context) and street-window
fraction (``pacer.data.layout.street_windows``), then plans on the aerial maps of both groups under the
realistic and inverted preference and prints each model's low-tier share and the share of the gap from
the uniform costmap (chance) to the in-view window oracle it closes (issue 24's yardstick), beside the
committed model. Usage:
python benchmarks/pacer_target_layouts.py [--profile default] --epochs 8 --street 0.5 --targets in_view context [--out DIR]
"""

from __future__ import annotations

import argparse
import dataclasses
import time

from torch.utils.data import Subset

from navlab.core.params import load_params
from navlab.pacer.aerial import aerial_maps
from navlab.pacer.artifacts import selection_windows
from navlab.pacer.datasets import pacer_dataset
from navlab.pacer.experiments import (
    context_limited_oracle_method,
    navigation_rows,
    pacer_method,
    uniform_method,
    window_oracle_method,
)
from navlab.pacer.terrain import load_terrain_bank
from navlab.pacer.train import PHASE_DATASETS, PhaseRun, Selection, load_model, train_phase


def with_data(params, target: str, street: float):
    data = params.pacer.data
    data = dataclasses.replace(data, train_target=target,
                               layout=dataclasses.replace(data.layout, street_windows=street))
    return dataclasses.replace(params, pacer=dataclasses.replace(params.pacer, data=data))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--epochs", type=int, default=8)
    parser.add_argument("--street", type=float, default=0.0)
    parser.add_argument("--targets", nargs="*", default=["in_view", "context"])
    parser.add_argument("--data", default="data")
    parser.add_argument("--artifacts", default="artifacts")
    parser.add_argument("--out", default="/tmp/pacer_target_layouts")
    args = parser.parse_args()
    base = load_params(args.profile)
    bank = load_terrain_bank(args.data, base.pacer.data)
    committed = f"{args.artifacts}/pacer/phase3/model.pt"
    models = {"committed": load_model(committed)}
    for target in args.targets:
        params = with_data(base, target, args.street)
        P, names, start = params.pacer, PHASE_DATASETS["phase3"], time.perf_counter()
        path = train_phase(
            P.model, dataclasses.replace(P.train, patience=args.epochs),
            [pacer_dataset(params, args.data, n, "train", bank) for n in names],
            [Subset(pacer_dataset(params, args.data, n, "val", bank), range(P.train.val_examples)) for n in names],
            f"{args.out}/{target}_{args.epochs}_{args.street}",
            PhaseRun("phase3", args.epochs, P.seed + 1, P.data.n_pairs, committed), progress=False,
            selection=Selection(selection_windows(params, args.data, bank), P.evaluation.cost_scale))
        print(f"fine-tuned with {target} targets, street windows {args.street}: {time.perf_counter() - start:.0f} s")
        models[f"{target} targets"] = load_model(path)
    methods = {name: (pacer_method(m, base.pacer.data), True) for name, m in models.items()}
    methods |= {"window oracle (in_view)": (window_oracle_method(base.pacer.data), True),
                "window oracle (context)": (window_oracle_method(with_data(base, "context", 0.0).pacer.data), True),
                "context-limited oracle": (context_limited_oracle_method(), True), "uniform": (uniform_method(), True)}
    P = base.pacer
    for env in ("seen", "unseen"):
        maps = aerial_maps(base, args.data, env, bank)
        for preference in ("realistic", "inverted"):
            rows = navigation_rows(maps, methods, bank, P.data, preference, P.evaluation.cost_scale, P.seed,
                                   P.evaluation.queries_per_map).rows
            low = {r["method"]: r["low"] for r in rows}
            chance, ceiling = low["uniform"], low["window oracle (in_view)"]
            print(f"{env}/{preference}: " + "; ".join(
                f"{name} {value:.3f} (gap {(value - chance) / (ceiling - chance):.2f})" for name, value in low.items()))


if __name__ == "__main__":
    main()
