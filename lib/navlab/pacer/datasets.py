"""PACER's datasets (Sec. V-C): D_real, D_shuffled, D_synthetic and the evaluation sets, made on the fly.

Every item is generated from its own seed ``(params.pacer.seed, recipe stream, split, index)`` (plus ``epoch``
when one is set, for augmentation), so item i is the same bytes in every epoch, on every machine, with
any number of DataLoader workers; nothing is written to data/. An item is a dict of tensors:

=========== ======================= =================================================================
key         dtype, shape            meaning
=========== ======================= =================================================================
image       float32 (3, S, S)       BEV image in [0, 1], zero outside the field of view
context     float32 (3n, 2h, w)     preference context: pair i in channels 3i..3i+2, preferred on top
costmap     float32 (S, S)          target cost (l-1)/(L-1) of each pixel's terrain rank l; 0 outside FOV
fov_mask    bool (S, S)             the trapezoid field of view (the loss is taken inside it only)
labels      int64 (S, S)            terrain ids (``TerrainBank.terrains``), -1 outside the FOV
ordering    int64 (L_max,)          the L terrains the target ranks, most preferred first, padded with -1
pairs       int64 (n, 2)            terrain ids (preferred, other) of each context pair, in channel order
=========== ======================= =================================================================

Layouts: the procedural ones of ``pacer.layouts`` (Voronoi regions and a trail), or, for a fraction
``pacer.data.layout.street_windows`` of training items, a window of a SuReNav train/val street map
(``STREET_SPLIT``: never the test tiles the evaluation maps are cut from), each semantic label painted
with one of 2-4 terrains. With the fraction 0 nothing extra is drawn and every item is as before.

Recipes (``RECIPES``):

Training recipes draw their contexts as ``pacer.data.train_context`` says: ``superset`` (as at
deployment and in the released code: pairs over the terrains in view plus ``context_extra`` others of
the same pool, every terrain in view named where n allows) or ``in_view``. The target ranks the terrains
as ``pacer.data.train_target`` says: ``in_view`` only those in view (in the superset's order), so a
terrain's level depends on its neighbours in the window; ``context`` every terrain of the superset, so
the levels are those of the operator's whole ordering, the same in every window of a map (the paper's
H(τ_l) = (l-1)/(L-1) ranks the whole total ordering, Sec. V-A).

* ``real``: seen terrains, the realistic ordering (phase 1);
* ``shuffled``: seen terrains, a uniformly random permutation per item (phase 2);
* ``synthetic``: a seen layout in which each terrain is replaced by a Sweet Home 3D texture with chance
  ``synthetic_replace`` (at least one is), then each terrain recoloured with chance ``recolour.probability``
  alike in image and context (``pacer.recolour``), random ordering (phase 3);
* evaluation (:func:`evaluation_dataset`): seen or unseen terrains x realistic or inverted ordering, with
  an informative context (in-view or superset) or an uninformative one (terrains of the other group only).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
import torch
from torch.utils.data import Dataset

from navlab.core.params import Params
from navlab.core.params.pacer import PacerDataParams
from navlab.core.seeding import rng as seeded_rng
from navlab.maps.dataset import load_maps
from navlab.maps.semantic_map import SemanticMap
from navlab.pacer.aerial import semantic_map_regions
from navlab.pacer.bev import fov_mask, render_bev
from navlab.pacer.context import preference_context, superset_terrains, uninformative_context
from navlab.pacer.layouts import bev_layout
from navlab.pacer.preferences import IGNORE, Preference, order_terrains, pad_ordering, target_costmap
from navlab.pacer.recolour import recolour_terrains
from navlab.pacer.terrain import TerrainBank, load_terrain_bank

Split = Literal["train", "val", "test"]
SPLITS: tuple[Split, ...] = ("train", "val", "test")
# street windows come from SuReNav's training geography only, never from its test tiles (the evaluation maps)
STREET_SPLIT = {"train": "train", "val": "val", "test": "val"}
ContextDraw = Literal["in_view", "superset"]
CONTEXT_DRAWS: tuple[ContextDraw, ...] = ("in_view", "superset")


@dataclass(frozen=True)
class Recipe:
    """How one dataset's items are made. Items are seeded by ``stream``: recipes that share it share their
    layouts and images and differ only in ordering and context (realistic vs inverted evaluation)."""

    name: str
    stream: str
    terrains: Literal["seen", "unseen"]
    preference: Preference
    synthetic: bool = False  # replace some terrains by synthetic ones (D_synthetic)
    informative: bool = True  # False: the context shows only terrains of the other group
    context: ContextDraw = "in_view"  # superset: pairs over the terrains in view plus context_extra others


RECIPES = {
    "real": Recipe("real", "real", "seen", "realistic"),
    "shuffled": Recipe("shuffled", "shuffled", "seen", "random"),
    "synthetic": Recipe("synthetic", "synthetic", "seen", "random", synthetic=True),
}


def max_terrains(params: PacerDataParams) -> int:
    """L_max: the most terrains one BEV image can show (the padded length of ``ordering``)."""
    in_view = params.layout.regions[1] + (1 if params.layout.path_probability > 0 else 0)
    return in_view + (params.context_extra if params.train_target == "context" else 0)


class PacerDataset(Dataset):
    """``size`` items of ``recipe`` for ``split``; see the module docstring for the item layout."""

    def __init__(self, bank: TerrainBank, params: PacerDataParams, recipe: Recipe, split: Split, size: int,
                 seed: int, epoch: int | None = None, street_maps: Sequence[SemanticMap] = ()):
        if split not in SPLITS:
            raise ValueError(f"split {split!r}: allowed splits are {', '.join(SPLITS)}")
        if params.layout.street_windows > 0 and not street_maps:
            raise ValueError(f"{recipe.name}/{split}: pacer.data.layout.street_windows > 0 needs the SuReNav maps "
                             "(street_maps=); build them with `python -m navlab data build`")
        self.bank, self.params, self.recipe, self.split = bank, params, recipe, split
        self.size, self.seed, self.epoch, self.street_maps = size, seed, epoch, tuple(street_maps)

    def __len__(self) -> int:
        return self.size

    def set_epoch(self, epoch: int | None) -> None:
        """Draw fresh items per epoch (augmentation); None: the same items every epoch."""
        self.epoch = epoch

    def __getitem__(self, index: int) -> dict[str, torch.Tensor]:
        return {key: torch.from_numpy(value) for key, value in self.item(index).items()}

    def item(self, index: int) -> dict[str, np.ndarray]:
        """Item ``index`` as numpy arrays (same keys, dtypes and shapes as ``__getitem__``)."""
        if not 0 <= index < self.size:
            raise IndexError(f"item {index} is outside {self.recipe.name}/{self.split} (size {self.size})")
        keys = ("pacer", self.recipe.stream, self.split, index) + (() if self.epoch is None else ("epoch", self.epoch))
        rng = seeded_rng(self.seed, *keys)
        return make_item(self.bank, self.params, self.recipe, rng, self.street_maps)


def make_item(bank: TerrainBank, params: PacerDataParams, recipe: Recipe, rng: np.random.Generator,
              street_maps: Sequence[SemanticMap] = ()) -> dict:
    """One item of ``recipe`` (numpy arrays); every random draw comes from ``rng``."""
    if params.layout.street_windows > 0 and rng.uniform() < params.layout.street_windows:
        regions = semantic_map_regions(street_maps, params.image_size, rng, params.layout.street_zoom)
        region_terrains = street_terrains(int(regions.max()) + 1, bank.ids(recipe.terrains),
                                          params.layout.regions[1] + 1, rng)
    else:
        regions = bev_layout(rng, params.image_size, params.layout, params.camera.near_width)
        region_terrains = rng.choice(bank.ids(recipe.terrains), size=int(regions.max()) + 1, replace=False)
    if recipe.synthetic:
        visible = np.unique(regions[fov_mask(params.image_size, params.camera.near_width)])
        region_terrains = _replace_with_synthetic(region_terrains, visible, bank, rng, params.synthetic_replace)
    terrain_map = region_terrains[regions]
    image, fov = render_bev(terrain_map, bank, rng, params)
    labels = np.where(fov, terrain_map, IGNORE)
    in_view = np.unique(labels[fov])
    ordering = order_terrains(in_view, recipe.preference, bank, rng)
    if recipe.informative and recipe.context == "superset":
        pool = np.concatenate([bank.ids(g) for g in (recipe.terrains, "synthetic")[: 1 + recipe.synthetic]])
        drawn = order_terrains(superset_terrains(in_view, pool, params.context_extra, rng), recipe.preference,
                               bank, rng)
        ordering = drawn if params.train_target == "context" else drawn[np.isin(drawn, in_view)]
        context, pairs = preference_context(bank, drawn, rng, params, cover=in_view)
    elif recipe.informative:
        context, pairs = preference_context(bank, ordering, rng, params)
    else:
        context, pairs = uninformative_context(bank, recipe.terrains, recipe.preference, rng, params)
    if recipe.synthetic:
        image, context = recolour_terrains(image, labels, context, pairs, rng, params.recolour)
    return {
        "image": np.ascontiguousarray(image.transpose(2, 0, 1)),
        "context": context,
        "costmap": target_costmap(labels, ordering),
        "fov_mask": fov,
        "labels": labels.astype(np.int64),
        "ordering": pad_ordering(ordering, max_terrains(params)),
        "pairs": pairs,
    }


def street_terrains(regions: int, pool: np.ndarray, most: int, rng: np.random.Generator) -> np.ndarray:
    """Terrain ids of a street window's ``regions`` (one per semantic label): 2..``most`` distinct terrains of
    ``pool``, each used at least once, as the evaluation maps assign several labels to one terrain."""
    count = min(regions, most, len(pool))
    count = int(rng.integers(min(2, count), count + 1))
    chosen = rng.choice(pool, size=count, replace=False)
    return rng.permutation(np.concatenate([chosen, rng.choice(chosen, size=regions - count)]))


def _replace_with_synthetic(terrains: np.ndarray, visible: np.ndarray, bank: TerrainBank,
                            rng: np.random.Generator, chance: float) -> np.ndarray:
    """Each terrain of the layout (``terrains``: one per region) becomes a distinct synthetic one with
    probability ``chance``, in every region it fills (a street window paints several labels with one
    terrain); at least one terrain in view (regions ``visible``) does, so every D_synthetic image shows a
    synthetic terrain."""
    if len(np.unique(terrains)) == len(terrains):  # one terrain per region: draw per region, as always
        kinds, index = terrains, np.arange(len(terrains))
    else:
        kinds, index = np.unique(terrains, return_inverse=True)
    replace = rng.uniform(size=len(kinds)) < chance
    shown = np.unique(index[visible])
    if not replace[shown].any():
        replace[shown[int(rng.integers(len(shown)))]] = True
    out = kinds.copy()
    out[replace] = rng.choice(bank.ids("synthetic"), size=int(replace.sum()), replace=False)
    return out[index]


def pacer_dataset(params: Params, data_dir: str | Path, name: str, split: Split = "train",
                  bank: TerrainBank | None = None) -> PacerDataset:
    """D_real / D_shuffled / D_synthetic (``name`` = real, shuffled, synthetic) for ``split``, sized by
    ``params.pacer.data.sizes``; pass ``bank`` to share one loaded bank between datasets."""
    if name not in RECIPES:
        raise ValueError(f"dataset {name!r}: allowed names are {', '.join(RECIPES)}")
    data = params.pacer.data
    bank = bank if bank is not None else load_terrain_bank(data_dir, data)
    recipe = dataclasses.replace(RECIPES[name], context=data.train_context)
    street_maps = load_maps(data_dir, STREET_SPLIT[split]) if data.layout.street_windows > 0 else ()
    return PacerDataset(bank, data, recipe, split, getattr(data.sizes, split), params.pacer.seed,
                        street_maps=street_maps)


def evaluation_dataset(params: Params, data_dir: str | Path, terrains: Literal["seen", "unseen"],
                       preference: Literal["realistic", "inverted"], informative: bool = True,
                       split: Split = "test", bank: TerrainBank | None = None,
                       context: ContextDraw = "superset") -> PacerDataset:
    """Held-out BEV items on ``terrains`` under the realistic or inverted ordering (Tables III-IV style),
    with an informative context (drawn over the terrains in view, or as at deployment over a superset of
    them) or an uninformative one (``informative=False``). All variants of one ``terrains`` show the same
    images: only the ordering, the costmap and the context differ."""
    if context not in CONTEXT_DRAWS:
        raise ValueError(f"context {context!r}: contexts are drawn {' or '.join(CONTEXT_DRAWS)}")
    if terrains not in ("seen", "unseen"):
        raise ValueError(f"terrains {terrains!r}: evaluation sets are 'seen' or 'unseen'")
    if preference not in ("realistic", "inverted"):
        raise ValueError(f"preference {preference!r}: evaluation sets are 'realistic' or 'inverted'")
    name = f"eval-{terrains}-{preference}-" + (context if informative else "uninformative")
    recipe = Recipe(name, f"eval-{terrains}", terrains, preference, informative=informative, context=context)
    data = params.pacer.data
    bank = bank if bank is not None else load_terrain_bank(data_dir, data)
    return PacerDataset(bank, data, recipe, split, getattr(data.sizes, split), params.pacer.seed)
