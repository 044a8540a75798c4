"""``python -m navlab params check``: does each profile of params.yaml *fit*, before hours are spent on it?

Loading params.yaml already checks every key's type and range and the rules tying keys of different
sections together (navlab.core.params.constraints: aerial maps no larger than the test maps they are
cut from, batches no larger than what they are drawn from). This dry-runs the shapes of each stage on
the CPU in seconds, without data/ and without training (issue 23 item 4, issue 24 item 6): it exists
because the ``gpu`` profile once trained for ~2 h and then stopped at the tables (its 512-px aerial
maps did not fit in the 500-px SuReNav test maps). Each check calls the code that would fail at run
time on stand-in inputs (models on the ``meta`` device: shapes, no memory; the validations the stages
themselves run), and compares memory estimates with the budget of the machine the profile targets.
The one real input it reads: the photographs of your own that ``pacer.data`` lists (``terrain_photos/``,
in git), each checked as the bank will read it.

Each ``*_problems`` function covers one stage family and returns one line per problem, naming the
params key; it may append what it measured to ``notes`` (parameter counts, sizes, memory).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from navlab.core.params import Params
from navlab.core.params.constraints import surenav_test_map_px

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


def pacer_data_problems(params: Params, notes: list[str]) -> list[str]:
    """The checks load_terrain_bank runs on pacer.data before any stage renders (class lists, ordering,
    [min, max] ranges, terrains per image, no photograph in two classes by content) and on the photographs
    of your own it lists (there, readable, large enough for this profile), without data/; the render sizes
    as a note."""
    from navlab.core.io import DataError
    from navlab.core.params import ParamsError, repo_root
    from navlab.pacer import terrain

    d = params.pacer.data
    notes.append(f"pacer aerial {d.aerial.size} px ({d.aerial.layout}, zoom {d.layout.street_zoom}), "
                 f"test maps {surenav_test_map_px(params)} px, BEV {d.image_size} px, "
                 f"patches {d.patch_size} / baselines {params.pacer.baselines.patch_size} px")
    try:
        terrain.check_terrain_params(d)
        terrain.check_distinct_photos(repo_root() / "data", d)  # the packaged ones where data/ is built
    except ParamsError as err:
        return [str(err)]
    problems = []
    for key, source in terrain.listed_photos(d):
        if terrain.is_own_photo(source):  # a packaged photograph needs data/: `data check`'s part
            try:
                terrain.read_listed_photo("", key, source, d)
            except DataError as err:
                problems.append(str(err))
    return list(dict.fromkeys(problems))  # a photograph one class lists twice: one line (two classes: one each)


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


def pacer_baseline_problems(params: Params, notes: list[str]) -> list[str]:
    """STERLING's encoder and the semantic classifier on ``meta``, each on two patches of
    pacer.baselines.patch_size (their conv-pool stages need a patch of at least 2^stages pixels)."""
    import torch

    from navlab.pacer.baselines.semantic_classifier import SemanticClassifier
    from navlab.pacer.baselines.sterling import SterlingEncoder

    b, problems = params.pacer.baselines, []
    with torch.device("meta"):
        models = {"sterling": SterlingEncoder(b.sterling.channels, b.sterling.embed_dim, b.patch_size),
                  "classifier": SemanticClassifier(range(len(params.pacer.data.seen)), b.classifier.channels,
                                                   b.patch_size)}
        patches = torch.empty(2, 3, b.patch_size, b.patch_size)
    for name, model in models.items():
        try:
            model(patches)
        except (RuntimeError, ValueError) as err:
            problems.append(f"pacer.baselines.{name}.channels = {list(model.channels)} on pacer.baselines.patch_size "
                            f"= {b.patch_size}: {str(err).splitlines()[0]}")
    return problems


def surenav_model_problems(params: Params, notes: list[str]) -> list[str]:
    """The SuReNav estimator (GPS and the MPNN-only ablation) at the profile's size, on the input
    estimator_input builds from a three-node region graph: its own checks, Psi per node, its size.
    On the CPU, not ``meta``: the attention path calls torch.nonzero, which needs real values; three nodes
    take milliseconds."""
    import torch

    from navlab.surenav.model.estimator import RelaxationCostEstimator
    from navlab.surenav.model.inputs import estimator_input

    m, counts = params.surenav.model, []
    data = estimator_input(_three_node_graph(), walk_steps=m.walk_steps)
    for attention in (True, False):
        try:
            model = RelaxationCostEstimator(m, attention=attention).eval()
            with torch.no_grad():
                psi = model(data)
        except (RuntimeError, ValueError) as err:
            line = str(err).splitlines()[0]
            return [line if line.startswith("surenav.") else f"surenav.model: {line}"]
        if psi.shape != (data.num_nodes,):
            return [f"surenav.model: Psi of shape {tuple(psi.shape)} for {data.num_nodes} nodes; expected one per node"]
        counts.append(sum(p.numel() for p in model.parameters()))
    notes.append(f"surenav estimator {counts[0]:,} parameters (MPNN-only ablation {counts[1]:,}), "
                 f"batch {params.surenav.train.batch_size} on {params.surenav.train.device}")
    return []


def _three_node_graph():
    """A free node between two soft ones, start and goal at the ends: the smallest graph with both kinds."""
    from navlab.core.grid import RasterFrame
    from navlab.core.labels import FREE_IDS, SOFT_IDS
    from navlab.graphs.region_graph import RegionGraph

    xy = np.array([[0.5, 0.5], [1.5, 0.5], [2.5, 0.5]])
    edges = np.array([[0, 1], [1, 2]])
    return RegionGraph(superpixels=np.arange(3, dtype=np.int32)[None], frame=RasterFrame((1, 3), 1.0),
                       region_ids=np.arange(3), node_label=np.array([SOFT_IDS[0], FREE_IDS[0], SOFT_IDS[0]]),
                       centroid=xy, anchor=xy, area=np.ones(3), edges=edges, edge_length=np.ones(2),
                       edge_affinity=np.ones(2), portal=np.array([[1.0, 0.5], [2.0, 0.5]]), start_node=0, goal_node=2)


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


CHECKS = (pacer_data_problems, pacer_model_problems, pacer_baseline_problems, surenav_model_problems, hj_problems)


def check_profile(params: Params) -> tuple[list[str], list[str]]:
    """(problems, notes) of one loaded profile, every stage family checked.

    On one torch thread (restored after): the few CPU ops are tiny, and on a shared 2-core machine two
    OpenMP threads spinning against other jobs made the three-node SuReNav forward 0.7 s instead of 3 ms.
    """
    import torch

    problems: list[str] = []
    notes: list[str] = []
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        for check in CHECKS:
            problems += check(params, notes)
    finally:
        torch.set_num_threads(threads)
    return problems, notes
