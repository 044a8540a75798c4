"""Discrete Fréchet distance: navlab's numba DP against similaritymeasures 1.5.0 (Python-loop DP), same run.

Both measure the same random-walk curve pairs; the script checks the values agree, and prints the
times and the ratio (target >= 100x at 500 points). The JIT is warmed before timing.
Usage: python benchmarks/frechet.py [--points 100 500 1000] [--repeats 3]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import similaritymeasures

from navlab.core.seeding import rng
from navlab.metrics.frechet import discrete_frechet


def _best_of(fn, repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        tic = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - tic)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, nargs="+", default=[100, 500, 1000])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    gen = rng(0, "benchmark", "frechet")
    discrete_frechet(np.zeros((2, 2)), np.ones((3, 2)))  # compile outside the timings
    print(f"{'points':>7} {'navlab ms':>10} {'similaritymeasures ms':>22} {'ratio':>8}")
    for n in args.points:
        p, q = gen.normal(size=(n, 2)).cumsum(axis=0), gen.normal(size=(n, 2)).cumsum(axis=0)
        ours, theirs = discrete_frechet(p, q), similaritymeasures.frechet_dist(p, q)
        if not np.isclose(ours, theirs, rtol=1e-12, atol=1e-12):
            raise SystemExit(f"values differ at n={n}: navlab {ours}, similaritymeasures {theirs}")
        t_ours = _best_of(lambda: discrete_frechet(p, q), args.repeats)  # noqa: B023
        t_ref = _best_of(lambda: similaritymeasures.frechet_dist(p, q), args.repeats)  # noqa: B023
        print(f"{n:>7} {1e3 * t_ours:>10.3f} {1e3 * t_ref:>22.1f} {t_ref / t_ours:>7.0f}x")


if __name__ == "__main__":
    main()
