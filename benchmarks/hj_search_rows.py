"""Table V's rows planned one task after another (``hj.planning.run_tasks``, the old notebook) beside the same
rows on ``--workers`` processes (``hj.search_rows.run_rows``, the notebook now), in one run: wall seconds,
their ratio, and that every result but the measured search seconds is the same.

The grids and the BRT margin are read from ``--artifacts`` (built there if missing).
Usage: python benchmarks/hj_search_rows.py [--profile default] [--artifacts artifacts] [--pairs 20] [--workers 2]
"""

from __future__ import annotations

import argparse
import dataclasses
import time

from navlab.core.params import load_params
from navlab.hj.grids import build_hj_grids
from navlab.hj.planning import Planner, TaskResult, random_pairs
from navlab.hj.search_rows import run_rows

ROWS = (("Dist + OBS", "Dist", "OBS"), ("TTR + BRT", "TTR", "BRT"))  # the paper's baseline row and its method


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--artifacts", default="artifacts")
    parser.add_argument("--pairs", type=int, default=20)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    params = load_params(args.profile)
    build_hj_grids(params, "unused", args.artifacts, progress=False)
    p = params.hj.planner
    planner = Planner(params, args.artifacts, p.table5.room, costs=True)
    print(f"BRT margin {planner.margin:.4f}")  # measured (or read) once, before the workers copy the planner
    pairs = random_pairs(planner.room, params.hj.grids.robot.radius_m, args.pairs, p.table5.min_distance_m,
                         params.hj.seed)
    rows = {label: (planner, pairs, h, pruner, "ANA*") for label, h, pruner in ROWS}
    timed = {}
    for workers in (1, args.workers):
        began = time.perf_counter()
        timed[workers] = (run_rows(rows, workers), time.perf_counter() - began)
    (serial, t1), (parallel, tn) = timed[1], timed[args.workers]
    timeless = [f.name for f in dataclasses.fields(TaskResult) if f.name != "seconds"]
    same = all([repr(getattr(a, f)) for f in timeless] == [repr(getattr(b, f)) for f in timeless]
               for label in rows for a, b in zip(serial[label], parallel[label], strict=True))
    print(f"{len(ROWS)} rows x {len(pairs)} pairs of ANA* ({p.anastar_max_expansions:,} expansions at most): one after "
          f"another {t1:.1f} s, on {args.workers} processes {tn:.1f} s: {t1 / tn:.2f}x; results equal: {same}")
    if not same:
        raise SystemExit("the rows planned on worker processes differ from the rows planned here")


if __name__ == "__main__":
    main()
