"""`params check` for HJ-search: each value-function solve's working set, the stored grids the planner
holds at once and the BRT margin's refined solve, against the machine's memory budgets.

Each ``*_problems(params, notes)`` returns one line per problem, naming the params key, and may append what it
measured to ``notes``; the manifest (``track.py``) lists them, ``navlab.pipeline.profile_check`` runs them on
every profile.
"""

from __future__ import annotations

import math

from navlab.core.budgets import GIB, budget_gib
from navlab.core.params import Params

# Peak working set of one HJ solve, in grid-sized float32 arrays (values, RK stages, per-axis left/right
# derivatives, dissipation, tube target, band reference): peak RSS of a static BRT and a TTR solve on the
# 97x55x11x36 grid divided by the grid's bytes (measured 14.6 / 25.0 / 26.6-28.6), rounded up.
HJ_WORKING_ARRAYS = {"upwind1": 16, "eno2": 26, "weno5": 30}
HJ_BYTES = 4  # float32: solver dtype and stored grids


def grid_problems(params: Params, notes: list[str]) -> list[str]:
    """HJ grids: each solve's working set on hj.grids.device, all stored grids held at once by the planner,
    and the finer BRT solve that measures the stored grid's margin (always on the CPU), against the budgets."""
    from navlab.core.params import ParamsError
    from navlab.hj.brt_margin import refined_grid
    from navlab.hj.grids import forward_only, specs

    g = params.hj.grids
    try:
        grids = specs(params)  # grid specs only: no solve
        if g.robot.v_min < 0:
            specs(forward_only(params))  # the forward-only car's variant grids keep the speed spacing
    except (ParamsError, ValueError) as err:
        return [str(err).splitlines()[0]]
    arrays = HJ_WORKING_ARRAYS[g.solver.scheme]
    solve = max(grids, key=lambda s: math.prod(s.grid.shape))
    solve_gib = math.prod(solve.grid.shape) * HJ_BYTES * arrays / GIB
    stored_gib = sum(math.prod(s.grid.shape) for s in grids) * HJ_BYTES / GIB
    refine = params.hj.planner.brt_margin_refine
    fine = refined_grid(next(s.grid for s in grids if s.name.startswith("static_brt")), refine)
    fine_gib = math.prod(fine.shape) * HJ_BYTES * arrays / GIB
    notes.append(f"hj {len(grids)} grids, {stored_gib:.2f} GiB stored; largest solve {solve.name} "
                 f"{list(solve.grid.shape)} ~{solve_gib:.1f} GiB on {g.device}; margin solve {list(fine.shape)} "
                 f"~{fine_gib:.1f} GiB on cpu ({arrays} working arrays, {g.solver.scheme})")
    problems = []
    key = "hj.grids.ttr.shape" if solve.name == "ttr" else (
        "hj.grids.human_brt.shape" if solve.name == "human_brt" else "hj.grids.static_brt.shape")
    if solve_gib > budget_gib(params, g.device):
        problems.append(f"{key} = {list(solve.grid.shape)}: one {g.solver.scheme} solve needs ~{solve_gib:.1f} GiB "
                        f"on {g.device} ({arrays} grid-sized float32 arrays), over the "
                        f"{budget_gib(params, g.device):g} GiB budget")
    if stored_gib > budget_gib(params, "cpu"):
        problems.append(f"hj.grids shapes: the {len(grids)} stored grids hold {stored_gib:.1f} GiB together, over the "
                        f"{budget_gib(params, 'cpu'):g} GiB RAM budget")
    if fine_gib > budget_gib(params, "cpu"):
        problems.append(f"hj.planner.brt_margin_refine = {list(refine)}: the margin's refined static BRT "
                        f"{list(fine.shape)} needs ~{fine_gib:.1f} GiB on the CPU (hj.brt_margin solves there), "
                        f"over the {budget_gib(params, 'cpu'):g} GiB budget")
    return problems
