"""The benchmark's environments (SuReNav Sec. VI-A): the safety-efficiency set and the human-likeness set.

Safety-efficiency: per test city, start-goal pairs on sidewalks 30-200 m apart; for each pair OSRM
(``maps.osrm``, the paper's router) routes a foot path, and up to ``max_seeds`` superpixels along it are
perturbed (``maps.perturb``: a new obstacle or an obfuscated prior). All changes are aggregated into
one modified map per city, "to increase disruption likelihood"; every method plans on the original
map and navigates in the modified one. Pairs are taken one by one with their change; a pair is kept
when its start and goal are connected through non-hard ground inside its episode window on the
original map (every method has a first plan), and its change leaves every kept pair's start and goal
untouched and connected on the modified map (success stays possible); otherwise the pair and its
change are dropped.

Human-likeness: the 100 semi-static test environments with their demonstrations (``experts``).

The safety-efficiency set is the `surenav_episodes` artefact (``artifacts/surenav/episodes/``), one
``.npz`` per city keyed on the generating code, the parameters and the map.
"""

from __future__ import annotations

import hashlib
import inspect
import json
import sys
import zipfile
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
from scipy import ndimage
from tqdm import tqdm

from navlab.core.io import DataError, load_npz, save_npz, sha256_json, write_json
from navlab.core.labels import FREE_IDS, HARD_IDS
from navlab.core.params import Params
from navlab.core.params.surenav_benchmark import EpisodeParams
from navlab.core.seeding import rng
from navlab.graphs.projection import trace_cells
from navlab.graphs.superpixels import label_consistent_slic
from navlab.maps.dataset import load_index, load_maps, load_network
from navlab.maps.osrm import OsrmRouter
from navlab.maps.perturb import obstruct_route
from navlab.maps.queries import sample_pairs
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.experts.personas import PERSONAS
from navlab.surenav.experts.store import Demonstration, load_demos

EPISODES_DIR = Path("surenav", "episodes")
CITIES = ("milan", "baltimore", "capitol_hill")  # index.json roles of the three test tiles (Fig. 4)
CANDIDATES_PER_PAIR = 6  # pairs drawn per pair kept (some have no route, or their change would cut a goal off)
_EIGHT = np.ones((3, 3), dtype=bool)


@dataclass(frozen=True)
class CityEpisodes:
    city: str  # the paper's city this tile stands in for
    map_name: str
    starts: np.ndarray  # (n, 2) int64 cells
    goals: np.ndarray  # (n, 2) int64 cells
    personas: np.ndarray  # (n,) the Expert reference row's persona per episode
    delta_cells: np.ndarray  # flat indices of every perturbed cell of the city's modified map
    delta_labels: np.ndarray  # their labels on the modified map

    def truth(self, labels: np.ndarray) -> np.ndarray:
        """The modified map the walkers navigate in."""
        out = labels.copy()
        out.ravel()[self.delta_cells] = self.delta_labels
        return out


@dataclass(frozen=True)
class Environment:
    """One episode of either set, in full-map cells: plan on ``prior``, navigate in ``truth``."""
    name: str  # "<city or map>/<index>"
    group: str  # the city (safety-efficiency) or the test map (human-likeness)
    prior: SemanticMap
    truth: np.ndarray
    start: np.ndarray  # (2,) int64 cell
    goal: np.ndarray  # (2,) int64 cell
    persona: int
    demonstration: Demonstration | None = None  # human-likeness only


def window(shape, start, goal, margin_cells: int) -> tuple[slice, slice]:
    """The episode's box: start and goal grown by ``margin_cells``, clipped to the map."""
    lo = np.maximum(np.minimum(start, goal) - margin_cells, 0)
    hi = np.minimum(np.maximum(start, goal) + margin_cells + 1, shape)
    return slice(int(lo[0]), int(hi[0])), slice(int(lo[1]), int(hi[1]))


def connected(labels: np.ndarray, start, goal, box: tuple[slice, slice]) -> bool:
    """Start and goal joined by 8-connected non-hard cells inside ``box``."""
    parts, _ = ndimage.label(~np.isin(labels[box], HARD_IDS), structure=_EIGHT)
    off = np.array([box[0].start, box[1].start])
    a, b = parts[tuple(np.asarray(start) - off)], parts[tuple(np.asarray(goal) - off)]
    return bool(a > 0 and a == b)


