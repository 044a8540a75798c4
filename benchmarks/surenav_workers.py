"""SuReNav benchmark episodes on worker processes: one torch thread per worker against torch's default.

Runs every method of Table I / Fig. 4 on a subset of the safety-efficiency environments with
``run_all`` (2 workers, one torch thread each), then the same tasks on 2 workers that keep torch's
default thread count (the reference: what ``run_all`` did before), and on one process. It checks that
all three give the same outcomes and prints the times and the ratio. Needs ``data/`` and the
``surenav_estimator`` / ``surenav_episodes`` artifacts (``dvc repro surenav_episodes``).
Usage: python benchmarks/surenav_workers.py [--every 30] [--profile default]
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context

import numpy as np

from navlab.core.params import load_params
from navlab.metrics.navigation import risk_table
from navlab.surenav.benchmark import Learned, benchmark_runs, make_policy, run_all, run_episode
from navlab.surenav.episodes import safety_efficiency_environments


def _default_threads_episode(task):
    env, method, learned, settings, graph = task
    return run_episode(env, method, lambda w: make_policy(method, env, learned, settings, w.scale), settings, graph,
                       risk_table(settings.unit_risk))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--every", type=int, default=30, help="take every n-th environment")
    parser.add_argument("--profile", default="default")
    parser.add_argument("--data", default="data")
    parser.add_argument("--artifacts", default="artifacts")
    args = parser.parse_args()
    params = load_params(args.profile)
    settings, graph = params.surenav.benchmark, params.surenav.graph
    learned = Learned.from_training(args.data, settings, args.artifacts, params.surenav)
    envs = safety_efficiency_environments(args.data, args.artifacts)[::args.every]
    runs, _ = benchmark_runs(learned)
    two = dataclasses.replace(settings, workers=2)
    t0 = time.perf_counter()
    ours = run_all(envs, runs, learned, two, graph, progress=False)
    t1 = time.perf_counter()
    tasks = [(env, method, learned, settings, graph) for env in envs for method in runs]
    with ProcessPoolExecutor(2, mp_context=get_context("fork")) as pool:
        reference = list(pool.map(_default_threads_episode, tasks, chunksize=2))
    t2 = time.perf_counter()
    sequential = run_all(envs, runs, learned, dataclasses.replace(settings, workers=1), graph, progress=False)
    t3 = time.perf_counter()
    for a, b in zip(ours, sequential):
        assert a.status == b.status and np.array_equal(a.trajectory, b.trajectory), \
            f"{a.method} on {a.environment}: 2 workers and 1 process differ"
    same = sum(a.status == b.status and np.array_equal(a.trajectory, b.trajectory) for a, b in zip(ours, reference))
    print(f"{len(tasks)} episodes ({len(envs)} environments x {len(runs)} runs); run_all on 2 workers and on "
          f"1 process give the same trajectories; the default-thread reference agrees on {same}/{len(tasks)}")
    print(f"run_all, 2 workers x 1 torch thread {t1 - t0:.1f} s; 2 workers x default threads (reference) "
          f"{t2 - t1:.1f} s; 1 process x 1 thread {t3 - t2:.1f} s; ratio ours/reference {(t1 - t0) / (t2 - t1):.3f}")


if __name__ == "__main__":
    main()
