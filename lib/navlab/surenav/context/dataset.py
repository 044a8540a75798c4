"""The context demonstrator's demonstrations as a dataset: the ``surenav_context_demos`` artefact step.

Train and validation: real tiles disjoint from the test tiles (``tiles``), ``train_pairs_per_map``
semi-static demonstrations each, drawn as ``environments.map_demonstrations`` draws the test ones.
Test: the five test tiles, drawn with the very generator ``environments.context_environments`` uses,
so the stored test demonstrations are Table I's 100 context environments. A tile where the walker
cannot find enough demonstrable pairs is skipped and named in the index.

Layout (``artifacts/surenav/context_demos/``): ``<split>/<map>.npz`` (the demonstrations in the
per-label store's format, ``experts.store``, with no static ones), ``<split>/<map>.map.npz`` (the tile's
SemanticMap: the train and validation tiles are not in data/), ``index.json`` (maps per split, skipped
tiles, the relaxation mix of every split).
"""

from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

import numpy as np
from tqdm.auto import tqdm

from navlab.core.io import DataError, load_npz, read_index, sha256_json, write_json
from navlab.core.labels import label_id
from navlab.core.params import Params
from navlab.core.seeding import rng
from navlab.graphs.superpixels import label_consistent_slic
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.context.environments import map_demonstrations
from navlab.surenav.context.tiles import real_tiles
from navlab.surenav.episodes import Environment
from navlab.surenav.experts.store import MapDemos, _unpack, save_map_demos

FOLDER = ("surenav", "context_demos")
SPLITS = ("train", "val", "test")
MIX_LABELS = {"road": ("road",), "grass": ("grass",), "parking": ("parking",), "rough": ("rough_terrain",),
              "living street": ("living_street",)}  # relaxation mix columns -> label names
_FIX = "build it with `python -m navlab artifacts build --only surenav_context_demos`"


def demo_rng(seed: int, split: str, name: str) -> np.random.Generator:
    """The generator of one tile's demonstrations; the test split's is ``context_environments``' own."""
    return rng(seed, "context demos", name) if split == "test" else rng(seed, "context demos", split, name)


def relaxation_mix(pairs: list[tuple[SemanticMap, MapDemos]]) -> dict:
    """Share of demonstrations relaxing each label group (a demonstration may relax several), share that
    jaywalked (a mid-block road region), and the count."""
    counts = dict.fromkeys(MIX_LABELS, 0)
    jaywalked = total = 0
    for smap, md in pairs:
        for demo in md.semi_static:
            relaxed = demo.labels_on(smap.labels).ravel()[demo.relaxed_cells]
            for group, names in MIX_LABELS.items():
                counts[group] += bool(np.isin(relaxed, [label_id(n) for n in names]).any())
            jaywalked += demo.jaywalked
            total += 1
    shares = {g: round(c / max(total, 1), 4) for g, c in counts.items()}
    return {"demonstrations": total, **shares, "jaywalked": round(jaywalked / max(total, 1), 4)}


def build_context_demos(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
    """Artefact step ``surenav_context_demos`` (see the module docstring)."""
    ctx, graph, settings = params.surenav.demos.context, params.surenav.graph, params.data.demos
    root = Path(artifacts_dir, *FOLDER)
    tiles = real_tiles(data_dir, params.data.maps, ctx.val_tiles, ctx.max_train_tiles, ctx.seed)
    if root.exists():
        shutil.rmtree(root)
    index: dict = {"maps": {}, "skipped": {}, "mix": {}}
    for split in SPLITS:
        n_pairs = ctx.test_pairs_per_map if split == "test" else ctx.train_pairs_per_map
        index["maps"][split], pairs = [], []
        for smap in tqdm(tiles[split], desc=f"context demos {split}", unit="tile"):
            superpixels = label_consistent_slic(smap.labels, graph.target_nodes, graph.compactness)
            try:
                demos = map_demonstrations(smap, superpixels, n_pairs, settings, demo_rng(ctx.seed, split, smap.name),
                                           graph)
            except DataError as err:
                if split == "test":
                    raise
                index["skipped"][smap.name] = str(err)
                continue
            fingerprint = sha256_json({"demos": settings, "graph": graph, "context": ctx, "map": smap.name,
                                       "labels": hashlib.sha256(smap.labels.tobytes()).hexdigest()})
            save_map_demos(root / split / f"{smap.name}.npz", superpixels, [], demos, fingerprint)
            smap.save(root / split / f"{smap.name}.map.npz")
            index["maps"][split].append(smap.name)
            pairs.append((smap, MapDemos(smap.name, split, superpixels, [], demos)))
        if not pairs:
            raise DataError(f"no {split} tile yields {n_pairs} context demonstrations; lower "
                            "surenav.demos.context.train_pairs_per_map")
        index["mix"][split] = relaxation_mix(pairs)
    write_json(root / "index.json", index)


def load_index(artifacts_dir: str | Path) -> dict:
    path = Path(artifacts_dir, *FOLDER, "index.json")
    if not path.is_file():
        raise DataError(f"{path} is missing; {_FIX}")
    try:
        index = read_index(path)
    except DataError:  # its own rebuild, not data/'s
        raise DataError(f"{path} is unreadable (not complete JSON); {_FIX}") from None
    maps = index.get("maps") if isinstance(index, dict) else None
    if not isinstance(maps, dict) or any(not isinstance(maps.get(split), list) for split in SPLITS):
        raise DataError(f"{path} does not list the tiles of each split ({', '.join(SPLITS)}); {_FIX}")
    return index


def load_context_demos(artifacts_dir: str | Path, split: str) -> list[tuple[SemanticMap, MapDemos]]:
    """(tile, its demonstrations) of one split, in the index's order."""
    if split not in SPLITS:
        raise ValueError(f"split {split!r}: splits are {', '.join(SPLITS)}")
    out = []
    for name in load_index(artifacts_dir)["maps"][split]:
        folder = Path(artifacts_dir, *FOLDER, split)
        arrays = load_npz(folder / f"{name}.npz", fix=_FIX)
        try:
            smap = SemanticMap.load(folder / f"{name}.map.npz")
        except DataError as err:  # this stage's tile: its rebuild, not data/'s
            raise DataError(f"{str(err).rsplit('; ', 1)[0]}; {_FIX}") from None
        out.append((smap, MapDemos(name, split, arrays["superpixels"], [], _unpack(arrays, "semi_static"))))
    return out


def stored_environments(artifacts_dir: str | Path) -> tuple[list[Environment], dict[str, np.ndarray]]:
    """The test demonstrations as Table I environments (as ``context_environments`` builds them, read from
    the stage's output rather than redrawn), and each test tile's stored superpixels."""
    envs, stored = [], {}
    for smap, md in load_context_demos(artifacts_dir, "test"):
        stored[smap.name] = md.superpixels
        for i, demo in enumerate(md.semi_static):
            envs.append(Environment(f"{smap.name}/{i}", smap.name, smap, demo.labels_on(smap.labels),
                                    smap.frame.world_to_cell(demo.start), smap.frame.world_to_cell(demo.goal),
                                    demo.persona, demo))
    return envs, stored
