"""The static BRT pruner's margin, measured: the stored grid against a finer solve of the same problem.

Why: a grid BRT is only as accurate as its resolution and scheme; near the zero level set a coarse grid
calls some states safe (V > 0) that a finer grid finds unsafe. Eq. 12 prunes V <= m with m "a small
positive value to account for numerical approximation errors": we choose m as the largest coarse value
among the fine grid's unsafe nodes, so the pruner drops every state the finer solve calls unsafe.
The finer grid refines each axis by an integer factor (``refine``; (n − 1)·f + 1 nodes on bounded axes,
n·f on the periodic heading), uses the same scheme, horizon and convergence test, and its nodes are
compared with the stored grid's multilinear interpolant there (the value the pruner reads: the compiled
pruner is tested equal to this numpy look-up, ``hj.pruners.static_prune_reference``). The numpy
look-up keeps the cached margin independent of the search code: editing the planner does not re-solve.

The result is cached as JSON under ``artifacts/hj_margins`` (the ``hj_margins`` stage's output, built after
``hj_grids``, so the search stages only read it and never write into another stage's output), keyed on
the grid's inputs, the factors and the source of the modules that compute it.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from navlab.core.fingerprint import code_fingerprint
from navlab.core.io import sha256_json, write_json
from navlab.core.params import Params
from navlab.hj.grids import _car, _settings, load_static_brt, room_obstacle_distance
from navlab.maps.rooms import load_room
from navlab.reach.grid import Grid
from navlab.reach.solver import Backend

CODE = ("navlab.hj.brt_margin",)  # and every navlab module it imports (core.fingerprint)
MARGINS_SUBDIR = "hj_margins"


def refined_grid(grid: Grid, refine: tuple[int, ...]) -> Grid:
    if len(refine) != grid.ndim or any(int(f) < 1 for f in refine):
        raise ValueError(f"refine {refine}: one integer factor >= 1 per axis of the {grid.ndim}-D grid")
    shape = tuple(n * f if p else (n - 1) * f + 1 for n, f, p in zip(grid.shape, refine, grid.periodic, strict=True))
    return Grid(grid.lo, grid.hi, shape, grid.periodic)


def coarse_at_nodes(lookup, fine_grid: Grid, chunk: int = 1 << 20) -> np.ndarray:
    """The stored grid's interpolant at every node of ``fine_grid`` (C order), a chunk of nodes at a time."""
    axes = [fine_grid.axis(d) for d in range(fine_grid.ndim)]
    n = int(np.prod(fine_grid.shape))
    out = np.empty(n)
    for a in range(0, n, chunk):
        idx = np.unravel_index(np.arange(a, min(a + chunk, n)), fine_grid.shape)
        out[a:a + chunk] = lookup(np.stack([axes[d][i] for d, i in enumerate(idx)], axis=1))
    return out


def margin_from_values(coarse_at_fine: np.ndarray, fine: np.ndarray, band: float = 0.1) -> dict[str, Any]:
    """Margin statistics from the coarse interpolant and the fine values at the same (fine) nodes."""
    missed = (fine <= 0.0) & (coarse_at_fine > 0.0)
    near = np.abs(fine) < band
    err = coarse_at_fine - fine
    return {
        "margin": float(coarse_at_fine[missed].max()) if missed.any() else 0.0,
        "missed_unsafe_nodes": int(missed.sum()),
        "unsafe_nodes": int((fine <= 0.0).sum()),
        "nodes": int(fine.size),
        "near_zero_band_m": band,
        "max_overestimate_near_zero": float(err[near].max()) if near.any() else 0.0,
        "p99_overestimate_near_zero": float(np.quantile(err[near], 0.99)) if near.any() else 0.0,
    }


def measure_static_brt_margin(params: Params, artifacts_dir: str | Path, room_name: str, refine: tuple[int, ...],
                              *, device: str = "cpu", progress: bool = False, log=print) -> dict[str, Any]:
    """Solve the room's static BRT on the refined grid and measure the stored grid's optimism (cached)."""
    lookup = load_static_brt(params, artifacts_dir, room_name)
    key = {"grid_inputs": lookup.stored.meta["inputs_hash"], "refine": list(refine), "code": code_fingerprint(*CODE)}
    cache = Path(artifacts_dir) / MARGINS_SUBDIR / f"brt_margin_{room_name}.json"
    if cache.is_file():
        cached = json.loads(cache.read_text())
        if cached.get("key") == sha256_json(key):
            log(f"[brt_margin] {room_name}: cached ({cache})")
            return cached["result"]
    from navlab.hj.reachability import static_brt

    g = params.hj.grids
    fine_grid = refined_grid(lookup.grid, tuple(refine))
    room = load_room(room_name)
    b = g.static_brt
    backend = Backend(device=device, progress=progress, compile=g.compile)
    sol = static_brt(room_obstacle_distance(room, fine_grid), _car(params), fine_grid, robot_radius=g.robot.radius_m,
                     max_horizon=b.horizon_s, band=b.band_m, tolerance=b.tolerance_m, window=b.window_s,
                     settings=_settings(params), backend=backend)
    fine = sol.values.detach().cpu().numpy().astype(np.float64)
    coarse = coarse_at_nodes(lookup, fine_grid)
    result = margin_from_values(coarse, fine.reshape(-1))
    result.update(coarse_shape=list(lookup.grid.shape), fine_shape=list(fine_grid.shape),
                  scheme=f"{g.solver.scheme}/RK{g.solver.rk_order}", fine_converged=bool(sol.converged))
    write_json(cache, {"key": sha256_json(key), "result": result})
    log(f"[brt_margin] {room_name}: {lookup.grid.shape} vs {fine_grid.shape}: margin {result['margin']:.4f}")
    return result


def build_brt_margins(params: Params, data_dir: str | Path, artifacts_dir: str | Path, *,
                      progress: bool = True, log=print) -> list[Path]:
    """Artefact step ``hj_margins``: the static-BRT margin of every room with a stored BRT
    (``hj.grids.rooms``), at ``hj.planner.brt_margin_refine``, solved on ``hj.grids.device``."""
    del data_dir  # rooms are analytic geometry
    refine = tuple(params.hj.planner.brt_margin_refine)
    for room in params.hj.grids.rooms:
        measure_static_brt_margin(params, artifacts_dir, room, refine, device=params.hj.grids.device,
                                  progress=progress, log=log)
    return [Path(artifacts_dir) / MARGINS_SUBDIR / f"brt_margin_{room}.json" for room in params.hj.grids.rooms]
