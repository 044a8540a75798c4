"""`params check` for PACER: the terrain bank's checks on ``pacer.data`` and the photographs of
your own it lists, and PACER's network and baselines built on ``meta`` against the machine's memory budget.

Each ``*_problems(params, notes)`` returns one line per problem, naming the params key, and may append what it
measured to ``notes``; the manifest (``track.py``) lists them, ``navlab.pipeline.profile_check`` runs them on
every profile.
"""

from __future__ import annotations

from collections.abc import Callable

from navlab.core.budgets import GIB, budget_gib
from navlab.core.params import Params
from navlab.core.params.constraints import surenav_test_map_px

ADAM_BYTES_PER_PARAM = 16  # fp32 weight, gradient and Adam's two moments


def data_problems(params: Params, notes: list[str]) -> list[str]:
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


def model_problems(params: Params, notes: list[str]) -> list[str]:
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


def baseline_problems(params: Params, notes: list[str]) -> list[str]:
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


def variant_problems(params: Params, notes: list[str]) -> list[str]:
    """The extra training seeds (``pacer.variants.seeds``) must differ from the main model's and each other:
    a repeated seed trains the same weights again, and the tables would count one model as two seeds."""
    p = params.pacer
    seeds = (p.seed, *p.variants.seeds)
    repeated = sorted({s for s in seeds if seeds.count(s) > 1})
    if repeated:
        return [(f"pacer.variants.seeds = {list(p.variants.seeds)} repeats seed(s) {repeated} "
                 f"(pacer.seed = {p.seed}); give each extra training seed once, none equal to pacer.seed")]
    return []
