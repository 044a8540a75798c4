"""How much Table VIII's Dense Room and Table IX's two-human cells move from one seeded run to the next.

Why (issue 26, "no worse than today"): one seeded run of a cell is 6 or 9 trips, so a cell that moved
between two commits may have moved by chance (the tables now pool hj.dynamic.table8/table9.runs runs per
cell for that reason). This re-runs the cells with runs first..N-1 (run r draws its pose and observation
noise from hj.dynamic.seed + r; runs 0..runs-1 are the tables') and prints each run's successes and
contacts, so a change can be read against the spread of the same code.

    .venv/bin/python benchmarks/hj_closed_loop_spread.py --first 4 --runs 8 --workers 2 [--profile default]
"""

from __future__ import annotations

import argparse
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from navlab.core.params import load_params
from navlab.hj.closed_loop import summarise_patrols, summarise_trips
from navlab.hj.scenarios import HUMAN_ROWS, ROOM_COMBOS, ClosedLoop

ARTIFACTS = Path(__file__).resolve().parents[1] / "artifacts"


def _cell(job):
    profile, artifacts, kind, method, run = job
    loop = ClosedLoop(load_params(profile), artifacts, log=lambda *_: None)
    if kind == "dense":
        heuristic, pruner = method.split(" + ")
        row = summarise_trips(method, "Dense Room", [loop.room_patrol("dense_room", heuristic, pruner, run)])
        return kind, method, run, f"{row['success']}/{row['trips']} (deadlocks {row['deadlocks']}, wall hits {row['wall_hits']})"
    row = summarise_patrols(method, 2, [loop.human_patrol(method, 2, run)], seed=0)
    return kind, method, run, f"{row['success']}/{row['trips']} (contacts {row['collisions']})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--first", type=int, default=0, help="first run index")
    parser.add_argument("--runs", type=int, default=5, help="one past the last run index")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--profile", default=None, help="params.yaml's own profile unless given")
    parser.add_argument("--artifacts", type=Path, default=ARTIFACTS)
    args = parser.parse_args()
    cells = [("dense", f"{h} + {p}") for h, p in ROOM_COMBOS] + [("humans", m) for m in HUMAN_ROWS]
    jobs = [(args.profile, args.artifacts, kind, method, r) for kind, method in cells for r in range(args.first, args.runs)]
    with ProcessPoolExecutor(args.workers) as pool:
        results = list(pool.map(_cell, jobs))
    for kind, title in (("dense", "Table VIII, Dense Room"), ("humans", "Table IX, two humans")):
        print(f"{title}, runs {args.first}..{args.runs - 1}:")
        for method in dict.fromkeys(m for k, m, _, _ in results if k == kind):
            cells = [text for k, m, _, text in sorted(results, key=lambda x: x[2]) if k == kind and m == method]
            print(f"  {method:12s} " + "; ".join(cells))


if __name__ == "__main__":
    main()
