"""The demonstrations in data/: one byte-deterministic .npz per map, written by the `demos` data step.

Layout: ``<data>/surenav/demos/<split>/<map>.npz`` holds the map's superpixel raster (the regions the
relaxed-region masks and perturbations refer to) and, per kind (``static``, ``semi_static``), every
demonstration's arrays concatenated with offsets; ``<data>/surenav/demos/index.json`` counts them.
The superpixels follow params.yaml ``surenav.graph`` (the graph the SuReNav planner is trained on), so
the snapshot depends on that section as well as on ``data.demos``.
"""

from __future__ import annotations

import hashlib
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from navlab.core.fingerprint import code_fingerprint
from navlab.core.io import (
    BUILD_STAMPS,
    DataError,
    load_npz,
    read_index,
    require,
    save_npz,
    sha256_json,
    write_json,
    write_text,
)
from navlab.core.params import Params
from navlab.core.params.surenav_graph import GraphParams
from navlab.core.seeding import rng
from navlab.graphs.incremental import resegment
from navlab.graphs.region_graph import RegionGraph, build_region_graph
from navlab.graphs.superpixels import label_consistent_slic
from navlab.maps.dataset import SPLITS, check_split, load_maps
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.experts.environments import Demonstration, map_environments

DEMOS_DIR = Path("surenav", "demos")
KINDS = ("static", "semi_static")
_RAGGED = {"path": np.float32, "relaxed_cells": np.int64, "relaxed_superpixels": np.int64,
           "delta_cells": np.int64, "delta_labels": np.uint8}
_FIX = "build the dataset with `python -m navlab data build` (step `demos`)"


@dataclass(frozen=True)
class MapDemos:
    map_name: str
    split: str
    superpixels: np.ndarray  # (rows, cols) int32, -1 in hard space
    static: list[Demonstration]
    semi_static: list[Demonstration]


def _pack(demos: list[Demonstration], kind: str) -> dict[str, np.ndarray]:
    out = {}
    for name, dtype in _RAGGED.items():
        parts = [getattr(d, name) for d in demos]
        empty = np.zeros((0, 2) if name == "path" else 0)
        out[f"{kind}/{name}"] = np.concatenate(parts or [empty]).astype(dtype)
        out[f"{kind}/{name}_offsets"] = np.cumsum([0] + [len(p) for p in parts]).astype(np.int64)
    out[f"{kind}/start"] = np.array([d.start for d in demos], dtype=np.float64).reshape(-1, 2)
    out[f"{kind}/goal"] = np.array([d.goal for d in demos], dtype=np.float64).reshape(-1, 2)
    out[f"{kind}/persona"] = np.array([d.persona for d in demos], dtype=np.int64)
    out[f"{kind}/jaywalked"] = np.array([d.jaywalked for d in demos], dtype=bool)
    out[f"{kind}/prefix_len"] = np.array([d.prefix_len for d in demos], dtype=np.int64)
    return out


def _unpack(arrays: dict[str, np.ndarray], kind: str) -> list[Demonstration]:
    demos = []
    for i in range(len(arrays[f"{kind}/persona"])):
        ragged = {name: arrays[f"{kind}/{name}"][arrays[f"{kind}/{name}_offsets"][i]:
                                                   arrays[f"{kind}/{name}_offsets"][i + 1]] for name in _RAGGED}
        demos.append(Demonstration(kind=kind, start=arrays[f"{kind}/start"][i], goal=arrays[f"{kind}/goal"][i],
                                   persona=int(arrays[f"{kind}/persona"][i]),
                                   jaywalked=bool(arrays[f"{kind}/jaywalked"][i]),
                                   prefix_len=int(arrays[f"{kind}/prefix_len"][i]), **ragged))
    return demos


def save_map_demos(path: str | Path, superpixels: np.ndarray, static: list[Demonstration],
                   semi_static: list[Demonstration], fingerprint: str) -> None:
    save_npz(path, {"superpixels": superpixels.astype(np.int32), "fingerprint": np.array(fingerprint),
                    **_pack(static, "static"), **_pack(semi_static, "semi_static")})


