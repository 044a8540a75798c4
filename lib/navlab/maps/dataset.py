"""The benchmark maps in data/surenav/maps: the ``maps`` build step and its loaders.

Layout: ``<split>/<name>.npz`` (a SemanticMap) and ``<split>/<name>.network.npz`` (its WalkableNetwork)
for split in train / val / test, and ``index.json`` listing every map (name, split, source city or
``procedural``, role, structure knob, measured street regularity, size). Train and validation maps are
procedural; the test maps are held-out real tiles (see ``tiles``).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
from tqdm import tqdm

from navlab.core.io import read_index, require, write_json
from navlab.core.params import Params
from navlab.core.seeding import rng
from navlab.maps.network import WalkableNetwork, network_from_raster
from navlab.maps.osm import CITIES, read_city
from navlab.maps.procedural import generate, street_regularity
from navlab.maps.semantic_map import SemanticMap
from navlab.maps.tiles import choose_test_tiles, cut_tiles

SPLITS = ("train", "val", "test")
FOLDER = ("surenav", "maps")


def _entry(smap: SemanticMap, split: str, source: str, role: str, structure: float | None) -> dict:
    rows, cols = smap.labels.shape
    res = smap.frame.resolution
    return {
        "name": smap.name, "split": split, "source": source, "role": role, "structure": structure,
        "regularity": round(street_regularity(smap.labels), 4), "size_m": [cols * res, rows * res],
        "shape": [rows, cols], "resolution_m": res,
    }


def _save(root: Path, split: str, smap: SemanticMap, network: WalkableNetwork) -> None:
    smap.save(root / split / f"{smap.name}.npz")
    network.save(root / split / f"{smap.name}.network.npz")


def structure_levels(seed: int, split: str, count: int) -> np.ndarray:
    """``count`` structure knobs stratified over [0, 1] (one per equal-width bin), so each split spans
    grid, mixed and irregular cities."""
    return (np.arange(count) + rng(seed, "structure", split).random(count)) / count


def build_maps(params: Params, out_dir: Path) -> None:
    """Data step ``maps``: held-out real test tiles and procedural train/val maps, with their networks."""
    p = params.data.maps
    root = Path(out_dir, *FOLDER)
    if root.exists():
        shutil.rmtree(root)  # a resumed build rewrites this step's folder from scratch
    entries = []
    tiles = []
    for city in tqdm(CITIES, desc="maps: cities", leave=False):
        smap, network = read_city(out_dir, city, p.resolution_m)
        tiles.extend(cut_tiles(city, smap, network, p.tile_size_m))
    for tile, role in choose_test_tiles(tiles, p.min_sidewalk_fraction, p.extra_test_tiles, p.seed):
        _save(root, "test", tile.map, tile.network)
        entries.append(_entry(tile.map, "test", tile.city, role, None))
    for split, count in (("train", p.train_maps), ("val", p.val_maps)):
        levels = structure_levels(p.seed, split, count)
        for k in tqdm(range(count), desc=f"maps: {split}", leave=False):
            structure = round(float(levels[k]), 4)
            smap = generate(p.seed, f"procedural_{split}_{k:02d}", structure, p.procedural, p.resolution_m)
            _save(root, split, smap, network_from_raster(smap))
            entries.append(_entry(smap, split, "procedural", "train" if split == "train" else "val", structure))
    write_json(root / "index.json", {"maps": entries})


def load_index(data_dir: str | Path) -> list[dict]:
    """Every map's index entry, in build order."""
    return read_index(require(data_dir, *FOLDER, "index.json"))["maps"]


def check_split(split: str) -> None:
    """A split name, or a ValueError listing the splits (maps and demonstrations share them)."""
    if split not in SPLITS:
        raise ValueError(f"split {split!r}: splits are {', '.join(SPLITS)}")


def load_maps(data_dir: str | Path, split: str) -> list[SemanticMap]:
    """The maps of one split (train / val / test), in index order."""
    check_split(split)
    return [SemanticMap.load(require(data_dir, *FOLDER, split, f"{e['name']}.npz"))
            for e in load_index(data_dir) if e["split"] == split]


def load_network(data_dir: str | Path, split: str, name: str) -> WalkableNetwork:
    """The walkable network of one map (metres in that map's frame)."""
    check_split(split)
    return WalkableNetwork.load(require(data_dir, *FOLDER, split, f"{name}.network.npz"))
