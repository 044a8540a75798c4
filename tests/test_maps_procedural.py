"""navlab.maps.procedural, routing and the `maps` data step."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from navlab.core.io import DataError
from navlab.core.labels import constraint_mask, label_id
from navlab.maps import dataset
from navlab.maps.network import edge_samples, network_from_raster
from navlab.maps.procedural import generate, street_regularity
from navlab.maps.routing import Router


@pytest.fixture(scope="module")
def proc(smoke_params):
    return dataclasses.replace(smoke_params.data.maps.procedural, tile_size_m=240.0)


def test_same_seed_same_map_other_name_other_map(proc):
    a = generate(0, "m", 0.5, proc, 2.0)
    assert np.array_equal(a.labels, generate(0, "m", 0.5, proc, 2.0).labels)
    assert not np.array_equal(a.labels, generate(0, "n", 0.5, proc, 2.0).labels)
    assert not np.array_equal(a.labels, generate(1, "m", 0.5, proc, 2.0).labels)


def test_structure_knob_changes_street_regularity(proc):
    def mean_regularity(structure):
        return np.mean([street_regularity(generate(0, f"k{i}", structure, proc, 2.0).labels) for i in range(3)])

    grid, mixed, medieval = mean_regularity(1.0), mean_regularity(0.5), mean_regularity(0.0)
    assert grid > 0.8 and medieval < 0.4 and grid > mixed > medieval


def test_procedural_map_has_every_street_ingredient(proc):
    labels = generate(0, "ingredients", 1.0, proc, 1.0).labels
    frac = np.bincount(labels.ravel(), minlength=9) / labels.size
    for name in ("sidewalk", "crosswalk", "road", "building", "grass"):
        assert frac[label_id(name)] > 0.005, name
    # sidewalks on both sides: every road cell is within a road width of a sidewalk cell
    assert 0.1 < frac[label_id("sidewalk")] < 0.4 and 0.05 < frac[label_id("road")] < 0.3


def test_structure_out_of_range_is_refused(proc):
    with pytest.raises(ValueError, match="structure"):
        generate(0, "bad", 1.5, proc, 2.0)


def _route_cells(smap, route):
    points, _ = edge_samples(route.xy, np.stack([np.arange(len(route.xy) - 1), np.arange(1, len(route.xy))], 1),
                             smap.frame.resolution / 4)
    return smap.frame.world_to_cell(points)


def _random_routes(smap, network, seed, count=8):
    router = Router(network)
    main = router.components()[0]
    pick = np.random.default_rng(seed).choice(main, size=(count, 2))
    routes = [router.route(network.xy[a], network.xy[b]) for a, b in pick]
    assert all(r is not None for r in routes)
    return routes


def test_routes_on_procedural_map_stay_on_sidewalks_and_crosswalks(proc):
    smap = generate(0, "routing", 0.3, proc, 1.0)
    network = network_from_raster(smap)
    for route in _random_routes(smap, network, 0):
        cells = _route_cells(smap, route)
        labels = smap.labels[cells[:, 0], cells[:, 1]]
        assert np.isin(labels, [label_id("sidewalk"), label_id("crosswalk")]).all()
        assert route.length_m >= np.linalg.norm(route.xy[-1] - route.xy[0]) - 1e-9


def test_router_matches_networkx_free_reference(proc):
    """Dijkstra's length equals a Bellman-Ford relaxation over the same edges (scipy's csgraph)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import shortest_path

    smap = generate(0, "reference", 0.6, proc, 2.0)
    network = network_from_raster(smap)
    n = len(network.xy)
    w = network.lengths
    graph = coo_matrix((np.r_[w, w], (np.r_[network.edges[:, 0], network.edges[:, 1]],
                                      np.r_[network.edges[:, 1], network.edges[:, 0]])), shape=(n, n)).tocsr()
    router = Router(network)
    main = router.components()[0]
    a, b = main[0], main[-1]
    ref = shortest_path(graph, method="BF", indices=[a])[0, b]
    assert router.route(network.xy[a], network.xy[b]).length_m == pytest.approx(ref)


def test_maps_step_outputs_and_routes_on_real_test_tiles(smoke_data, smoke_params):
    index = dataset.load_index(smoke_data)
    test = [e for e in index if e["split"] == "test"]
    assert len(test) == 5 and {e["source"] for e in test} == {"helsinki", "monaco", "kouvola"}
    roles = [e["role"] for e in test]
    assert sorted(roles[:3]) == ["baltimore", "capitol_hill", "milan"] and roles[3:] == ["human_likeness"] * 2
    p = smoke_params.data.maps
    assert len(dataset.load_maps(smoke_data, "train")) == p.train_maps
    assert len(dataset.load_maps(smoke_data, "val")) == p.val_maps
    for entry, smap in zip(test, dataset.load_maps(smoke_data, "test"), strict=True):
        assert np.mean(smap.labels == label_id("sidewalk")) >= p.min_sidewalk_fraction
        network = dataset.load_network(smoke_data, "test", entry["name"])
        for route in _random_routes(smap, network, 1, count=4):
            cells = _route_cells(smap, route)
            assert smap.frame.contains(cells).all()
            assert not constraint_mask(smap.labels[cells[:, 0], cells[:, 1]], "hard").any()


def _fake_tiles():
    from navlab.core.grid import RasterFrame
    from navlab.maps.network import WalkableNetwork
    from navlab.maps.semantic_map import SemanticMap
    from navlab.maps.tiles import Tile

    gen = np.random.default_rng(0)
    tiles = []
    for city in ("helsinki", "kouvola", "monaco"):
        for k in range(6):
            labels = np.where(gen.random((20, 20)) < gen.uniform(0, 0.3), label_id("sidewalk"), label_id("road"))
            smap = SemanticMap(f"{city}_{k}", labels.astype(np.uint8), RasterFrame((20, 20), 1.0))
            tiles.append(Tile(city, 0, k, smap, WalkableNetwork(np.zeros((0, 2)), np.zeros((0, 2), np.int64))))
    return tiles


def test_test_split_is_seeded_and_takes_well_mapped_tiles():
    from navlab.maps.tiles import choose_test_tiles

    tiles = _fake_tiles()
    names = [[t.map.name for t, _ in choose_test_tiles(tiles, 0.05, 2, seed)] for seed in range(6)]
    again = [[t.map.name for t, _ in choose_test_tiles(tiles, 0.05, 2, seed)] for seed in range(6)]
    assert names == again and len({tuple(n) for n in names}) > 1
    for seed in range(6):
        chosen = choose_test_tiles(tiles, 0.05, 2, seed)
        assert len({t.map.name for t, _ in chosen}) == 5
        for tile, role in chosen[:3]:
            same_city = [t.sidewalk_fraction for t in tiles if t.city == tile.city]
            assert tile.sidewalk_fraction >= max(np.median(same_city), 0.05)
            assert role == {"helsinki": "baltimore", "monaco": "milan", "kouvola": "capitol_hill"}[tile.city]
        assert all(t.sidewalk_fraction >= 0.05 and r == "human_likeness" for t, r in chosen[3:])


def test_missing_maps_raise_data_error(tmp_path):
    with pytest.raises(DataError, match="data build"):
        dataset.load_maps(tmp_path, "train")
    with pytest.raises(ValueError, match="train, val, test"):
        dataset.load_maps(tmp_path, "holdout")