def _keeps_pairs(labels: np.ndarray, change: np.ndarray, pairs) -> bool:
    """No pair's start or goal is changed and every pair whose window the change touches stays connected."""
    rows, cols = np.nonzero(change)
    for start, goal, box in pairs:
        if change[tuple(start)] or change[tuple(goal)]:
            return False
        touched = ((rows >= box[0].start) & (rows < box[0].stop) & (cols >= box[1].start) & (cols < box[1].stop)).any()
        if touched and not connected(labels, start, goal, box):
            return False
    return True


def city_episodes(smap: SemanticMap, city: str, router: OsrmRouter, superpixels: np.ndarray,
                  settings: EpisodeParams, margin_cells: int, generator: np.random.Generator) -> CityEpisodes:
    """The safety-efficiency episodes of one test city (see the module docstring)."""
    frame, res = smap.frame, smap.frame.resolution
    clearance = int(np.ceil(settings.endpoint_clearance_m / res))
    try:
        candidates = sample_pairs(smap, FREE_IDS, CANDIDATES_PER_PAIR * settings.per_city, settings.min_distance_m,
                                  settings.max_distance_m, generator)
    except ValueError as err:
        raise DataError(f"{err} (surenav.benchmark.episodes in params.yaml)") from None
    labels = smap.labels.copy()
    changed = np.zeros(labels.shape, dtype=bool)
    kept: list[tuple[np.ndarray, np.ndarray, tuple[slice, slice]]] = []
    for start, goal in candidates:
        box = window(labels.shape, start, goal, margin_cells)
        if changed[tuple(start)] or changed[tuple(goal)] or not connected(smap.labels, start, goal, box):
            continue
        route = router.route(frame.cell_to_world(start), frame.cell_to_world(goal))
        if route is None:
            continue
        points = np.concatenate([frame.cell_to_world(start)[None], route.xy, frame.cell_to_world(goal)[None]])
        cells = trace_cells(points, frame)
        cells = cells[frame.contains(cells)]
        if len(cells) < 2:
            continue
        change = obstruct_route(labels, superpixels, cells, int(generator.integers(1, settings.max_seeds + 1)),
                                generator, obstacle_probability=settings.obstacle_probability,
                                clearance_cells=clearance)
        if not change.changed.any() or not _keeps_pairs(change.labels, change.changed, [*kept, (start, goal, box)]):
            continue  # the change would cut an episode (this one or an earlier one) off its goal: drop the pair
        labels, changed = change.labels, changed | change.changed
        kept.append((start, goal, box))
        if len(kept) == settings.per_city:
            break
    if len(kept) < settings.per_city:
        raise DataError(f"{smap.name} ({city}): only {len(kept)} of {settings.per_city} start-goal pairs keep a "
                        "perturbed route and a reachable goal; lower surenav.benchmark.episodes.per_city or max_seeds")
    kept = [(s, g) for s, g, _ in kept]
    pairs = np.asarray(kept, dtype=np.int64)
    cells = np.flatnonzero(changed)
    return CityEpisodes(city, smap.name, pairs[:, 0], pairs[:, 1],
                        generator.integers(len(PERSONAS), size=len(pairs)).astype(np.int64),
                        cells.astype(np.int64), labels.ravel()[cells].astype(np.uint8))


def _source_digest() -> str:
    """sha256 of the navlab sources that decide the episodes: a changed generator makes new episodes."""
    modules = ["navlab.surenav.episodes", "navlab.maps.perturb", "navlab.maps.osrm", "navlab.maps.queries",
               "navlab.graphs.superpixels", "navlab.graphs.projection", "navlab.core.seeding"]
    return hashlib.sha256("".join(inspect.getsource(sys.modules[m]) for m in modules).encode()).hexdigest()


def _test_city_maps(data_dir: Path) -> list[tuple[str, SemanticMap]]:
    roles = {e["name"]: e["role"] for e in load_index(data_dir) if e["split"] == "test"}
    maps = {m.name: m for m in load_maps(data_dir, "test")}
    out = [(roles[name], maps[name]) for name in maps if roles[name] in CITIES]
    missing = sorted(set(CITIES) - {city for city, _ in out})
    if missing:
        raise DataError(f"{data_dir}: no test tile for {missing}; rebuild the dataset (`python -m navlab data build`)")
    return sorted(out, key=lambda item: CITIES.index(item[0]))


