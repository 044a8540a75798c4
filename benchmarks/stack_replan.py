"""Side by side: the stack's local re-plan (``navlab.stack.motion.HJFollower``) against the 83 ms period of a
12 Hz re-plan, and against the same follower as HJ-search's own code would run it per call (the primitive table
rebuilt by every search, the OBS clearance rasters at the rooms' 0.02 m).

Each episode of the stack's world (``stack_episode``) is driven once per variant along the context
demonstrator's route (no trained layer is needed: the route is SuReNav's Expert's), among its pedestrians,
re-planning at ``stack.replan_hz`` in simulated time; printed per variant: re-plans, p50 / p95 / max wall time
per re-plan, the p95 as a share of the period, the trips' outcomes; then the tuned / reference p95 ratio.
One torch thread; other jobs on the machine lengthen both variants alike (they alternate per episode).
"""

from __future__ import annotations

import argparse
import json

import numpy as np
import torch

from navlab.core.params import load_params
from navlab.maps.dataset import load_maps
from navlab.pacer.terrain import load_terrain_bank
from navlab.stack.ablation import drive
from navlab.stack.motion import HJFollower, allowed_ground
from navlab.stack.route import expert_route
from navlab.stack.world import stack_episode

ROOM_CLEARANCE_M = 0.02  # hj.pruners' default raster: what HJ-search's rooms use


def drive_variant(follower: HJFollower, episode, route, params, reference: bool):
    """One drive with the follower as tuned, or as the HJ code runs per call (``reference``)."""
    kept_table, kept_resolution = follower.table, follower.clearance_resolution_m
    if reference:
        follower.table, follower.clearance_resolution_m = None, ROOM_CLEARANCE_M
    try:
        xy = episode.prior.frame.cell_to_world(route)
        return drive(episode, xy, allowed_ground(episode, route), follower, params)
    finally:
        follower.table, follower.clearance_resolution_m = kept_table, kept_resolution


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--episodes", type=int, default=4)
    parser.add_argument("--data-dir", default="data")
    parser.add_argument("--artifacts-dir", default="artifacts")
    parser.add_argument("--out", default=None, help="write the results here as JSON")
    run = parser.parse_args()
    torch.set_num_threads(1)
    params = load_params(run.profile)
    bank = load_terrain_bank(run.data_dir, params.pacer.data)
    tiles = load_maps(run.data_dir, "test")
    follower = HJFollower(params, run.artifacts_dir)
    period_ms = 1e3 / params.stack.replan_hz
    seconds: dict[str, list[np.ndarray]] = {"tuned": [], "reference": []}
    outcomes: dict[str, list[str]] = {"tuned": [], "reference": []}
    for index in range(run.episodes):
        episode = stack_episode(index, tiles, params, bank)
        route = expert_route(episode, params).trajectory
        for variant in ("tuned", "reference"):
            driven = drive_variant(follower, episode, route, params, variant == "reference")
            seconds[variant].append(driven.plan_seconds)
            outcomes[variant].append(driven.outcome)
        print(f"{episode.name}: {outcomes['tuned'][-1]} / {outcomes['reference'][-1]}", flush=True)
    results = {"period_ms": period_ms}
    for variant, runs in seconds.items():
        ms = np.concatenate(runs) * 1e3
        p50, p95 = np.percentile(ms, [50, 95])
        results[variant] = {"replans": len(ms), "p50_ms": float(p50), "p95_ms": float(p95),
                            "max_ms": float(ms.max()), "p95_share_of_period": float(p95 / period_ms),
                            "outcomes": outcomes[variant]}
        print(f"{variant}: {len(ms)} re-plans, p50 {p50:.1f} ms, p95 {p95:.1f} ms ({p95 / period_ms:.2f} of the "
              f"{period_ms:.1f} ms period), max {ms.max():.1f} ms", flush=True)
    results["p95_ratio_tuned_over_reference"] = results["tuned"]["p95_ms"] / results["reference"]["p95_ms"]
    print(f"p95 tuned / reference: {results['p95_ratio_tuned_over_reference']:.2f}")
    if run.out:
        with open(run.out, "w", encoding="utf8") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