def load_demos(data_dir: str | Path, split: str) -> list[MapDemos]:
    """Every map's demonstrations of one split, in map-name order: the maps ``index.json`` lists, not the
    files that happen to lie in the folder (a deleted or stray file must not change the dataset)."""
    check_split(split)
    index = read_index(require(data_dir, DEMOS_DIR, "index.json"))
    if split not in index:
        raise DataError(f"{Path(data_dir, DEMOS_DIR, 'index.json')} lists no {split!r} split; {_FIX}")
    out = []
    for name in sorted(index[split]):
        path = Path(data_dir, DEMOS_DIR, split, f"{name}.npz")
        arrays = load_npz(path, fix=_FIX)
        out.append(MapDemos(path.stem, split, arrays["superpixels"], _unpack(arrays, "static"),
                            _unpack(arrays, "semi_static")))
    return out


def build_demos(params: Params, out_dir: Path) -> None:
    """The `demos` data step: demonstrations on every map the `maps` step wrote into ``out_dir``."""
    settings, graph = params.data.demos, params.surenav.graph
    code = code_fingerprint(__name__)  # a build resumed under edited generator code redoes every map
    index = {}
    for split in SPLITS:
        maps = load_maps(out_dir, split)
        n_pairs = settings.test_pairs_per_map if split == "test" else settings.pairs_per_map
        index[split] = {}
        folder = Path(out_dir, DEMOS_DIR, split)
        for stale in set(folder.glob("*.npz")) - {folder / f"{m.name}.npz" for m in maps}:
            stale.unlink()  # a resumed build over other maps: load_demos would read this file as a map's
        for semantic_map in tqdm(maps, desc=f"demos {split}", unit="map"):
            target = folder / f"{semantic_map.name}.npz"
            fingerprint = sha256_json({"demos": settings, "graph": graph, "map": semantic_map.name,
                                       "labels": hashlib.sha256(semantic_map.labels.tobytes()).hexdigest()})
            stamp = Path(out_dir, BUILD_STAMPS, "demos", split, f"{semantic_map.name}.done")
            key = sha256_json({"fingerprint": fingerprint, "code": code})
            if not _is_built(target, fingerprint, stamp, key):
                superpixels = label_consistent_slic(semantic_map.labels, graph.target_nodes, graph.compactness)
                static, semi = map_environments(semantic_map, superpixels, n_pairs, settings,
                                                rng(settings.seed, "demos", split, semantic_map.name),
                                                graph.compactness)
                save_map_demos(target, superpixels, static, semi, fingerprint)
                write_text(stamp, key)
            index[split][semantic_map.name] = {"static": n_pairs, "semi_static": n_pairs}
    write_json(Path(out_dir, DEMOS_DIR, "index.json"), index)


def demo_graph(md: MapDemos, demo: Demonstration, semantic_map: SemanticMap, graph: GraphParams) -> RegionGraph:
    """The region graph a demonstration lives on, start and goal set; its ``relaxed_superpixels`` are
    node ids of this graph (``np.searchsorted(g.region_ids, demo.relaxed_superpixels)`` gives nodes).

    Static: the map's stored superpixels. Semi-static: those after the incremental update (Algorithm 1)
    for the perturbed cells.
    """
    labels = demo.labels_on(semantic_map.labels)
    superpixels = md.superpixels
    if len(demo.delta_cells):
        changed = np.zeros(labels.shape, dtype=bool)
        changed.ravel()[demo.delta_cells] = True
        superpixels = resegment(superpixels, labels, changed, graph.compactness)
    region_graph = build_region_graph(superpixels, labels, semantic_map.frame, graph.tau_m)
    return region_graph.with_endpoints(demo.start, demo.goal)


def _is_built(target: Path, fingerprint: str, stamp: Path, key: str) -> bool:
    """A finished map file from an interrupted build with the same settings and code (resume: its stamp,
    outside data/, holds ``key``); an unreadable one is not finished, so it is rebuilt rather than
    stopping the build."""
    if not stamp.is_file() or stamp.read_text() != key:
        return False
    try:
        with np.load(target, allow_pickle=False) as npz:
            return "fingerprint" in npz.files and str(npz["fingerprint"]) == fingerprint
    except (OSError, ValueError, zipfile.BadZipFile, EOFError):  # OSError covers a missing file
        return False