def build_episodes(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
    """Artefact step `surenav_episodes`: one file per test city; a file whose key matches is kept."""
    bench, graph = params.surenav.benchmark, params.surenav.graph
    folder = Path(artifacts_dir, EPISODES_DIR)
    index = {}
    for city, smap in tqdm(_test_city_maps(Path(data_dir)), desc="episodes", unit="city"):
        target = folder / f"{city}.npz"
        key = sha256_json({"code": _source_digest(), "episodes": asdict(bench.episodes), "seed": bench.seed,
                           "margin": bench.executor.window_margin_m, "graph": asdict(graph), "map": smap.name,
                           "labels": hashlib.sha256(smap.labels.tobytes()).hexdigest()})
        if not _is_built(target, key):
            superpixels = label_consistent_slic(smap.labels, graph.target_nodes, graph.compactness)
            margin = int(np.ceil(bench.executor.window_margin_m / smap.frame.resolution))
            with OsrmRouter(load_network(data_dir, "test", smap.name)) as router:
                eps = city_episodes(smap, city, router, superpixels, bench.episodes, margin,
                                    rng(bench.seed, "episodes", city, smap.name))
            save_npz(target, {"key": np.array(key), **{k: np.asarray(v) for k, v in asdict(eps).items()}})
        index[city] = smap.name
    write_json(folder / "index.json", index)


def _is_built(target: Path, key: str) -> bool:
    try:
        with np.load(target, allow_pickle=False) as npz:
            return "key" in npz.files and str(npz["key"]) == key
    except (OSError, ValueError, zipfile.BadZipFile, EOFError):
        return False


def load_city_episodes(artifacts_dir: str | Path) -> list[CityEpisodes]:
    """The safety-efficiency episodes, city by city in the paper's order."""
    folder = Path(artifacts_dir, EPISODES_DIR)
    fix = "build them with `python -m navlab artifacts build --only surenav_episodes`"
    if not (folder / "index.json").is_file():
        raise DataError(f"{folder}: no episodes; {fix}")
    index = json.loads((folder / "index.json").read_text())
    out = []
    for city in CITIES:
        arrays = load_npz(folder / f"{city}.npz", fix=fix)
        out.append(CityEpisodes(str(arrays["city"]), str(arrays["map_name"]), arrays["starts"], arrays["goals"],
                                arrays["personas"], arrays["delta_cells"], arrays["delta_labels"]))
        if out[-1].map_name != index[city]:
            raise DataError(f"{folder}/{city}.npz is stale (map {out[-1].map_name}, index {index[city]}); {fix}")
    return out


def safety_efficiency_environments(data_dir: str | Path, artifacts_dir: str | Path) -> list[Environment]:
    """Every safety-efficiency episode as an Environment (prior = the test tile, truth = its modified map)."""
    maps = {m.name: m for m in load_maps(data_dir, "test")}
    out = []
    for ce in load_city_episodes(artifacts_dir):
        smap = maps[ce.map_name]
        truth = ce.truth(smap.labels)
        for i, (s, g) in enumerate(zip(ce.starts, ce.goals, strict=True)):
            out.append(Environment(f"{ce.city}/{i}", ce.city, smap, truth, s, g, int(ce.personas[i])))
    return out


def human_likeness_environments(data_dir: str | Path) -> list[Environment]:
    """The semi-static test environments with their demonstrations (prior = the test map, truth = the
    map the demonstration was drawn on)."""
    maps = {m.name: m for m in load_maps(data_dir, "test")}
    out = []
    for md in load_demos(data_dir, "test"):
        smap = maps[md.map_name]
        for i, demo in enumerate(md.semi_static):
            start, goal = smap.frame.world_to_cell(demo.start), smap.frame.world_to_cell(demo.goal)
            out.append(Environment(f"{md.map_name}/{i}", md.map_name, smap, demo.labels_on(smap.labels),
                                   start, goal, demo.persona, demo))
    return out
