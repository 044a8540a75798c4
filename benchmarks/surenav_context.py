"""SuReNav's context demonstrator (issue 25, step 1): its two properties through Table I's executor.

Redraws Table I's 100 human-likeness environments with the context demonstrator
(``navlab.surenav.context``), runs its own planner (the Expert row), the non-learned per-label cost
fields and SuReNav's executor with the rule Psi through ``benchmark.run_episode``, and prints every
row and the two properties (paired 95% bootstrap intervals) against the best per-label field, chosen
on the context VALIDATION demonstrations (``measure.select_field``: the surenav_context_demos stage's
train and val tiles), never on these test environments. Needs ``data/`` and that stage's output:
nothing here is trained. About 2.5 minutes on one core.
Usage: python benchmarks/surenav_context.py [--data data] [--artifacts artifacts] [--profile default]
[--out result.json]
"""

from __future__ import annotations

import argparse
import json
import time

from navlab.core.params import load_params
from navlab.surenav.context.dataset import load_context_demos
from navlab.surenav.context.environments import context_environments
from navlab.surenav.context.measure import measure, select_field


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--data", default="data")
    parser.add_argument("--artifacts", default="artifacts", help="holds surenav/context_demos (train and val)")
    parser.add_argument("--out", default=None, help="also write the result as JSON here")
    args = parser.parse_args()
    params = load_params(args.profile)
    s = params.surenav
    tic = time.perf_counter()
    envs, stored = context_environments(args.data, params.data.demos, s.demos.context, s.graph)
    field = select_field(load_context_demos(args.artifacts, "train"), load_context_demos(args.artifacts, "val"),
                         s.benchmark, s.graph)
    result = measure(envs, stored, field, s.benchmark, s.graph, s.demos.context, s.planner.mode,
                     s.model.window_margin_m)
    print(f"{result['environments']} environments, {time.perf_counter() - tic:.0f} s")
    print("| method | Fréchet | 95% CI | relaxation IoU | 95% CI | SR |\n|---|---|---|---|---|---|")
    for r in result["rows"]:
        print(f"| {r['method']} | {r['frechet']:.3f} | {r['frechet_ci']} | {r['relaxation_iou']:.3f} | "
              f"{r['relaxation_iou_ci']} | {r['sr']:.2f} |")
    print(f"best per-label field: {result['best_field']} (validation IoU {result['field_val_iou']})")
    for name in ("context_share", "region_expressible"):
        p = result[name]
        print(f"{name}: ΔIoU {p['delta_iou']:+.3f} {p['delta_iou_ci']} (at least {p['at_least']}): "
              f"{'holds' if p['holds'] else 'does not hold'}")
    if args.out:
        with open(args.out, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
