"""A SuReNav test set from any OpenStreetMap extract, and the committed models evaluated on it (issue 60 item 4).

Why: the benchmark's test cities are three shipped extracts; a user who wants to know how the trained
context estimators do in *their* city gives an extract (``.osm``, ``.osm.pbf``, ``.osm.bz2``) and gets
the same Table I / Fig. 4 reports (``docs/your_city.md``). Nothing here is new method: every step is
the builder the shipped cities use, run on the user's tiles.

Test set (``build_test_set``), under ``<folder>/``:

- the extract rasterised as the ``maps`` step rasterises the shipped cities (``maps.osm.read_city``, at
  ``data.maps.resolution_m``; tags the extract lacks are warned about, ``osm.missing_tags``), with its walkable
  network;
- cut into ``data.maps.tile_size_m`` tiles (``maps.tiles.cut_tiles``; an extract smaller than one tile
  is one tile); the ``max_tiles`` tiles with the most sidewalk, each holding at least
  ``data.maps.min_sidewalk_fraction``, are the test tiles (the better-mapped part, as ``choose_test_tiles``
  prefers);
- per tile: its superpixel graph (``label_consistent_slic``), the context demonstrator's semi-static
  demonstrations (Table I's environments, ``context.environments.map_demonstrations``,
  ``surenav.demos.context.test_pairs_per_map`` of them) and the safety-efficiency episodes along OSRM
  routes (Fig. 4's, ``episodes.city_episodes``, ``surenav.benchmark.episodes.per_city`` of them).

Each tile's files carry a key over this code, the parameters and the extract's bytes: a re-run skips the
tiles already built and rebuilds a tile whose key changed. A tile whose walker finds too few pairs is
skipped and named in ``index.json`` (as ``surenav_context_demos`` does); none left is an error.

Evaluation (``evaluate``): Table I's methods (``context.benchmark.methods``: every trained estimator run,
the non-learned Psi, the best per-label field, the baselines with their priors from the context TRAINING
demonstrations) on the demonstrations, and Fig. 4's (``context.safety.fig4_methods``) on the episodes,
summarised by the shipped cities' own table builders. The models and priors are read from an artefacts
folder (``surenav_context_demos`` and ``surenav_context_estimator``); nothing is trained here.
"""

from __future__ import annotations

import hashlib
import json
import re
import warnings
from dataclasses import asdict, replace
from pathlib import Path
from typing import NamedTuple

import numpy as np
from tqdm.auto import tqdm

from navlab.core.fingerprint import code_fingerprint
from navlab.core.io import DataError, load_npz, save_npz, sha256_json, write_json
from navlab.core.params import Params
from navlab.core.seeding import rng
from navlab.graphs.superpixels import label_consistent_slic
from navlab.maps import osm
from navlab.maps.network import WalkableNetwork
from navlab.maps.osrm import OsrmRouter
from navlab.maps.semantic_map import SemanticMap
from navlab.maps.tiles import Tile, cut_tiles
from navlab.metrics.tables import Table
from navlab.surenav.context import benchmark as context_benchmark
from navlab.surenav.context import safety
from navlab.surenav.context.dataset import load_index as load_context_index
from navlab.surenav.context.environments import map_demonstrations
from navlab.surenav.episodes import CityEpisodes, Environment, city_episodes
from navlab.surenav.experts.store import _unpack, save_map_demos

INDEX = "index.json"
DEFAULT_MAX_TILES = 5  # as many test tiles as the shipped benchmark's human-likeness set
_FIX = "run `python -m navlab city run EXTRACT --name NAME` again (it rebuilds what is missing)"
_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")


def check_name(name: str) -> str:
    """A name usable as a folder and a tile prefix, else one line naming it and the fix."""
    if not _NAME.fullmatch(name):
        raise ValueError(f"--name {name!r}: use letters, digits, '_', '.' or '-' (it names the folder "
                         f"NAME/ under --out-dir and the tiles), starting with a letter or digit")
    return name


