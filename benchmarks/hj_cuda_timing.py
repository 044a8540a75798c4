"""Timings of navlab.reach on CUDA: paper-size TTR and static BRT grids, and CPU vs CUDA on one grid.

The paper (HJ-search, Sec. VIII-A) precomputed a ≈1.4 GB TTR and a ≈1.2 GB static-map BRT in 27.7 and
26 minutes on a 16-core CPU. Read as float32 arrays, those are ≈350 M and ≈300 M grid points; the
paper gives no axes, so we take these counts (the TTR's goal-centred frame spans every goal offset
in the room; 5 cm in x, y for the TTR, 2.5 cm for the BRT):

  TTR  (x, y, v, θ) = 385 × 217 × 21 × 200 over [−9.6, 9.6] × [−5.4, 5.4] × [0, v_max] × [−π, π)
       351 M points, 1.40 GB float32
  BRT  (x, y, v, θ) = 385 × 217 × 20 × 180 over the 9.6 m × 5.4 m room, 301 M points, 1.20 GB float32

Both with WENO5 + TVD-RK3 + local Lax-Friedrichs, CFL 0.75. The room is a stand-in with exact signed
distance (walls plus three boxes); the real rooms come from navlab.maps.rooms.

    python benchmarks/hj_cuda_timing.py --device cuda             # everything below
    python benchmarks/hj_cuda_timing.py --only ratio --device cuda

Measured 2026-11-23 on one H100 80GB (torch 2.11, compiled Hamiltonian, compile time included):
BRT 79.5 s (≈20 s compiling, converged at τ = 8.06 s, 1120 steps), TTR 110 s (≈15 s compiling,
τ = 14 s, 99.5 % of states reached); peak 10.4 float32 per grid point. CPU (16 threads) vs CUDA on the
81×41×11×36 BRT, τ = 3 s: 23-30 s vs 1.8-2.0 s eager (13-15×) and 0.05 s compiled (≈500×).
"""

from __future__ import annotations

import argparse
import math
import time

import torch

from navlab.hj.reachability import general_ttr, static_brt
from navlab.reach.dynamics import DubinsCar4D
from navlab.reach.grid import Grid
from navlab.reach.settings import SolverSettings
from navlab.reach.solver import Backend, solve

CAR = DubinsCar4D(v_max=1.0, a_min=-1.0, a_max=1.0, omega_max=1.0)
ROOM = (9.6, 5.4)
BOXES = (((2.0, 1.5), (3.0, 3.5)), ((5.0, 0.0), (5.6, 2.2)), ((6.8, 3.2), (8.0, 4.2)))
ROBOT_RADIUS = 0.3
SETTINGS = SolverSettings(scheme="weno5", rk_order=3, cfl=0.75)


def room_signed_distance(x: torch.Tensor, y: torch.Tensor) -> torch.Tensor:
    sdf = torch.minimum(torch.minimum(x, ROOM[0] - x), torch.minimum(y, ROOM[1] - y))
    for (x0, y0), (x1, y1) in BOXES:
        qx = (x - (x0 + x1) / 2).abs() - (x1 - x0) / 2
        qy = (y - (y0 + y1) / 2).abs() - (y1 - y0) / 2
        box = torch.sqrt(qx.clamp(min=0) ** 2 + qy.clamp(min=0) ** 2) + torch.clamp(
            torch.maximum(qx, qy), max=0
        )
        sdf = torch.minimum(sdf, box)
    return sdf


def room_grid(shape) -> Grid:
    return Grid(
        (0.0, 0.0, 0.0, -math.pi), (ROOM[0], ROOM[1], CAR.v_max, math.pi), shape, (False, False, False, True)
    )


def _sync(device):
    if torch.device(device).type == "cuda":
        torch.cuda.synchronize()


def _memory_report(device, points: int) -> str:
    if torch.device(device).type != "cuda":
        return ""
    peak = torch.cuda.max_memory_allocated()
    return f"peak {peak / 2**30:.1f} GiB = {peak / (4 * points):.1f} float32 per grid point"


def time_brt(shape, device, compile: bool, max_horizon: float):
    grid = room_grid(shape)
    sdf = room_signed_distance(grid.mesh(0, device)[:, :, 0, 0], grid.mesh(1, device)[:, :, 0, 0])
    if torch.device(device).type == "cuda":
        torch.cuda.reset_peak_memory_stats()
    _sync(device)
    start = time.perf_counter()
    solution = static_brt(
        sdf,
        CAR,
        grid,
        robot_radius=ROBOT_RADIUS,
        max_horizon=max_horizon,
        band=0.3,
        tolerance=0.01,
        window=0.5,
        settings=SETTINGS,
        backend=Backend(device=device, compile=compile),
    )
    _sync(device)
    seconds = time.perf_counter() - start
    points = math.prod(shape)
    print(
        f"BRT {shape} ({points / 1e6:.0f} M points, {4 * points / 1e9:.2f} GB float32) on {device}"
        f"{' compiled' if compile else ''}: {seconds:.1f} s, τ = {solution.time:.2f} s, {solution.steps} steps, "
        f"converged={solution.converged}; {_memory_report(device, points)}",
        flush=True,
    )
    return solution, seconds


