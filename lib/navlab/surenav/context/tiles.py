"""Real training and validation tiles for the context benchmark, disjoint from the test tiles (issue 25, step 2).

The ``maps`` data step cuts every shipped OSM extract (Helsinki, Kouvola, Monaco) into 500 m tiles and
keeps five as test tiles; the train and validation maps it writes are procedural. The same extracts
hold more whole tiles than the five (``default``: 52 tiles, 25 of them with at least
``data.maps.min_sidewalk_fraction`` sidewalk besides the test ones). This module cuts them again from
``data/raw`` exactly as the ``maps`` step does (same reader, resolution and tile size, the same seeded
choice of test tiles), drops the test tiles and the tiles with too little sidewalk, and splits the rest
into validation and training tiles by a seeded draw. Nothing in ``data/`` is rewritten: the tiles are
recomputed inside the ``surenav_context_demos`` stage.

Disjoint means no cell in common; a training tile may border a test tile (tiles of one city are cut
side by side), as the paper's tiles of one city do.
"""

from __future__ import annotations

from pathlib import Path

from navlab.core.params.maps import MapsParams
from navlab.core.seeding import rng
from navlab.maps.osm import CITIES, read_city
from navlab.maps.semantic_map import SemanticMap
from navlab.maps.tiles import Tile, choose_test_tiles, cut_tiles


def split_tiles(tiles: list[Tile], maps: MapsParams, val_tiles: int, max_train_tiles: int, seed: int
                ) -> dict[str, list[Tile]]:
    """{"train", "val", "test"} tiles: test as the ``maps`` step chooses them, then every other tile with
    enough sidewalk, ``val_tiles`` of them drawn for validation and the rest (at most ``max_train_tiles``
    when > 0, the first of a seeded order) for training."""
    test = [t for t, _ in choose_test_tiles(tiles, maps.min_sidewalk_fraction, maps.extra_test_tiles, maps.seed)]
    names = {t.map.name for t in test}
    rest = [t for t in tiles if t.map.name not in names and t.sidewalk_fraction >= maps.min_sidewalk_fraction]
    if len(rest) <= val_tiles:
        raise ValueError(f"only {len(rest)} real non-test tiles have enough sidewalk; lower "
                         "surenav.demos.context.val_tiles (it must leave some to train on)")
    order = rng(seed, "context tiles").permutation(len(rest))
    val = [rest[int(k)] for k in sorted(order[:val_tiles])]
    train = [rest[int(k)] for k in order[val_tiles:]]
    if max_train_tiles:
        train = train[:max_train_tiles]
    train.sort(key=lambda t: t.map.name)
    splits = {"train": train, "val": val, "test": test}
    check_disjoint(splits)
    return splits


def check_disjoint(splits: dict[str, list[Tile]]) -> None:
    """Held out stays held out: a ValueError when one tile sits in two splits (or twice in one). Tiles of a
    city are cut side by side on one grid, so distinct (city, row, col) never share a cell on the ground."""
    where: dict[tuple[str, int, int], str] = {}
    for split, tiles in splits.items():
        for t in tiles:
            first = where.setdefault((t.city, t.row, t.col), split)
            if first != split or sum(u.city == t.city and (u.row, u.col) == (t.row, t.col) for u in tiles) > 1:
                raise ValueError(f"tile {t.map.name} is in the {first} split and again in the {split} split; the "
                                 "splits must share no tile (a held-out tile would be trained on)")


def real_tiles(data_dir: str | Path, maps: MapsParams, val_tiles: int, max_train_tiles: int, seed: int
               ) -> dict[str, list[SemanticMap]]:
    """``split_tiles`` of the shipped extracts in ``data_dir``/raw, as semantic maps (each in its own frame)."""
    tiles = []
    for city in CITIES:
        smap, network = read_city(data_dir, city, maps.resolution_m)
        tiles.extend(cut_tiles(city, smap, network, maps.tile_size_m))
    return {split: [t.map for t in chosen]
            for split, chosen in split_tiles(tiles, maps, val_tiles, max_train_tiles, seed).items()}
