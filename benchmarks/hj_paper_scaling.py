"""The HJ solver toward the paper-size grids on this CPU: time per step and peak memory at growing fractions
of the `paper` profile's TTR (481 x 481 x 21 x 72) and static BRT (385 x 217 x 41 x 90), the growth
exponents, and the full size extrapolated beside the paper's 27.7 and 26 min on 16 cores (HJ-search,
Sec. VIII-A).

Why per step: a full solve is (steps) x (time per step), and the step count is not a measurement: the
solver's CFL step is cfl / max_rate(grid), fixed by the grid's spacing and the car's bounds
(``reach.solver``), so the number of steps to the profile's horizon is computed exactly for the full grid
(an upper bound: the static BRT stops at convergence, the TTR when nothing new is reached for ``stall_s``;
the H100 runs in ``hj_cuda_timing.py`` stopped at 1120 BRT steps, 10 s horizon). What is measured is the
time per step (WENO5 + TVD-RK3 + local Lax-Friedrichs, float32, the Hamiltonian compiled as `hj_grids`
runs it) and the peak resident memory, each fraction in its own process (its own peak), x and y scaled
by ``s`` (the value and heading axes kept: the paper's resolution in v and θ), the car, room and
settings those of the `paper` profile. Fits: time per step ∝ cells^b, peak memory = a + c · cells.

    PYTHONPATH=lib python benchmarks/hj_paper_scaling.py                 # fractions 1/8 .. 1/3, one thread
    PYTHONPATH=lib python benchmarks/hj_paper_scaling.py --threads 2 --scales 0.125 0.25

Results (measured on this 2-core machine) are in benchmarks/README.md, "HJ solver toward the paper-size grids".
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import resource
import subprocess
import sys
import time

import numpy as np

PAPER_MINUTES = {"ttr": 27.7, "static_brt": 26.0}  # Sec. VIII-A, on a 16-core CPU


def _spec(kind: str, scale: float):
    """The `paper` profile's grid spec of ``kind``, x and y scaled by ``scale`` (at least 9 nodes each)."""
    from navlab.core.params import load_params
    from navlab.hj import grids as hj_grids

    params = load_params("paper")
    g = params.hj.grids
    section = g.ttr if kind == "ttr" else g.static_brt
    shape = tuple(max(9, round(n * scale)) if axis < 2 else n for axis, n in enumerate(section.shape))
    section = dataclasses.replace(section, shape=shape)
    grids = dataclasses.replace(g, **{kind: section}, device="cpu")
    params = dataclasses.replace(params, hj=dataclasses.replace(params.hj, grids=grids))
    spec = hj_grids.ttr_spec(params) if kind == "ttr" else hj_grids.static_brt_spec(params, "simulation")
    return params, spec, section.horizon_s


def steps_to_horizon(kind: str, scale: float) -> int:
    """Steps of the CFL-limited solve to the profile's horizon on the scaled grid (``reach.solver``'s dt)."""
    import torch

    from navlab.hj import grids as hj_grids
    from navlab.reach.solver import dissipation_coefficients, max_rate

    params, spec, horizon = _spec(kind, scale)
    grid, settings = spec.grid, hj_grids._settings(params)
    state = [grid.mesh(d, "cpu", torch.float32) for d in range(grid.ndim)]  # broadcast axes: no full mesh
    rate = max_rate(dissipation_coefficients(hj_grids._car(params), grid, state, settings.dissipation), grid)
    return math.ceil(horizon * rate / settings.cfl)


