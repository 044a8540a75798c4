"""The stack's ablation over its episodes: every row on every episode, in forked workers (one torch thread
each; the layers, PACER's network and HJ-search's memory-mapped grids, loaded once before the fork)."""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing import get_context

import torch

from navlab.core.params import Params
from navlab.maps.dataset import load_maps
from navlab.pacer.terrain import load_terrain_bank
from navlab.stack.ablation import Outcome, load_layers, run_episode
from navlab.stack.world import stack_episode

_JOB: dict = {}  # what the forked workers read: params, tiles, bank, layers


def _one_thread() -> None:
    torch.set_num_threads(1)


def _episode(index: int) -> list[Outcome]:
    job = _JOB
    episode = stack_episode(index, job["tiles"], job["params"], job["bank"])
    return run_episode(episode, job["layers"], job["params"])


def run_ablation(params: Params, data_dir: str, artifacts_dir: str, log: Callable[[str], None] = print) -> list[Outcome]:
    """Every row of ``stack.ablation.ROWS`` on the ``stack.episodes`` episodes, on ``stack.workers`` processes,
    a progress line per episode; outcomes in episode order."""
    bank = load_terrain_bank(data_dir, params.pacer.data)
    _JOB.update(params=params, tiles=load_maps(data_dir, "test"), bank=bank,
                layers=load_layers(params, artifacts_dir, bank))
    count, began, done = params.stack.episodes, time.perf_counter(), {}
    try:
        if params.stack.workers == 1:
            _one_thread()
            results = map(_episode, range(count))
            for index, outcomes in enumerate(results):
                done[index] = outcomes
                log(f"stack: {len(done)}/{count} episodes ({time.perf_counter() - began:.0f} s)")
        else:
            with ProcessPoolExecutor(params.stack.workers, mp_context=get_context("fork"),
                                     initializer=_one_thread) as pool:
                futures = {pool.submit(_episode, index): index for index in range(count)}
                for future in as_completed(futures):
                    done[futures[future]] = future.result()
                    log(f"stack: {len(done)}/{count} episodes ({time.perf_counter() - began:.0f} s)")
    finally:
        _JOB.clear()
    return [outcome for index in range(count) for outcome in done[index]]

