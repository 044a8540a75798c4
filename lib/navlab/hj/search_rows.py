"""The rows of Tables I-V (HJ-search paper Sec. VII-A to VII-C) planned in worker processes.

Why: a row plans every task of its list (start, goal) with one heuristic, pruner and algorithm, and each
task's result is a pure function of the planner's inputs (the search is deterministic; only its measured
seconds depend on the machine), so the tasks of all rows run side by side on ``hj.workers`` processes
instead of one after another on one core: Table V alone, 100 pairs x 8 rows of ANA*, took 442 s on one
core of the two (2026-12-03). Each worker receives the notebook's planners once (value functions and BRT
margin as measured) and runs one torch thread, as the closed-loop workers do (``hj.scenarios.run_cells``).
The per-call timing of Table VII stays serial (``hj.timing``): there the seconds are the result.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor

from navlab.hj.planning import Planner, TaskResult, run_tasks

Row = tuple[Planner, Sequence[tuple], str, str, str]  # planner, tasks (start, goal_xy), heuristic, pruner, algorithm

_PLANNERS: tuple[Planner, ...] = ()  # each worker's copies of the planners


def _start_worker(planners: tuple[Planner, ...]) -> None:
    import torch

    global _PLANNERS
    torch.set_num_threads(1)  # one thread per process: two processes' thread pools would contend for the cores
    _PLANNERS = planners


def _plan(job: tuple) -> TaskResult:
    which, start, goal, heuristic, pruner, algorithm = job
    return _PLANNERS[which].run(start, goal, heuristic, pruner, algorithm)[0]


def run_rows(rows: Mapping[str, Row], workers: int) -> dict[str, list[TaskResult]]:
    """{label: (planner, tasks, heuristic, pruner, algorithm)} -> {label: one TaskResult per task, in order},
    as ``hj.planning.run_tasks`` gives them row by row (which runs them here when ``workers`` <= 1), or in
    ``workers`` processes.
    A planner that uses the BRT pruner should have measured its margin first (``planner.margin``), so that
    the workers read it rather than each measuring it."""
    if workers <= 1:
        return {label: run_tasks(*row) for label, row in rows.items()}
    planners = tuple({id(r[0]): r[0] for r in rows.values()}.values())
    which = {id(p): i for i, p in enumerate(planners)}
    jobs = [(which[id(planner)], start, goal, heuristic, pruner, algorithm)
            for planner, tasks, heuristic, pruner, algorithm in rows.values() for start, goal in tasks]
    with ProcessPoolExecutor(min(workers, max(len(jobs), 1)), initializer=_start_worker, initargs=(planners,)) as pool:
        results = list(pool.map(_plan, jobs))
    done = iter(results)
    return {label: [next(done) for _ in row[1]] for label, row in rows.items()}
