"""Grid A* (navlab, pure Python heap) against scikit-image's MCP_Geometric (Cython Dijkstra), same run.

Both solve the same single-pair query on the same cost model; the script prints times, expansions and
the ratio. Usage: python benchmarks/grid_astar.py [--size 600] [--queries 5]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from navlab.core.seeding import rng
from navlab.search.grid_astar import plan
from navlab.search.grid_reference import dijkstra_cost


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=600)
    parser.add_argument("--queries", type=int, default=5)
    args = parser.parse_args()
    gen = rng(0, "benchmark", "grid_astar")
    cost = gen.uniform(1.0, 4.0, (args.size, args.size))
    cost[gen.random(cost.shape) < 0.2] = np.inf
    t_ours = t_ref = 0.0
    for _ in range(args.queries):
        free = np.argwhere(np.isfinite(cost))
        start, goal = (tuple(free[i]) for i in gen.choice(len(free), 2, replace=False))
        t0 = time.perf_counter()
        ours = plan(cost, start, goal)
        t1 = time.perf_counter()
        reference = dijkstra_cost(cost, start, goal)
        t2 = time.perf_counter()
        t_ours, t_ref = t_ours + t1 - t0, t_ref + t2 - t1
        assert np.isclose(ours.cost, reference) or not np.isfinite(reference)
        print(f"query {start}->{goal}: cost {ours.cost:.1f}, A* {t1 - t0:.3f} s ({ours.expansions} expansions), "
              f"MCP_Geometric {t2 - t1:.3f} s")
    print(f"total: navlab A* {t_ours:.2f} s, MCP_Geometric {t_ref:.2f} s, ratio ours/reference {t_ours / t_ref:.2f}")


if __name__ == "__main__":
    main()