def worker(kind: str, scale: float, steps: int, threads: int, compile: bool = True) -> dict:
    """Time ``steps`` solver steps (after a compiling warm-up) on the scaled grid; peak RSS of this process."""
    import torch

    from navlab.hj import grids as hj_grids
    from navlab.reach.solver import Backend, dissipation_coefficients, max_rate, solve

    torch.set_num_threads(threads)
    params, spec, _ = _spec(kind, scale)
    grid, car, settings = spec.grid, hj_grids._car(params), hj_grids._settings(params)
    x, y = np.meshgrid(grid.axis(0), grid.axis(1), indexing="ij")
    if kind == "ttr":  # the goal disc at the origin, as general_ttr starts
        surface = np.hypot(x, y) - params.hj.grids.ttr.goal_radius_m
    else:  # the room's walls and obstacles less the robot's radius, as static_brt starts
        surface = hj_grids.room_obstacle_distance(hj_grids.load_room("simulation"), grid) \
            - params.hj.grids.robot.radius_m
    initial = torch.as_tensor(surface, dtype=torch.float32)[:, :, None, None].expand(grid.shape).contiguous()
    state = [grid.mesh(d, "cpu", torch.float32) for d in range(grid.ndim)]
    dt = settings.cfl / max_rate(dissipation_coefficients(car, grid, state, settings.dissipation), grid)
    backend = Backend(device="cpu", progress=False, compile=compile)
    solve(car, grid, initial, 2 * dt, settings, backend=backend)  # compiles the Hamiltonian for this shape
    start = time.perf_counter()
    solution = solve(car, grid, initial, steps * dt * (1 - 1e-6), settings, backend=backend)
    seconds = time.perf_counter() - start
    return {"kind": kind, "scale": scale, "shape": list(grid.shape), "cells": math.prod(grid.shape),
            "steps": solution.steps, "s_per_step": seconds / solution.steps,
            "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def measure(kind: str, scales: list[float], steps: int, threads: int, compile: bool = True) -> list[dict]:
    rows = []
    for scale in scales:
        out = subprocess.run([sys.executable, __file__, "--worker", kind, str(scale), "--steps", str(steps),
                              "--threads", str(threads), *([] if compile else ["--eager"])],
                             capture_output=True, text=True, check=True)
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
        r = rows[-1]
        print(f"  {kind} {'x'.join(map(str, r['shape']))}: {r['cells'] / 1e6:.1f} M cells, "
              f"{1000 * r['s_per_step']:.0f} ms/step, peak {r['peak_mib']:.0f} MiB", flush=True)
    return rows


def extrapolate(kind: str, rows: list[dict], threads: int) -> str:
    """The full size from the largest fraction's cost per cell and step: once the arrays outgrow the caches
    (between ~7 and ~12 M cells here) a step streams them from memory and its time grows linearly with the
    cells, so the exponent fitted over every fraction (printed) mixes two regimes and overshoots."""
    cells = np.array([r["cells"] for r in rows], dtype=float)
    per_step = np.array([r["s_per_step"] for r in rows])
    peak = np.array([r["peak_mib"] for r in rows])
    b = np.polyfit(np.log(cells), np.log(per_step), 1)[0]
    ns = 1e9 * per_step[-1] / cells[-1]
    c, m0 = np.polyfit(cells, peak, 1)
    full = math.prod(_spec(kind, 1.0)[1].grid.shape)
    steps = steps_to_horizon(kind, 1.0)
    minutes = ns * 1e-9 * full * steps / 60
    paper_ns = PAPER_MINUTES[kind] * 60 * 16 / (full * steps) * 1e9
    gib = (m0 + c * full) / 1024
    return (f"{kind}: fitted time per step ∝ cells^{b:.2f} over every fraction; {ns:.0f} ns per cell and step at "
            f"the largest ({threads} thread(s)); full size {full / 1e6:.0f} M cells, at most {steps} steps to the "
            f"horizon: ~{minutes / 60:.1f} h here ({minutes * threads / 16:.0f} min if it scaled perfectly to 16 "
            f"cores; paper {PAPER_MINUTES[kind]} min on 16 cores, i.e. <= {paper_ns:.0f} ns per cell, step and "
            f"core), peak ~{gib:.0f} GiB ({c * 2**20 / 4:.0f} float32 per cell)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scales", type=float, nargs="+", default=[0.125, 0.167, 0.25, 0.333])
    parser.add_argument("--steps", type=int, default=6, help="timed steps per fraction (after the warm-up)")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--kinds", nargs="+", default=["ttr", "static_brt"], choices=["ttr", "static_brt"])
    parser.add_argument("--eager", action="store_true", help="do not compile the Hamiltonian (a quick check only)")
    parser.add_argument("--worker", nargs=2, metavar=("KIND", "SCALE"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        print(json.dumps(worker(args.worker[0], float(args.worker[1]), args.steps, args.threads, not args.eager)))
        return
    for kind in args.kinds:
        rows = measure(kind, args.scales, args.steps, args.threads, not args.eager)
        print(extrapolate(kind, rows, args.threads), flush=True)


if __name__ == "__main__":
    main()
