"""Real-city tiles: cut a city raster into square tiles and hold some out as the test cities.

The paper tests on three held-out cities of different structure (Baltimore: grid, Milan: irregular,
Capitol Hill: mixed) plus two more maps for human-likeness. Our stand-ins: one tile each from
Helsinki (grid-like), Monaco (irregular) and Kouvola (suburban), then ``extra`` more real tiles, each
drawn by a seeded generator among the tiles with enough sidewalk (``choose_test_tiles``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.core.labels import label_id
from navlab.core.seeding import rng
from navlab.maps.network import WalkableNetwork, clip
from navlab.maps.semantic_map import SemanticMap

TEST_CITY_ROLES = {"helsinki": "baltimore", "monaco": "milan", "kouvola": "capitol_hill"}


@dataclass(frozen=True)
class Tile:
    city: str
    row: int
    col: int
    map: SemanticMap
    network: WalkableNetwork

    @property
    def sidewalk_fraction(self) -> float:
        return float(np.mean(self.map.labels == label_id("sidewalk")))


def cut_tiles(city: str, smap: SemanticMap, network: WalkableNetwork, size_m: float) -> list[Tile]:
    """Every whole ``size_m`` square tile of the city, row-major, each in its own frame (origin 0, 0)."""
    cells = round(size_m / smap.frame.resolution)
    tiles = []
    rows, cols = smap.labels.shape
    for i in range(rows // cells):
        for j in range(cols // cells):
            labels = smap.labels[i * cells:(i + 1) * cells, j * cells:(j + 1) * cells].copy()
            name = f"{city}_r{i}c{j}"
            frame = RasterFrame((cells, cells), smap.frame.resolution)
            x0, y0 = j * cells * smap.frame.resolution, i * cells * smap.frame.resolution
            side = cells * smap.frame.resolution
            tiles.append(Tile(city, i, j, SemanticMap(name, labels, frame), clip(network, x0, y0, side, side)))
    return tiles


def choose_test_tiles(tiles: list[Tile], min_sidewalk: float, extra: int, seed: int) -> list[tuple[Tile, str]]:
    """(tile, role) for one test tile per city (role: the paper city it stands for) and ``extra`` more
    (role ``human_likeness``), drawn among the tiles with at least ``min_sidewalk`` sidewalk cells.

    A test city's tile comes from the better-mapped half of that city (sidewalk fraction at least the
    city's median), so that it shows the city's streets rather than its harbour or its fields.
    """
    eligible = [t for t in tiles if t.sidewalk_fraction >= min_sidewalk]
    chosen: list[tuple[Tile, str]] = []
    for city, role in TEST_CITY_ROLES.items():
        median = np.median([t.sidewalk_fraction for t in tiles if t.city == city] or [np.inf])
        pool = [t for t in eligible if t.city == city and t.sidewalk_fraction >= median]
        if not pool:
            raise ValueError(f"{city}: no tile has a sidewalk fraction >= {min_sidewalk}; "
                             "lower data.maps.min_sidewalk_fraction in params.yaml")
        chosen.append((pool[int(rng(seed, "test_city", city).integers(len(pool)))], role))
    rest = [t for t in eligible if all(t is not c for c, _ in chosen)]
    if len(rest) < extra:
        raise ValueError(f"only {len(rest)} more tiles have enough sidewalk for data.maps.extra_test_tiles = "
                         f"{extra}; lower it or data.maps.min_sidewalk_fraction")
    picks = rng(seed, "human_likeness").choice(len(rest), size=extra, replace=False)
    chosen.extend((rest[int(k)], "human_likeness") for k in sorted(picks))
    return chosen
