"""PACER inference: our `default` costmap network against the paper-size architecture, same machine, same run.

The paper-size network is the released code's (U-Net 64…2048 with a 4096-wide bottleneck, ResNet-50
context encoder, concat-MLP fusion; ~573M parameters) built from the `paper` profile with random
weights: speed does not depend on the weights. Each model runs at its own profile's BEV size and,
for a like-for-like compute ratio, ours also at the paper's size. FLOPs come from
torch.utils.flop_counter. The tier scores of the reproduced tables are printed beside the ratio when
the reports exist.

Usage: python benchmarks/pacer_inference.py [--device cpu] [--repeats 3] [--reports-dir reports]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import torch
from torch.utils.flop_counter import FlopCounterMode

from navlab.core.params import load_params
from navlab.pacer.model import build_model, count_parameters


def inputs(profile: str, batch: int, device: str, size: int | None = None):
    data = load_params(profile).pacer.data
    side = size or data.image_size
    image = torch.rand(batch, 3, side, side, device=device)
    context = torch.rand(batch, 3 * data.n_pairs, 2 * data.patch_size, data.patch_size, device=device)
    return image, context


def flops(model, image, context) -> int:
    counter = FlopCounterMode(display=False)
    with counter, torch.no_grad():
        model(image[:1], context[:1])
    return counter.get_total_flops()


def costmaps_per_second(model, image, context, repeats: int) -> float:
    with torch.no_grad():
        model(image, context)  # warm-up
        if image.is_cuda:
            torch.cuda.synchronize()
        start = time.perf_counter()
        for _ in range(repeats):
            model(image, context)
        if image.is_cuda:
            torch.cuda.synchronize()
    return repeats * len(image) / (time.perf_counter() - start)


def tier_scores(reports_dir: Path) -> list[str]:
    lines = []
    for table in ("table1_seen", "table2_unseen"):
        path = reports_dir / "pacer" / f"{table}.json"
        if path.is_file():
            report = json.loads(path.read_text())
            for row in report["rows"]:
                if row.get("method") == "PACER":
                    lines.append(f"{table}: PACER low {row['low']}, medium {row['medium']}, high {row['high']} "
                                 f"({report['profile']} profile)")
    return lines or [f"no tier scores yet under {reports_dir}/pacer (run the pacer notebooks)"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--batch", type=int, default=8, help="costmaps per forward pass of our model")
    parser.add_argument("--paper-batch", type=int, default=1, help="costmaps per forward pass, paper-size model")
    parser.add_argument("--threads", type=int, default=None, help="torch CPU threads (default: torch's)")
    parser.add_argument("--reports-dir", default="reports")
    args = parser.parse_args()
    torch.manual_seed(0)
    if args.threads:
        torch.set_num_threads(args.threads)
    ours = build_model(load_params("default").pacer.model, device=args.device).eval()
    paper = build_model(load_params("paper").pacer.model, device=args.device).eval()
    paper_size = load_params("paper").pacer.data.image_size
    runs = [("ours (default)", ours, "default", None, args.batch),
            ("ours at paper size", ours, "default", paper_size, args.batch),
            ("paper-size architecture", paper, "paper", None, args.paper_batch)]
    results = {}
    for name, model, profile, size, batch in runs:
        image, context = inputs(profile, batch, args.device, size)
        results[name] = (flops(model, image, context), costmaps_per_second(model, image, context, args.repeats))
        print(f"{name:26s} {count_parameters(model) / 1e6:9.3f} M params, input {tuple(image.shape[1:])}, "
              f"{results[name][0] / 1e9:9.3f} GFLOP/costmap, {results[name][1]:9.2f} costmaps/s ({args.device})")
    paper_flops, paper_rate = results["paper-size architecture"]
    for name in ("ours (default)", "ours at paper size"):
        f, rate = results[name]
        print(f"compute ratio paper/{name}: {paper_flops / f:.0f}x fewer FLOPs, {rate / paper_rate:.0f}x more "
              f"costmaps/s (target >= 50x)")
    print(f"parameter ratio: {count_parameters(paper) / count_parameters(ours):.0f}x")
    for line in tier_scores(Path(args.reports_dir)):
        print(line)


if __name__ == "__main__":
    main()