def extract_digest(path: str | Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def choose_tiles(name: str, smap: SemanticMap, network: WalkableNetwork, params: Params,
                 max_tiles: int) -> list[Tile]:
    """The test tiles: the ``max_tiles`` whole tiles with the most sidewalk among those with enough (the whole
    map as one tile when it is smaller than a tile), in name order; none is a DataError naming the fix."""
    p = params.data.maps
    tiles = cut_tiles(name, smap, network, p.tile_size_m)
    if not tiles:  # smaller than one tile: the whole extract is the tile
        tiles = [Tile(name, 0, 0, SemanticMap(f"{name}_r0c0", smap.labels, smap.frame), network)]
    fractions = sorted(round(t.sidewalk_fraction, 4) for t in tiles)
    eligible = sorted((t for t in tiles if t.sidewalk_fraction >= p.min_sidewalk_fraction),
                      key=lambda t: (-t.sidewalk_fraction, t.map.name))
    if not eligible:
        raise DataError(f"{name}: no tile has a sidewalk fraction >= data.maps.min_sidewalk_fraction = "
                        f"{p.min_sidewalk_fraction} (its tiles: {fractions}); give an extract where sidewalks or "
                        "footways are mapped, or lower data.maps.min_sidewalk_fraction in a params file (--params)")
    return sorted(eligible[:max_tiles], key=lambda t: t.map.name)


def _tile_key(params: Params, digest: str, tile: Tile) -> str:
    """What a tile's files depend on: this code, the parameters used, the extract's bytes and the tile."""
    s = params.surenav
    return sha256_json({"code": code_fingerprint(__name__), "maps": asdict(params.data.maps),
                        "demos": asdict(params.data.demos), "context": asdict(s.demos.context),
                        "graph": asdict(s.graph), "benchmark": asdict(s.benchmark), "extract": digest,
                        "tile": tile.map.name})


def _is_built(path: Path, key: str) -> bool:
    try:
        with np.load(path, allow_pickle=False) as npz:
            return "key" in npz.files and str(npz["key"]) == key
    except (OSError, ValueError, EOFError):
        return False


def build_tile(tile: Tile, city: str, params: Params, folder: Path, key: str) -> None:
    """One tile's map, network, superpixels, context demonstrations and safety-efficiency episodes."""
    s, smap = params.surenav, tile.map
    superpixels = label_consistent_slic(smap.labels, s.graph.target_nodes, s.graph.compactness)
    ctx = s.demos.context
    demos = map_demonstrations(smap, superpixels, ctx.test_pairs_per_map, params.data.demos,
                               rng(ctx.seed, "context demos", city, smap.name), s.graph)
    bench = s.benchmark
    margin = int(np.ceil(bench.executor.window_margin_m / smap.frame.resolution))
    with OsrmRouter(tile.network) as router:
        eps = city_episodes(smap, city, router, superpixels, bench.episodes, margin,
                            rng(bench.seed, "episodes", city, smap.name))
    smap.save(folder / f"{smap.name}.map.npz")
    tile.network.save(folder / f"{smap.name}.network.npz")
    save_map_demos(folder / f"{smap.name}.demos.npz", superpixels, [], demos, key)
    # written last, with the key: its presence with this key marks the tile complete
    arrays = {k: np.asarray(v) for k, v in asdict(eps).items()}
    save_npz(folder / f"{smap.name}.episodes.npz", {"key": np.array(key), **arrays})


def build_test_set(extract: str | Path, name: str, params: Params, folder: str | Path,
                   max_tiles: int = DEFAULT_MAX_TILES) -> dict:
    """The test set of ``extract`` under ``folder`` (module docstring); returns its index."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", osm.MissingTagsWarning)
        smap, network = osm.read_city(None, extract, params.data.maps.resolution_m)
    missing = [str(w.message) for w in caught if issubclass(w.category, osm.MissingTagsWarning)]
    for w in caught:  # shown to the user as well as recorded in the index
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    digest = extract_digest(extract)
    index = {"name": name, "extract": str(Path(extract).resolve()), "extract_sha256": digest,
             "resolution_m": params.data.maps.resolution_m, "missing_tags": missing, "tiles": [], "skipped": {}}
    for tile in tqdm(choose_tiles(name, smap, network, params, max_tiles), desc=f"{name}: tiles", unit="tile"):
        key = _tile_key(params, digest, tile)
        if not _is_built(folder / f"{tile.map.name}.episodes.npz", key):
            try:
                build_tile(tile, name, params, folder, key)
            except DataError as err:
                index["skipped"][tile.map.name] = str(err)
                continue
        index["tiles"].append(tile.map.name)
    if not index["tiles"]:
        raise DataError(f"{name}: no tile yields a test set ({'; '.join(index['skipped'].values())})")
    write_json(folder / INDEX, index)
    return index


class TestSet(NamedTuple):
    """A built test set: Table I's environments with each tile's superpixels, and Fig. 4's episodes."""
    demonstrations: list[Environment]
    superpixels: dict[str, np.ndarray]
    episodes: list[Environment]
    index: dict


def load_test_set(folder: str | Path) -> TestSet:
    """The test set ``build_test_set`` wrote (as ``context.dataset.stored_environments`` reads the shipped one)."""
    folder = Path(folder)
    if not (folder / INDEX).is_file():
        raise DataError(f"{folder / INDEX} is missing; {_FIX}")
    index = json.loads((folder / INDEX).read_text())
    demos, stored, episodes = [], {}, []
    for name in index["tiles"]:
        smap = SemanticMap.load(folder / f"{name}.map.npz")
        arrays = load_npz(folder / f"{name}.demos.npz", fix=_FIX)
        stored[name] = arrays["superpixels"]
        for i, demo in enumerate(_unpack(arrays, "semi_static")):
            demos.append(Environment(f"{name}/{i}", name, smap, demo.labels_on(smap.labels),
                                     smap.frame.world_to_cell(demo.start), smap.frame.world_to_cell(demo.goal),
                                     demo.persona, demo))
        e = load_npz(folder / f"{name}.episodes.npz", fix=_FIX)
        ce = CityEpisodes(str(e["city"]), str(e["map_name"]), e["starts"], e["goals"], e["personas"],
                          e["delta_cells"], e["delta_labels"])
        truth = ce.truth(smap.labels)
        for i, (s, g) in enumerate(zip(ce.starts, ce.goals, strict=True)):
            episodes.append(Environment(f"{name}/{i}", name, smap, truth, s, g, int(ce.personas[i])))
    return TestSet(demos, stored, episodes, index)


def _retitled(table: Table, name: str) -> Table:
    """The shipped table, titled and noted for the user's city (its id stays, so the report format is the same)."""
    return replace(table, paper_ref=f"{table.paper_ref}, on {name}",
                   notes=f"Evaluated on {name} (`python -m navlab city run`, docs/your_city.md): the shipped "
                         f"cities' sentences below about tiles and cities describe the committed benchmark, "
                         f"the rows are {name}'s. {table.notes}")


def evaluate(test_set: TestSet, params: Params, artifacts_dir: str | Path, name: str,
             progress: bool = True) -> tuple[Table, Table]:
    """(Table I, Fig. 4) of the committed models on ``test_set`` (module docstring)."""
    field = context_benchmark.best_field(params, artifacts_dir)
    runs, methods = context_benchmark.methods(params, artifacts_dir, field)
    outcomes = context_benchmark.run_all(test_set.demonstrations, test_set.superpixels, runs, params, progress)
    table1 = context_benchmark.table(outcomes, methods, params, load_context_index(artifacts_dir),
                                     context_benchmark.training_note(artifacts_dir, params), field)
    runs, methods = safety.fig4_methods(params, artifacts_dir)
    outcomes = context_benchmark.run_all(test_set.episodes, {}, runs, params, progress)
    fig4 = safety.fig4_table(outcomes, methods, test_set.episodes, params)
    return _retitled(table1, name), _retitled(fig4, name)
