"""Side-by-side: navlab's torch level-set solver against hj_reachability (JAX) on the same problem.

Problem (issue 4): the 4D Dubins car (x, y, v, θ; Eq. 19, v ∈ [0, v_max] by state-dependent
acceleration bounds) avoiding the walls and obstacles of the 9.6 m × 5.4 m simulation room (signed
distance minus the robot radius), avoid BRT over 3 s, WENO5 + TVD-RK3 + Lax-Friedrichs, CFL 0.75,
float32, V = min(V, l) after every step (the tube), linear-extrapolation ghost cells — the same on both
sides. Dissipation: hj_reachability's default ``global_lax_friedrichs`` bounds the gradient globally but
evaluates α(x) at every state, which for this car (α independent of the gradient) is navlab's
``dissipation="local"``; with it both solvers agree to float32 round-off. Each solver runs in its own
subprocess (so peak memory is its own): once to pay JIT compilation / warm-up, then ``--repeats`` times,
and the medians of those are compared. ``--cpus N`` pins both workers to the same N cores (torch also
runs N threads; XLA sizes its pool from the affinity): on a shared machine torch's OpenMP threads wait on
each other when a core is taken, so an equal, pinned share is the fair comparison. Printed: time, peak
memory, agreement (IoU of the zero sublevel sets, max |ΔV| away from kinks) and the speed ratio (target
>= 3x, IoU > 0.99).

Measured 2026-11-23 on the shared 2-core CPU box, ``--cpus 1`` (warm medians; navlab's first run includes
the torch.compile of the Hamiltonian, hj_reachability's its jit):

    grid          navlab            hj_reachability   ratio   IoU     max|ΔV| smooth  peak MiB (ours/hj)
    41×41×11×36   3.37 s (21.5 s)   18.0 s (24.4 s)   5.3x    1.0000  1.2e-3          258 / 169   --compile
    81×41×11×36   7.09 s (36.3 s)   43.4 s (52.1 s)   6.1x    1.0000  6.8e-4          331 / 277   --compile
    41×41×11×36   13.2 s            17.2 s            1.3x    1.0000  1.3e-3           86 / 167   eager
    41×41×11×36   23.1 s            18.7 s            0.8x    1.0000  1.3e-3           96 / 168   eager, before
                                                                              the one-pass WENO5 (024b1c1)

A repeat of the first row gave 2.84 s vs 16.75 s (5.9x), first run 6.9 s: inductor's on-disk cache
(/tmp/torchinductor_$USER or $TORCHINDUCTOR_CACHE_DIR) already held the kernels, so a new process compiles in ~4 s.

hj_reachability is not a navlab dependency. Install it in its own environment and point --jax-python at
it (the JAX worker imports only numpy, jax and hj_reachability):

    python3.11 -m venv /work/hjbench && /work/hjbench/bin/pip install -r benchmarks/requirements-hj.txt
    PYTHONPATH=lib python benchmarks/hj_solver.py --jax-python /work/hjbench/bin/python --shapes 41x41x11x36 \
        --compile --cpus 1
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

V_MAX, A_MIN, A_MAX, OMEGA_MAX, ROBOT_RADIUS = 1.0, -0.5, 0.5, 1.0, 0.285
HORIZON, CFL = 3.0, 0.75
LO, HI = (0.0, 0.0, 0.0, -np.pi), (9.6, 5.4, V_MAX, np.pi)


def _failure_values(shape) -> np.ndarray:
    """l(x) on the grid nodes: clearance of the robot in the simulation room (navlab.maps.rooms)."""
    from navlab.maps.rooms import load_room
    from navlab.reach.grid import Grid

    grid = Grid(LO, HI, tuple(shape), (False, False, False, True))
    x, y = np.meshgrid(grid.axis(0), grid.axis(1), indexing="ij")
    sdf = load_room("simulation").signed_distance(x, y, ROBOT_RADIUS).astype(np.float32)
    return np.ascontiguousarray(np.broadcast_to(sdf[:, :, None, None], grid.shape))


def _peak_rss_bytes() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


# --------------------------------------------------------------------------- workers (subprocesses)

def torch_worker(failure: np.ndarray, device: str, compile: bool, repeats: int) -> tuple[np.ndarray, list[float], dict]:
    import torch

    torch.set_num_threads(len(os.sched_getaffinity(0)))

    from navlab.hj.reachability import avoid_tube
    from navlab.reach.dynamics import DubinsCar4D
    from navlab.reach.grid import Grid
    from navlab.reach.settings import SolverSettings
    from navlab.reach.solver import Backend

    grid = Grid(LO, HI, failure.shape, (False, False, False, True))
    car = DubinsCar4D(V_MAX, A_MIN, A_MAX, OMEGA_MAX, control_mode="max")
    settings = SolverSettings(scheme="weno5", rk_order=3, cfl=CFL, dissipation="local")  # = hj's default GLF
    backend = Backend(device=device, progress=False, compile=compile)
    times, base = [], _peak_rss_bytes()
    for _ in range(1 + repeats):
        if device.startswith("cuda"):
            torch.cuda.synchronize()
            torch.cuda.reset_peak_memory_stats()
        start = time.perf_counter()
        sol = avoid_tube(car, grid, failure, HORIZON, settings, backend=backend)
        values = sol.values.cpu().numpy()
        times.append(time.perf_counter() - start)
    peak = (torch.cuda.max_memory_allocated() if device.startswith("cuda") else _peak_rss_bytes() - base)
    return values, times, {"steps": sol.steps, "peak_bytes": peak,
                           "memory": "CUDA max allocated" if device.startswith("cuda") else "RSS growth"}


def jax_worker(failure: np.ndarray, device: str, compile: bool, repeats: int) -> tuple[np.ndarray, list[float], dict]:
    del compile  # hj_reachability always jit-compiles the whole solve
    os.environ.setdefault("XLA_PYTHON_CLIENT_PREALLOCATE", "false")
    import hj_reachability as hj
    import jax
    import jax.numpy as jnp

    class DubinsCar4D(hj.Dynamics):
        """The same car, with the speed kept in [0, v_max] by state-dependent acceleration bounds."""

        def __init__(self):
            super().__init__("max", "min", hj.sets.Box(jnp.array([A_MIN, -OMEGA_MAX]), jnp.array([A_MAX, OMEGA_MAX])),
                             hj.sets.Box(jnp.zeros(1), jnp.zeros(1)))

        def _accel_bounds(self, v):
            tol = 1e-6 * V_MAX
            return jnp.where(v <= tol, 0.0, A_MIN), jnp.where(v >= V_MAX - tol, 0.0, A_MAX)

        def __call__(self, state, control, disturbance, time):
            _, _, v, th = state
            return jnp.array([v * jnp.cos(th), v * jnp.sin(th), control[0], control[1]])

        def optimal_control_and_disturbance(self, state, time, grad_value):
            lo, hi = self._accel_bounds(state[2])
            a = jnp.where(grad_value[2] >= 0, hi, lo)
            omega = jnp.where(grad_value[3] >= 0, OMEGA_MAX, -OMEGA_MAX)
            return jnp.array([a, omega]), jnp.zeros(1)

        def partial_max_magnitudes(self, state, time, value, grad_value_box):
            _, _, v, th = state
            lo, hi = self._accel_bounds(v)
            return jnp.abs(jnp.array([v * jnp.cos(th), v * jnp.sin(th), jnp.maximum(-lo, hi), OMEGA_MAX]))

    bc = hj.boundary_conditions
    with jax.default_device(jax.devices(device)[0]):
        grid = hj.Grid.from_lattice_parameters_and_boundary_conditions(
            hj.sets.Box(jnp.array(LO), jnp.array(HI)), failure.shape,
            boundary_conditions=(bc.extrapolate, bc.extrapolate, bc.extrapolate, bc.periodic))
        target = jnp.asarray(failure)
        settings = hj.SolverSettings.with_accuracy(
            "very_high", CFL_number=CFL, value_postprocessor=lambda t, v: jnp.minimum(v, target))
        dynamics, times = DubinsCar4D(), []
        base = _peak_rss_bytes()
        for _ in range(1 + repeats):
            start = time.perf_counter()
            out = hj.solve(settings, dynamics, grid, jnp.array([0.0, -HORIZON]), target, progress_bar=False)
            values = np.asarray(out[-1].block_until_ready())
            times.append(time.perf_counter() - start)
    stats = jax.devices(device)[0].memory_stats() or {}
    peak = stats.get("peak_bytes_in_use", _peak_rss_bytes() - base)
    return values, times, {"peak_bytes": peak,
                           "memory": "JAX peak bytes in use" if "peak_bytes_in_use" in stats else "RSS growth"}


def _worker_main(kind: str, inp: str, out: str, device: str, compile: str, repeats: str, cpus: str) -> None:
    if int(cpus) > 0:
        os.sched_setaffinity(0, sorted(os.sched_getaffinity(0))[: int(cpus)])
    failure = np.load(inp)
    worker = torch_worker if kind == "torch" else jax_worker
    values, times, info = worker(failure, device, compile == "1", int(repeats))
    np.save(out, values.astype(np.float32))
    Path(out).with_suffix(".json").write_text(json.dumps({"times": times, **info}))


# --------------------------------------------------------------------------- comparison

def kink_mask(values: np.ndarray) -> np.ndarray:
    """Nodes next to a kink of V in x or y (one-sided slopes differ by > 0.5, i.e. a slope that turns),
    or within two nodes of the x/y grid edges (where the ghost-cell extrapolation dominates)."""
    mask = np.zeros(values.shape, bool)
    for dim in (0, 1):
        d = np.diff(values, axis=dim)
        jump = np.abs(np.diff(d, axis=dim)) / (HI[dim] - LO[dim]) * (values.shape[dim] - 1) > 0.5
        inner = [slice(None)] * values.ndim
        inner[dim] = slice(1, -1)
        mask[tuple(inner)] |= jump
        for shift in (-1, 1):
            mask |= np.roll(mask, shift, axis=dim)
        edge = [slice(None)] * values.ndim
        for s in (slice(0, 2), slice(-2, None)):
            edge[dim] = s
            mask[tuple(edge)] = True
    return mask


def compare(ours: np.ndarray, ref: np.ndarray) -> dict:
    a, b = ours <= 0, ref <= 0
    smooth = ~(kink_mask(ours) | kink_mask(ref))
    diff = np.abs(ours - ref)
    return {"iou": float((a & b).sum() / max((a | b).sum(), 1)), "max_dv_smooth": float(diff[smooth].max()),
            "mean_dv": float(diff.mean()), "max_dv_all": float(diff.max()), "smooth_fraction": float(smooth.mean())}


def run_pair(shape, torch_device: str, jax_device: str, jax_python: str, workdir: Path, compile: bool,
             repeats: int, cpus: int) -> dict:
    failure = _failure_values(shape)
    inp = workdir / f"l_{'x'.join(map(str, shape))}.npy"
    np.save(inp, failure)
    results = {}
    for kind, python, device in (("torch", sys.executable, torch_device), ("jax", jax_python, jax_device)):
        out = workdir / f"{kind}_{inp.stem}.npy"
        env = {**os.environ, "PYTHONUNBUFFERED": "1"}
        subprocess.run([python, __file__, "--worker", kind, str(inp), str(out), device, str(int(compile)),
                        str(repeats), str(cpus)],
                       check=True, env=env)
        results[kind] = {"values": np.load(out), **json.loads(out.with_suffix(".json").read_text())}
    agreement = compare(results["torch"]["values"], results["jax"]["values"])
    return {"shape": list(shape), "torch": {k: v for k, v in results["torch"].items() if k != "values"},
            "jax": {k: v for k, v in results["jax"].items() if k != "values"}, **agreement,
            "speed_ratio": _warm(results["jax"]["times"]) / _warm(results["torch"]["times"])}


def _warm(times: list[float]) -> float:
    """Median of the runs after the first (which pays compilation)."""
    return float(np.median(times[1:]))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shapes", nargs="+", default=["41x41x11x36", "81x41x11x36"])
    parser.add_argument("--torch-device", default="cpu")
    parser.add_argument("--jax-device", default="cpu", help="cpu or gpu")
    parser.add_argument("--jax-python", default=sys.executable, help="python of the environment with hj_reachability")
    parser.add_argument("--compile", action="store_true", help="navlab: torch.compile the numerical Hamiltonian")
    parser.add_argument("--json", default=None, help="also write the results here")
    parser.add_argument("--keep", default=None, help="keep the inputs and both solutions (.npy) in this folder")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs after the warm-up (median reported)")
    parser.add_argument("--cpus", type=int, default=0, help="pin both workers to this many cores (0: all)")
    parser.add_argument("--worker", nargs=7, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.worker:
        _worker_main(*args.worker)
        return 0
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(args.keep or tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        for s in args.shapes:
            shape = tuple(int(n) for n in s.split("x"))
            r = run_pair(shape, args.torch_device, args.jax_device, args.jax_python, workdir, args.compile,
                         args.repeats, args.cpus)
            rows.append(r)
            t, j = r["torch"], r["jax"]
            print(f"grid {s}: navlab torch ({args.torch_device}) {_warm(t['times']):.2f} s "
                  f"(first run {t['times'][0]:.2f} s), peak {t['peak_bytes'] / 2**20:.0f} MiB [{t['memory']}] | "
                  f"hj_reachability ({args.jax_device}) {_warm(j['times']):.2f} s (first run incl. jit "
                  f"{j['times'][0]:.2f} s), peak {j['peak_bytes'] / 2**20:.0f} MiB [{j['memory']}]")
            print(f"    speed ratio (hj / navlab, warm medians): {r['speed_ratio']:.2f}x   IoU {r['iou']:.4f}   "
                  f"max|ΔV| away from kinks {r['max_dv_smooth']:.2e} (on {100 * r['smooth_fraction']:.0f}% of nodes), "
                  f"mean |ΔV| {r['mean_dv']:.2e}, max |ΔV| {r['max_dv_all']:.2e}", flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
