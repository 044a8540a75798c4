"""Rendered aerial maps for the navigation experiments (PACER Sec. VI-A, Tables I-II).

The paper plans with A* over drone orthophotos of its campus (seen) and OpenAerialMap tiles (unseen).
Ours are large rendered maps over 3-5 terrains of one group, textured at the BEV images' ground scale
(a window of ``image_size`` pixels is one BEV image's footprint), with a start and a goal near opposite
edges. The label layout is either procedural (many warped Voronoi regions and a few trails from edge to
edge) or, with ``aerial.layout: surenav``, a window of a SuReNav test map (real OpenStreetMap tiles and
their procedural kin) drawn at ``layout.street_zoom`` pixels per metre: each semantic label becomes one
terrain, so sidewalks are the trails and the region shapes are a city's. The hidden total ordering for
scoring is the realistic one (or its inversion) over ``terrains``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from navlab.core.params import Params
from navlab.core.params.pacer import PacerDataParams
from navlab.core.seeding import rng as seeded_rng
from navlab.maps.dataset import load_maps
from navlab.maps.semantic_map import SemanticMap
from navlab.pacer.bev import render_aerial
from navlab.pacer.layouts import aerial_layout
from navlab.pacer.terrain import TerrainBank, load_terrain_bank

EDGE_MARGIN = 0.04  # start and goal sit this fraction of the map inside its edges


@dataclass(frozen=True, eq=False)
class AerialMap:
    image: np.ndarray  # float32 (3, S, S) RGB in [0, 1]
    labels: np.ndarray  # int64 (S, S) terrain ids
    terrains: np.ndarray  # int64 (L,) terrain ids on the map, ascending
    start: tuple[int, int]  # (row, col)
    goal: tuple[int, int]


def semantic_map_regions(semantic_maps: Sequence[SemanticMap], size: int, rng: np.random.Generator,
                         zoom: int = 1) -> np.ndarray:
    """Region ids of a ``size`` × ``size`` window of one of ``semantic_maps``: one region per label present.

    At ``zoom`` z the window covers ``ceil(size / z)`` map pixels (metres), each drawn as z × z pixels
    (nearest neighbour), so a 2 m sidewalk is 2 z pixels of texture (``pacer.data.layout.street_zoom``).
    """
    semantic = semantic_maps[int(rng.integers(len(semantic_maps)))]
    rows, cols = semantic.labels.shape
    cut = -(-size // zoom)
    if rows < cut or cols < cut:
        raise ValueError(f"{semantic.name}: map {semantic.labels.shape} is smaller than the aerial size {size} "
                         f"at zoom {zoom} ({cut} px); lower pacer.data.aerial.size, raise "
                         "pacer.data.layout.street_zoom or raise data.maps.tile_size_m")
    r0, c0 = (int(rng.integers(n - cut + 1)) for n in (rows, cols))
    _, regions = np.unique(semantic.labels[r0:r0 + cut, c0:c0 + cut], return_inverse=True)
    # the crop drops fewer than z rows and columns, so every block (and every label's id) keeps a pixel
    return regions.reshape(cut, cut).repeat(zoom, axis=0).repeat(zoom, axis=1)[:size, :size]


def aerial_map(bank: TerrainBank, params: PacerDataParams, terrains: Literal["seen", "unseen"], index: int,
               seed: int, semantic_maps: Sequence[SemanticMap] = ()) -> AerialMap:
    """Map ``index`` of the ``terrains`` group, seeded by ``(seed, "pacer-aerial", terrains, index)``.

    ``semantic_maps`` are needed (and used) only with ``aerial.layout: surenav``.
    """
    rng = seeded_rng(seed, "pacer-aerial", terrains, index)
    aerial = params.aerial
    if aerial.layout == "surenav":
        if not semantic_maps:
            raise ValueError("aerial.layout 'surenav' needs the SuReNav maps (pass semantic_maps)")
        regions = semantic_map_regions(semantic_maps, aerial.size, rng, params.layout.street_zoom)
    else:
        regions = aerial_layout(rng, aerial, params.layout, params.image_size)
    group = bank.ids(terrains)
    count = int(rng.integers(aerial.terrains[0], min(aerial.terrains[1], len(group)) + 1))
    chosen = rng.choice(group, size=count, replace=False)
    n_regions = int(regions.max()) + 1
    region_terrains = np.concatenate([rng.permutation(chosen), rng.choice(chosen, size=max(0, n_regions - count))])
    labels = region_terrains[:n_regions][regions]
    image = render_aerial(labels, bank, rng, params)
    start, goal = _start_goal(rng, aerial.size)
    return AerialMap(np.ascontiguousarray(image.transpose(2, 0, 1)), labels.astype(np.int64), np.unique(labels),
                     start, goal)


def aerial_maps(params: Params, data_dir: str | Path, terrains: Literal["seen", "unseen"],
                bank: TerrainBank | None = None) -> list[AerialMap]:
    """The ``params.pacer.data.aerial.maps`` evaluation maps of one group (seen or unseen environments)."""
    if terrains not in ("seen", "unseen"):
        raise ValueError(f"terrains {terrains!r}: aerial maps are 'seen' or 'unseen' environments")
    data = params.pacer.data
    bank = bank if bank is not None else load_terrain_bank(data_dir, data)
    semantic_maps = load_maps(data_dir, "test") if data.aerial.layout == "surenav" else ()
    return [aerial_map(bank, data, terrains, i, params.pacer.seed, semantic_maps) for i in range(data.aerial.maps)]


def _start_goal(rng: np.random.Generator, size: int) -> tuple[tuple[int, int], tuple[int, int]]:
    """Opposite edges (left-right or top-bottom, either way round), random positions along them."""
    near, far = round(EDGE_MARGIN * size), size - 1 - round(EDGE_MARGIN * size)
    a, b = (int(v) for v in rng.integers(round(0.15 * size), round(0.85 * size), size=2))
    ends = [(a, near), (b, far)] if rng.uniform() < 0.5 else [(near, a), (far, b)]
    if rng.uniform() < 0.5:
        ends.reverse()
    return ends[0], ends[1]