def time_ttr(shape, device, compile: bool, horizon: float):
    half = 9.6
    grid = Grid(
        (-half, -half, 0.0, -math.pi), (half, half, CAR.v_max, math.pi), shape, (False, False, False, True)
    )
    if torch.device(device).type == "cuda":
        torch.cuda.reset_peak_memory_stats()
    _sync(device)
    start = time.perf_counter()
    ttr = general_ttr(
        CAR, grid, 0.3, horizon, SETTINGS, stall_time=0.5, backend=Backend(device=device, compile=compile)
    )
    _sync(device)
    seconds = time.perf_counter() - start
    points = math.prod(shape)
    reached = float((ttr < horizon).float().mean())
    print(
        f"TTR {shape} ({points / 1e6:.0f} M points, {4 * points / 1e9:.2f} GB float32) on {device}"
        f"{' compiled' if compile else ''}: {seconds:.1f} s, max TTR {float(ttr.max()):.2f} s, "
        f"{100 * reached:.1f}% reached before the {horizon} s horizon; {_memory_report(device, points)}",
        flush=True,
    )
    return ttr, seconds


def cpu_vs_cuda(shape, horizon: float, compile: bool):
    """Same problem, fixed horizon: CPU eager against CUDA eager and (optionally) compiled; values must agree."""
    grid = room_grid(shape)
    sdf = room_signed_distance(grid.mesh(0)[:, :, 0, 0], grid.mesh(1)[:, :, 0, 0])
    failure = (sdf - ROBOT_RADIUS)[:, :, None, None].expand(shape).contiguous()
    runs = [("cpu", False), ("cuda", False)] + ([("cuda", True)] if compile else [])
    results = {}
    for device, compiled in runs:
        # warm-up (and compilation) on a short horizon, then the timed run
        backend = Backend(device=device, progress=False, compile=compiled)
        solve(CAR, grid, failure, 0.05, SETTINGS, backend=backend)
        _sync(device)
        start = time.perf_counter()
        solution = solve(CAR, grid, failure, horizon, SETTINGS, backend=backend)
        _sync(device)
        results[device, compiled] = (time.perf_counter() - start, solution.values.cpu(), solution.steps)
    cpu_s, cpu_v, steps = results["cpu", False]
    print(
        f"BRT {shape}, WENO5 + RK3, τ = {horizon} s ({steps} steps): CPU ({torch.get_num_threads()} threads) {cpu_s:.2f} s"
    )
    for (device, compiled), (seconds, values, _) in results.items():
        if device == "cuda":
            print(
                f"  CUDA{' compiled' if compiled else ' eager'}: {seconds:.2f} s, CPU/CUDA ratio {cpu_s / seconds:.1f}x, "
                f"max |ΔV| vs CPU {float((cpu_v - values).abs().max()):.1e}",
                flush=True,
            )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="cuda")
    parser.add_argument("--only", choices=["ratio", "brt", "ttr"], action="append")
    parser.add_argument("--eager", action="store_true", help="do not torch.compile the numerical Hamiltonian")
    parser.add_argument("--brt-shape", type=int, nargs=4, default=(385, 217, 20, 180))
    parser.add_argument("--ttr-shape", type=int, nargs=4, default=(385, 217, 21, 200))
    parser.add_argument("--ratio-shape", type=int, nargs=4, default=(81, 41, 11, 36))
    parser.add_argument("--brt-max-horizon", type=float, default=10.0)
    parser.add_argument("--ttr-horizon", type=float, default=14.0)
    args = parser.parse_args()
    only = set(args.only or ["ratio", "brt", "ttr"])
    compile = not args.eager
    if torch.cuda.is_available():
        print(f"GPU: {torch.cuda.get_device_name()}, torch {torch.__version__}", flush=True)
    if "ratio" in only:
        cpu_vs_cuda(tuple(args.ratio_shape), 3.0, compile=compile)
    if "brt" in only:
        time_brt(tuple(args.brt_shape), args.device, compile, args.brt_max_horizon)
    if "ttr" in only:
        time_ttr(tuple(args.ttr_shape), args.device, compile, args.ttr_horizon)


if __name__ == "__main__":
    main()
