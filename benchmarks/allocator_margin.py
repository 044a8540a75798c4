"""Side by side: one static-BRT solve of the ``hj_margins`` kind with glibc's default malloc against
``navlab.core.allocator.keep_freed_memory`` (what ``python -m navlab`` sets for every stage).

The solve is the margin stage's: the ``default`` profile's simulation-room static BRT on the grid refined by
``--refine`` (the stage's ``hj.planner.brt_margin_refine``, 2 x 2 x 1 x 2), run for ``--horizon`` seconds of the
BRT (the stage runs to convergence, up to 8 s: the cost per step is what compares). Each variant runs in its own
process, alternating ``--repeats`` times; printed per run: wall, user and system CPU seconds and minor page faults,
then the median CPU-time ratio (tuned / default) and whether the two value functions are bit for bit equal.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import textwrap

WORKER = textwrap.dedent("""
    import hashlib, json, resource, sys, time
    import torch
    from navlab.core.allocator import keep_freed_memory
    from navlab.core.params import load_params
    from navlab.hj.brt_margin import refined_grid
    from navlab.hj.grids import _car, _settings, room_obstacle_distance, static_brt_spec
    from navlab.hj.reachability import static_brt
    from navlab.maps.rooms import load_room
    from navlab.reach.solver import Backend
    mode, refine, horizon, threads = sys.argv[1], tuple(json.loads(sys.argv[2])), float(sys.argv[3]), int(sys.argv[4])
    if mode == "tuned":
        keep_freed_memory()
    torch.set_num_threads(threads)
    params = load_params("default")
    g, b = params.hj.grids, params.hj.grids.static_brt
    grid = refined_grid(static_brt_spec(params, "simulation").grid, refine)
    before, start = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
    solution = static_brt(room_obstacle_distance(load_room("simulation"), grid), _car(params), grid,
                          robot_radius=g.robot.radius_m, max_horizon=horizon, band=b.band_m, tolerance=b.tolerance_m,
                          window=b.window_s, settings=_settings(params),
                          backend=Backend(device="cpu", progress=False, compile=False))
    after = resource.getrusage(resource.RUSAGE_SELF)
    digest = hashlib.sha256(solution.values.detach().cpu().numpy().tobytes()).hexdigest()
    print(json.dumps({"mode": mode, "shape": list(grid.shape), "wall_s": time.perf_counter() - start,
                      "user_s": after.ru_utime - before.ru_utime, "sys_s": after.ru_stime - before.ru_stime,
                      "faults": after.ru_minflt - before.ru_minflt, "digest": digest}))
""")


def run(mode: str, args) -> dict:
    env = {k: v for k, v in os.environ.items() if not k.startswith("MALLOC_")}
    out = subprocess.run([sys.executable, "-c", WORKER, mode, json.dumps(args.refine), str(args.horizon),
                          str(args.threads)], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--refine", type=int, nargs=4, default=[2, 2, 1, 2])
    parser.add_argument("--horizon", type=float, default=0.5, help="seconds of the BRT to solve")
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--threads", type=int, default=1)
    args = parser.parse_args()
    rows = []
    for _ in range(args.repeats):
        for mode in ("default", "tuned"):
            row = run(mode, args)
            rows.append(row)
            print(f"{mode:8s} {tuple(row['shape'])}: wall {row['wall_s']:.1f} s, user {row['user_s']:.1f} s, "
                  f"sys {row['sys_s']:.1f} s, {row['faults']:,} page faults", flush=True)
    cpu = {m: statistics.median(r["user_s"] + r["sys_s"] for r in rows if r["mode"] == m) for m in ("default", "tuned")}
    same = len({r["digest"] for r in rows}) == 1
    print(f"CPU seconds, median: default {cpu['default']:.1f}, tuned {cpu['tuned']:.1f}: ratio "
          f"{cpu['tuned'] / cpu['default']:.2f}; value functions bit for bit equal: {same}")


if __name__ == "__main__":
    main()
