"""Any city (issue 60 item 4): the OSM loaders take any extract, and a SuReNav test set is built and evaluated on
one the repository never shipped (tests/fixtures/West-Oakland.osm.bz2, see tests/fixtures/SOURCES.md).

Why: a new user's extract differs from the three shipped ones (no header box, crossings on traffic signals,
no buildings or sidewalks mapped); each of those used to crash, be ignored or give a silently emptier map.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import osmium
import pytest

from navlab.core.labels import label_id
from navlab.maps import osm
from tests.test_maps import _lonlat, _osm_xml, _square

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
    assert [str(w.message).split(": ")[1] for w in caught] == ["no crossings mapped (no highway=crossing node, "
                                                               "crossing=* traffic-signals node or footway=crossing way)"]
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
    service = _write(tmp_path / "service.osm", [([(0.0, 100.0), (180.0, 100.0)], {"highway": "service"})])
    assert any("and there are none, so the map has no sidewalk" in m for m in _missing(service))
    mapped = _write(tmp_path / "mapped.osm", [
        ([(0.0, 100.0), (90.0, 100.0), (180.0, 100.0)], {"highway": "residential", "sidewalk": "both"}),
        (_square(20.0, 20.0, 60.0, 60.0), {"building": "yes"})], {2: {"highway": "crossing"}})
    assert _missing(mapped) == []
