"""Grid searches side by side in one run, on the real test maps of data/ (SuReNav benchmark tiles).

1. navlab grid A* (numba) against scikit-image's MCP_Geometric (Cython Dijkstra) on the same
   single-pair queries and cost model; both costs must agree.
2. D* Lite re-planning against from-scratch grid A* while an agent walks its path and cells ahead of it
   get blocked (semi-static changes); both must give the same cost after every change.

Times exclude numba compilation (every compiled function is called once before timing). Usage:
python benchmarks/grid_astar.py [--data-dir data] [--queries 30] [--walks 6]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from navlab.core.labels import cost_raster
from navlab.core.seeding import rng
from navlab.maps.dataset import load_maps
from navlab.search.dstar_lite import DStarLite
from navlab.search.grid_astar import plan
from navlab.search.grid_reference import dijkstra_cost

# per-metre costs of the soft labels for the benchmark rasters (free = 1, hard = blocked)
SOFT_COST = {"crosswalk": 1.2, "road": 6.0, "living_street": 2.0, "parking": 2.5, "grass": 3.0, "rough_terrain": 4.0}


def _queries(gen, cost: np.ndarray, count: int, min_cells: int) -> list[tuple[tuple, tuple]]:
    free = np.argwhere(np.isfinite(cost))
    pairs = []
    while len(pairs) < count:
        a, b = free[gen.choice(len(free), 2, replace=False)]
        if np.hypot(*(a - b)) >= min_cells and np.isfinite(dijkstra_cost(cost, tuple(a), tuple(b))):
            pairs.append((tuple(int(v) for v in a), tuple(int(v) for v in b)))
    return pairs


def astar_vs_mcp(maps, gen, queries: int) -> None:
    t_ours = t_ref = 0.0
    expansions = 0
    for smap in maps:
        cost = cost_raster(smap.labels, SOFT_COST)
        for start, goal in _queries(gen, cost, queries, min_cells=30):
            t0 = time.perf_counter()
            ours = plan(cost, start, goal, resolution=smap.frame.resolution)
            t1 = time.perf_counter()
            reference = dijkstra_cost(cost, start, goal, resolution=smap.frame.resolution)
            t2 = time.perf_counter()
            assert np.isclose(ours.cost, reference, rtol=1e-9), (smap.name, start, goal, ours.cost, reference)
            t_ours, t_ref, expansions = t_ours + t1 - t0, t_ref + t2 - t1, expansions + ours.expansions
        print(f"  {smap.name} {smap.labels.shape}: {queries} queries done")
    n = queries * len(maps)
    print(f"grid A* vs MCP_Geometric, {n} queries: navlab {1e3 * t_ours / n:.1f} ms/query "
          f"({expansions / n:.0f} expansions), MCP_Geometric {1e3 * t_ref / n:.1f} ms/query; "
          f"speed-up (MCP time / ours) {t_ref / t_ours:.2f}x")


def dstar_vs_replanning(maps, gen, walks: int, block: int = 3, every: int = 5) -> None:
    """Walk each query's path; every ``every`` steps block a block x block square on the path ahead."""
    t_dstar = t_astar = 0.0
    replans = exp_dstar = exp_astar = 0
    for smap in maps:
        base = cost_raster(smap.labels, SOFT_COST)
        res = smap.frame.resolution
        for start, goal in _queries(gen, base, walks, min_cells=80):
            cost = base.copy()
            t0 = time.perf_counter()
            agent = DStarLite(cost, start, goal, resolution=res)
            path = agent.plan()
            t_dstar += time.perf_counter() - t0
            here, step = start, 0
            while path.cells is not None and len(path.cells) > 1:
                here = tuple(int(v) for v in path.cells[1])
                step += 1
                changed = np.empty((0, 2), np.int64)
                if step % every == 0 and len(path.cells) > 12:
                    centre = path.cells[int(gen.integers(6, min(len(path.cells) - 1, 30)))]
                    rr, cc = np.mgrid[-(block // 2):block // 2 + 1, -(block // 2):block // 2 + 1]
                    cells = np.stack([rr.ravel() + centre[0], cc.ravel() + centre[1]], axis=1)
                    inside = (cells >= 0).all(axis=1) & (cells < cost.shape).all(axis=1)
                    cells = cells[inside]
                    cells = cells[~((cells == here).all(axis=1) | (cells == goal).all(axis=1))]
                    changed = cells[np.isfinite(cost[cells[:, 0], cells[:, 1]])]
                    cost[changed[:, 0], changed[:, 1]] = np.inf
                t0 = time.perf_counter()
                agent.move_to(here)
                if len(changed):
                    agent.update_costs(changed, np.full(len(changed), np.inf))
                path = agent.plan()
                t1 = time.perf_counter()
                if len(changed):  # A* has to plan again from scratch only when something changed
                    scratch = plan(cost, here, goal, resolution=res)
                    t2 = time.perf_counter()
                    assert np.isclose(path.cost, scratch.cost, rtol=1e-9), (smap.name, path.cost, scratch.cost)
                    t_astar += t2 - t1
                    replans += 1
                    exp_astar += scratch.expansions
                    exp_dstar += path.expansions
                t_dstar += t1 - t0
    print(f"D* Lite vs from-scratch A*, {walks * len(maps)} walks, {replans} re-plans after a change: "
          f"D* Lite {t_dstar:.3f} s for the whole walks incl. the first plan "
          f"({exp_dstar / max(replans, 1):.0f} expansions per repair), A* {t_astar:.3f} s for its re-plans only "
          f"({exp_astar / max(replans, 1):.0f} expansions each); speed-up (A* / D* Lite) {t_astar / t_dstar:.2f}x")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data-dir", default="data")
    parser.add_argument("--queries", type=int, default=30, help="A* queries per map")
    parser.add_argument("--walks", type=int, default=6, help="D* Lite walks per map")
    args = parser.parse_args()
    maps = load_maps(args.data_dir, "test")
    warm = np.ones((8, 8))
    plan(warm, (0, 0), (7, 7))
    agent = DStarLite(warm, (0, 0), (7, 7))
    agent.plan()
    agent.move_to((1, 1))
    agent.update_costs(np.array([[3, 3]]), np.array([np.inf]))
    agent.plan()
    gen = rng(0, "benchmark", "grid_astar")
    astar_vs_mcp(maps, gen, args.queries)
    dstar_vs_replanning(maps, gen, args.walks)


if __name__ == "__main__":
    main()
