"""Any city (issue 60 item 4): the OSM loaders take any extract, and a SuReNav test set is built and evaluated on
one the repository never shipped (tests/fixtures/West-Oakland.osm.bz2, see tests/fixtures/SOURCES.md).

Why: a new user's extract differs from the three shipped ones (no header box, crossings on traffic signals,
no buildings or sidewalks mapped); each of those used to crash, be ignored or give a silently emptier map.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import osmium
import pytest
from tests.test_maps import _lonlat, _osm_xml, _square

from navlab.core.labels import FREE_IDS, label_id
from navlab.maps import osm
from navlab.maps.network import WalkableNetwork

OAKLAND = Path("tests/fixtures/West-Oakland.osm.bz2")


def _write(path: Path, ways, node_tags=None) -> Path:
    path.write_text(_osm_xml(ways, node_tags or {}))
    return path


def _missing(path: Path) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        osm.read_city(None, path, 1.0)
    return [str(w.message) for w in caught if issubclass(w.category, osm.MissingTagsWarning)]


def test_a_city_loader_takes_any_extract_path():
    with pytest.warns(osm.MissingTagsWarning) as caught:
        smap, network = osm.read_city("unused", OAKLAND, 2.0)
    # West Oakland maps buildings and sidewalks but no crossing (its four traffic signals carry no crossing=*)
    expected = "no crossings mapped (no highway=crossing node, crossing=* traffic-signals node or footway=crossing way)"
    assert [str(w.message).split(": ")[1] for w in caught] == [expected]
    assert not (smap.labels == label_id("crosswalk")).any()
    assert smap.name == "West-Oakland"
    assert 300 < smap.labels.shape[1] * 2.0 < 450 and 250 < smap.labels.shape[0] * 2.0 < 400  # ~380 x 330 m
    for name in ("building", "sidewalk", "road"):
        assert (smap.labels == label_id(name)).mean() > 0.01, name
    assert len(network.xy) > 20 and len(network.edges) > 20
    assert osm.load_city("unused", str(OAKLAND), 2.0).labels.shape == smap.labels.shape


@pytest.mark.parametrize("city, message", [
    ("paris", r"unknown city 'paris': give one of helsinki, kouvola, monaco or the path of an OpenStreetMap extract"),
    ("nowhere/paris.osm.pbf", r"nowhere/paris.osm.pbf: no such extract file; check the path"),
    ("tests/fixtures/SOURCES.md", r"unknown city .*SOURCES.md.*\.osm\.bz2"),
])
def test_a_bad_city_is_one_line_naming_it_and_the_fix(city, message):
    with pytest.raises(ValueError, match=message) as err:
        osm.read_city("unused", city, 1.0)
    assert "\n" not in str(err.value)


def test_a_header_without_a_box_takes_the_nodes_extent(tmp_path):
    ways = [(_square(20.0, 20.0, 60.0, 60.0), {"building": "yes"}),
            ([(0.0, 100.0), (180.0, 100.0)], {"highway": "residential"})]
    path = _write(tmp_path / "nobox.osm", ways)  # _osm_xml writes no <bounds>
    reader = osmium.io.Reader(str(path), osmium.osm.osm_entity_bits.NOTHING)
    assert not reader.header().box().valid()
    reader.close()
    proj = osm.city_projection(path, path)
    west, north = _lonlat(0.0, 20.0)[0], _lonlat(0.0, 20.0)[1]
    assert proj.west == pytest.approx(west) and proj.north == pytest.approx(north)
    assert proj.size_m == pytest.approx((180.0, 80.0), abs=0.01)


def test_an_extract_without_nodes_names_the_file(tmp_path):
    path = tmp_path / "empty.osm"
    path.write_text('<?xml version="1.0"?><osm version="0.6"></osm>')
    with pytest.raises(ValueError, match=r"empty.osm: no node with a location"):
        osm.city_projection(path, path)


def test_a_crossing_tagged_on_traffic_signals_is_a_crosswalk(tmp_path):
    road = ([(0.0, 100.0), (50.0, 100.0), (100.0, 100.0), (150.0, 100.0), (200.0, 100.0)],
            {"highway": "residential", "sidewalk": "no"})
    tags = {2: {"highway": "traffic_signals", "crossing": "traffic_signals"},  # (50, 100)
            3: {"highway": "traffic_signals", "crossing": "no"},  # (100, 100): signals without a crossing
            4: {"highway": "crossing"}}  # (150, 100)
    blocks = [(_square(0.0, 0.0, 40.0, 40.0), {"building": "yes"}), (_square(0.0, 160.0, 40.0, 200.0), {"building": "yes"})]
    path = _write(tmp_path / "signals.osm", [road, *blocks], tags)  # no header box: the frame starts at (0, 0)
    smap, _ = osm.read_extract(path, osm.city_projection(path, path), 1.0, "signals")
    cw = label_id("crosswalk")

    def at(x, y):
        r, c = smap.frame.world_to_cell(np.array([x, y]))
        return int(smap.labels[r, c])
    assert smap.labels.shape in ((199, 199), (200, 200))  # the nodes' extent, floored to whole cells
    assert at(50.0, 99.5) == cw and at(150.0, 99.5) == cw
    assert at(100.0, 99.5) == label_id("road") and at(75.0, 99.5) == label_id("road")
    assert osm.is_crossing_node({"highway": "traffic_signals", "crossing": "uncontrolled"})
    assert not osm.is_crossing_node({"highway": "traffic_signals"})


def test_missing_buildings_sidewalks_and_crossings_are_each_named_with_their_fallback(tmp_path):
    bare = _write(tmp_path / "bare.osm", [([(0.0, 100.0), (180.0, 100.0)], {"highway": "residential"}),
                                          (_square(0.0, 0.0, 10.0, 10.0), {"leisure": "park"})])
    found = _missing(bare)
    assert len(found) == 3
    assert "bare (bare.osm): no buildings mapped: blocks are rasterised as rough_terrain" in found[0]
    assert "no sidewalks or footways mapped: sidewalks are derived on both sides" in found[1]
    assert "and there are none" not in found[1]
    assert "no crossings mapped" in found[2] and "no crosswalk cells" in found[2]
    service = _write(tmp_path / "service.osm", [([(0.0, 0.0), (180.0, 100.0)], {"highway": "service"})])
    assert any("and there are none, so the map has no sidewalk" in m for m in _missing(service))
    mapped = _write(tmp_path / "mapped.osm", [
        ([(0.0, 100.0), (90.0, 100.0), (180.0, 100.0)], {"highway": "residential", "sidewalk": "both"}),
        (_square(20.0, 20.0, 60.0, 60.0), {"building": "yes"})], {2: {"highway": "crossing"}})
    assert _missing(mapped) == []


@pytest.fixture(scope="module")
def oakland_run(tmp_path_factory):
    """The command's entry point on West Oakland (smoke profile), with smoke-size models trained here.

    The committed models are not in a test checkout, so the artefacts the evaluation reads are made the way
    their stages make them, only smaller: West Oakland's own demonstrations stand in as the context
    training and validation tiles (``surenav_context_demos``'s layout) and ``build_context_estimators`` trains
    every estimator run on them (smoke: 2 epochs). It tests the plumbing, not the models' quality."""
    from navlab.cli import run_city
    from navlab.core.params import load_params
    from navlab.surenav.any_city import build_test_set, load_test_set
    from navlab.surenav.context.dataset import FOLDER, relaxation_mix
    from navlab.surenav.context.training import build_context_estimators
    from navlab.surenav.experts.store import MapDemos

    params = load_params("smoke")
    root = tmp_path_factory.mktemp("oakland")
    out, art = root / "cities", root / "artifacts"
    build_test_set(OAKLAND, "oakland", params, out / "oakland" / "testset")
    test_set = load_test_set(out / "oakland" / "testset")
    name = test_set.index["tiles"][0]
    index = {"maps": {}, "skipped": {}, "mix": {}}
    for split in ("train", "val", "test"):
        folder = art.joinpath(*FOLDER, split)
        folder.mkdir(parents=True)
        for suffix in (".map.npz", ".demos.npz"):
            (folder / f"{name}{suffix.replace('.demos', '')}").write_bytes(
                (out / "oakland" / "testset" / f"{name}{suffix}").read_bytes())
        index["maps"][split] = [name]
        smap = test_set.demonstrations[0].prior
        md = MapDemos(name, split, test_set.superpixels[name], [], [e.demonstration for e in test_set.demonstrations])
        index["mix"][split] = relaxation_mix([(smap, md)])
    (art.joinpath(*FOLDER) / "index.json").write_text(__import__("json").dumps(index))
    build_context_estimators(params, None, art)
    written = run_city(OAKLAND, "oakland", params, art, out, progress=False)
    return params, out / "oakland", test_set, written


def test_the_test_set_is_on_the_extracts_streets(oakland_run):
    params, folder, test_set, _ = oakland_run
    index = json.loads((folder / "testset" / "index.json").read_text())
    assert index["tiles"] == ["oakland_r0c0"] and index["extract_sha256"].startswith("92efe9ed")
    assert len(index["missing_tags"]) == 1 and "no crossings mapped" in index["missing_tags"][0]
    smap = test_set.episodes[0].prior
    for name in ("building", "sidewalk", "road"):  # what West Oakland maps, in the raster
        assert (smap.labels == label_id(name)).any(), name
    assert len(test_set.demonstrations) == params.surenav.demos.context.test_pairs_per_map
    assert len(test_set.episodes) == params.surenav.benchmark.episodes.per_city
    network = WalkableNetwork.load(folder / "testset" / "oakland_r0c0.network.npz")
    free = np.isin(smap.labels, FREE_IDS)
    for env in test_set.episodes + test_set.demonstrations:
        for cell in (env.start, env.goal):
            assert free[tuple(cell)]  # on a sidewalk or crosswalk of the map
            # within a few cells of the walkable network (the OSRM episodes are routed on it)
            d = np.linalg.norm(network.xy - smap.frame.cell_to_world(cell), axis=1).min()
            assert d < 40.0
    assert any(len(e.truth.ravel()) and (e.truth != smap.labels).any() for e in test_set.episodes)  # perturbed


def test_the_reports_have_every_methods_row(oakland_run):
    from navlab.pipeline.reports import read_table
    from navlab.surenav.context.benchmark import SURENAV

    _, folder, _, written = oakland_run
    assert [p.name for p in written] == ["table1_human_likeness.json", "fig4_safety_efficiency.json",
                                         "fig4_safety_efficiency.png"]
    assert all(p.is_file() and p.parent.is_relative_to(folder / "reports" / "surenav") for p in written)
    table1, fig4 = read_table(written[0]), read_table(written[1])
    methods = {r["method"] for r in table1["rows"]}
    assert {SURENAV, "D* Lite", "COA*", "RCR", "Expert (context demonstrator's planner)"} <= methods
    assert all(r["environments"] == 2 and r["frechet"] is not None for r in table1["rows"])
    assert {r["city"] for r in fig4["rows"]} == {"oakland_r0c0"}
    assert {SURENAV, "D* Lite", "COA*", "RCR"} <= {r["method"] for r in fig4["rows"]}
    assert "on oakland" in table1["paper_ref"] and (folder / "reports" / "surenav" / "table1_human_likeness.md").is_file()


def test_the_command_refuses_a_bad_extract_in_one_line(capsys):
    from navlab.cli import main

    assert main(["city", "run", "nowhere.osm.pbf", "--name", "x"]) == 2
    assert capsys.readouterr().err.strip() == ("error: nowhere.osm.pbf: no such extract file; check the path (an "
                                               "OpenStreetMap extract, .osm, .osm.pbf, .pbf, .osm.bz2, .osm.gz)")
    assert main(["city", "run", str(OAKLAND), "--name", "../x"]) == 2
    assert "--name '../x'" in capsys.readouterr().err
