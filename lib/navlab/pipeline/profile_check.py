"""``python -m navlab params check``: does each profile of params.yaml *fit*, before hours are spent on it?

Loading params.yaml already checks every key's type and range; this checks how keys of different
sections fit together, by dry-running the shapes of each stage on the CPU in seconds, without data/
and without training (issue 23 item 4, issue 24 item 6). It exists because the ``gpu`` profile once
trained for ~2 h and then stopped at the tables: its aerial maps (512 px) did not fit in the 500-px
SuReNav test maps they are cut from. Each rule here comes from the code that would fail at run time,
called on stand-in inputs where that is cheap (models on the ``meta`` device: shapes, no memory).

Each ``*_problems`` function covers one stage family and returns one line per problem, naming the
params key; it may append what it measured to ``notes`` (parameter counts, sizes, memory).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from navlab.core.params import Params

GIB = 2**30
# Memory budgets, by the machine a profile targets. smoke and default run on the shared 2-core CPU machine
# (23 GiB RAM): 16 GiB leaves room for the OS, a notebook kernel and a second job. gpu and paper target one
# single-GPU machine (an 80 GB H100 shows ~78 GiB to torch; 128 GiB RAM, of which 3/4 for one stage).
CPU_MACHINE_RAM_GIB = 16.0
GPU_MACHINE_RAM_GIB = 96.0
GPU_MEMORY_GIB = 78.0
# Peak working set of one HJ solve, in grid-sized float32 arrays (values, RK stages, per-axis left/right
# derivatives, dissipation, tube target, band reference): peak RSS of a static BRT and a TTR solve on the
# 97x55x11x36 grid divided by the grid's bytes (measured 14.6 / 25.0 / 26.6-28.6), rounded up.
HJ_WORKING_ARRAYS = {"upwind1": 16, "eno2": 26, "weno5": 30}
HJ_BYTES = 4  # float32: solver dtype and stored grids
ADAM_BYTES_PER_PARAM = 16  # fp32 weight, gradient and Adam's two moments


def budget_gib(params: Params, device: str) -> float:
    """Memory one stage may use on ``device`` ("cpu" or "cuda") under this profile (see the constants)."""
    if device == "cuda":
        return GPU_MEMORY_GIB
    return GPU_MACHINE_RAM_GIB if params.profile in ("gpu", "paper") else CPU_MACHINE_RAM_GIB


def surenav_test_map_px(params: Params) -> int:
    """Pixels per side of a SuReNav test map: real-city tiles cut as navlab.maps.tiles.cut_tiles does."""
    m = params.data.maps
    return round(m.tile_size_m / m.resolution_m)


def pacer_render_problems(params: Params, notes: list[str]) -> list[str]:
    """Aerial maps against the test maps they are cut from, BEV windows and patches against their images."""
    from navlab.core.grid import RasterFrame
    from navlab.maps.semantic_map import SemanticMap
    from navlab.pacer.aerial import semantic_map_regions

    d, problems = params.pacer.data, []
    side, size = surenav_test_map_px(params), d.aerial.size
    notes.append(f"pacer aerial {size} px ({d.aerial.layout}), test maps {side} px, BEV {d.image_size} px, "
                 f"patches {d.patch_size} / baselines {params.pacer.baselines.patch_size} px")
    if d.aerial.layout == "surenav":  # the very rule aerial maps are cut by, on a blank map of the test maps' size
        blank = SemanticMap("test map", np.zeros((side, side), np.uint8), RasterFrame((side, side), 1.0))
        try:
            semantic_map_regions([blank], size, np.random.default_rng(0))
        except ValueError:
            problems.append(f"pacer.data.aerial.size = {size} exceeds the {side}-px SuReNav test maps "
                            f"(data.maps.tile_size_m / resolution_m = {params.data.maps.tile_size_m:g} / "
                            f"{params.data.maps.resolution_m:g}); the navigation tables would stop with a "
                            f"ValueError after training; use <= {side}")
    if d.image_size >= size:  # costmap_over_map reflect-pads the map by one BEV window: needs window < map
        problems.append(f"pacer.data.image_size = {d.image_size} must be smaller than pacer.data.aerial.size = "
                        f"{size} (the aerial costmap reflect-pads the map by one BEV window)")
    if params.pacer.baselines.patch_size > d.image_size:  # baselines.patches.sample_patches refuses it
        problems.append(f"pacer.baselines.patch_size = {params.pacer.baselines.patch_size} exceeds the BEV image "
                        f"pacer.data.image_size = {d.image_size}")
    return problems


def pacer_model_problems(params: Params, notes: list[str]) -> list[str]:
    """Build the PACER network on ``meta`` and run one BEV image + context through it (shapes only),
    then compare its training memory (weights, Adam, saved activations of a batch) with the budget."""
    import torch

    from navlab.pacer.model import PacerNet, count_parameters

    d, t = params.pacer.data, params.pacer.train
    with torch.device("meta"):
        model = PacerNet(params.pacer.model, context_pairs=d.n_pairs)
        image = torch.empty(1, 3, d.image_size, d.image_size)
        context = torch.empty(1, 3 * d.n_pairs, 2 * d.patch_size, d.patch_size)
    model.eval()  # batch norm on a batch of one: shapes as in training, without its batch-of-one refusal
    activations = _activation_count(model, lambda: model(image, context))
    if isinstance(activations, str):
        return [f"pacer.model with pacer.data.image_size = {d.image_size}, patch_size = {d.patch_size}: {activations}"]
    n = count_parameters(model)
    need = (n * ADAM_BYTES_PER_PARAM + t.batch_size * activations * 4) / GIB
    budget = budget_gib(params, t.device)
    notes.append(f"pacer model {n / 1e6:.2f} M parameters; training at batch {t.batch_size} needs ~{need:.1f} GiB "
                 f"of {budget:g} GiB ({t.device})")
    if need > budget:
        return [(f"pacer.train.batch_size = {t.batch_size}: training needs ~{need:.1f} GiB on {t.device} "
                 f"(model {n / 1e6:.1f} M parameters at pacer.data.image_size = {d.image_size}), "
                 f"over the {budget:g} GiB budget")]
    return []


def _activation_count(model, forward: Callable[[], object]) -> int | str:
    """Elements of every leaf module's output in one forward (what backward keeps), or the error's text."""
    import torch

    total = [0]

    def hook(_module, _inputs, output):
        total[0] += sum(o.numel() for o in (output if isinstance(output, tuple) else (output,))
                        if isinstance(o, torch.Tensor))

    handles = [m.register_forward_hook(hook) for m in model.modules() if not list(m.children())]
    try:
        forward()
    except (RuntimeError, ValueError) as err:
        return str(err).splitlines()[0]
    finally:
        for h in handles:
            h.remove()
    return total[0]


def pacer_batch_problems(params: Params, notes: list[str]) -> list[str]:
    """A batch larger than the examples it is drawn from never happens: the stated size is a typo."""
    p, problems = params.pacer, []
    pairs = [("pacer.train.batch_size", p.train.batch_size,
              "pacer.train.examples_per_epoch", p.train.examples_per_epoch),
             ("pacer.train.val_examples", p.train.val_examples, "pacer.data.sizes.val", p.data.sizes.val),
             ("pacer.baselines.sterling.batch_size", p.baselines.sterling.batch_size,
              "pacer.baselines.sterling.patches_per_epoch", p.baselines.sterling.patches_per_epoch),
             ("pacer.baselines.classifier.batch_size", p.baselines.classifier.batch_size,
              "pacer.baselines.classifier.patches_per_epoch", p.baselines.classifier.patches_per_epoch)]
    for key, value, of_key, of in pairs:
        if value > of:
            problems.append(f"{key} = {value} exceeds {of_key} = {of}")
    return problems


def surenav_model_problems(params: Params, notes: list[str]) -> list[str]:
    """Build the SuReNav estimator (GPS and the MPNN-only ablation) on ``meta``: its own checks, its size."""
    import torch

    from navlab.surenav.model.estimator import RelaxationCostEstimator

    counts = []
    for attention in (True, False):
        try:
            with torch.device("meta"):
                model = RelaxationCostEstimator(params.surenav.model, attention=attention)
        except ValueError as err:
            return [str(err).splitlines()[0]]
        counts.append(sum(p.numel() for p in model.parameters()))
    notes.append(f"surenav estimator {counts[0]:,} parameters (MPNN-only ablation {counts[1]:,}), "
                 f"batch {params.surenav.train.batch_size} on {params.surenav.train.device}")
    return []


def hj_problems(params: Params, notes: list[str]) -> list[str]:
    """HJ grids: each solve's working set on hj.grids.device, all stored grids held at once by the planner,
    and the finer BRT solve that measures the stored grid's margin (always on the CPU), against the budgets."""
    from navlab.core.params import ParamsError
    from navlab.reach.brt_margin import refined_grid
    from navlab.reach.precompute import specs

    g = params.hj.grids
    try:
        grids = specs(params)  # grid specs only: no solve
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
                        f"{list(fine.shape)} needs ~{fine_gib:.1f} GiB on the CPU (reach.brt_margin solves there), "
                        f"over the {budget_gib(params, 'cpu'):g} GiB budget")
    return problems


CHECKS = (pacer_render_problems, pacer_model_problems, pacer_batch_problems, surenav_model_problems, hj_problems)


def check_profile(params: Params) -> tuple[list[str], list[str]]:
    """(problems, notes) of one loaded profile, every stage family checked."""
    problems: list[str] = []
    notes: list[str] = []
    for check in CHECKS:
        problems += check(params, notes)
    return problems, notes
