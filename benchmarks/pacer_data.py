"""PACER data: item throughput per dataset on one core, and the vectorised margin ranking error against a
plain pair loop, same run.

Items are made on the fly in DataLoader workers, so generation must outpace CPU training (target:
200 items/s per core at the ``default`` size). Prints items/s (process CPU time, OpenCV on one thread)
per dataset and the margin-ranking speed-up with identical results.
Usage: python benchmarks/pacer_data.py [--profile default] [--items 300] [--data-dir data]
"""

from __future__ import annotations

import argparse
import itertools
import time

import cv2
import numpy as np

from navlab.core.params import load_params
from navlab.core.seeding import rng
from navlab.pacer.datasets import evaluation_dataset, pacer_dataset
from navlab.pacer.margin_ranking import margin_ranking_error
from navlab.pacer.terrain import load_terrain_bank

TARGET_ITEMS_PER_S = 200.0


def margin_ranking_loop(pred: np.ndarray, labels: np.ndarray, ordering: np.ndarray, points: np.ndarray) -> float:
    """The textbook definition, one pair at a time (the reference)."""
    rank = {int(t): i for i, t in enumerate(ordering)}
    total, count = 0.0, 0
    for a, b in itertools.combinations(points.tolist(), 2):
        pa, pb = pred.flat[a], pred.flat[b]
        ra, rb = rank[int(labels.flat[a])], rank[int(labels.flat[b])]
        if ra == rb or (ra < rb) != (pa < pb):
            total += abs(pa - pb)
        count += 1
    return total / count


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--items", type=int, default=300)
    parser.add_argument("--data-dir", default="data")
    args = parser.parse_args()
    cv2.setNumThreads(1)
    params = load_params(args.profile)
    bank = load_terrain_bank(args.data_dir, params.pacer.data)
    datasets = {name: pacer_dataset(params, args.data_dir, name, bank=bank) for name in ("real", "shuffled", "synthetic")}
    datasets["eval-unseen"] = evaluation_dataset(params, args.data_dir, "unseen", "realistic", bank=bank)
    for name, dataset in datasets.items():
        count = min(args.items, len(dataset))
        start = time.process_time()
        for index in range(count):
            dataset[index]
        rate = count / (time.process_time() - start)
        print(f"{name:12s} {params.pacer.data.image_size}px: {rate:6.0f} items/s per core "
              f"({rate / TARGET_ITEMS_PER_S:.1f}x the {TARGET_ITEMS_PER_S:.0f} items/s target)")

    item = datasets["real"].item(0)
    ordering = item["ordering"][item["ordering"] >= 0]
    pred = item["costmap"] + rng(0, "benchmark", "noise").normal(0.0, 0.2, item["costmap"].shape)
    start = time.perf_counter()
    ours = margin_ranking_error(pred, item["labels"], ordering, 500, rng=rng(0, "benchmark", "points"))
    t_ours = time.perf_counter() - start
    valid = np.flatnonzero(item["labels"] >= 0)  # the same 500 points margin_ranking_error draws
    points = rng(0, "benchmark", "points").choice(valid, size=min(500, len(valid)), replace=False)
    start = time.perf_counter()
    reference = margin_ranking_loop(pred, item["labels"], ordering, points)
    t_ref = time.perf_counter() - start
    assert np.isclose(ours, reference), (ours, reference)
    print(f"margin ranking error (500 points, {len(points) * (len(points) - 1) // 2} pairs): {ours:.4f}; "
          f"vectorised {t_ours * 1e3:.1f} ms, pair loop {t_ref * 1e3:.0f} ms, speed-up {t_ref / t_ours:.0f}x")


if __name__ == "__main__":
    main()
