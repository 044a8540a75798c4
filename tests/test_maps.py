"""navlab.maps: OSM rasteriser, walkable network, real tiles and the benchmark maps build."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.labels import constraint_mask, label_id
from navlab.maps import osm
from navlab.maps.network import edge_samples

WEST, SOUTH, EAST, NORTH = 24.0, 60.0, 24.004, 60.002
RES = 1.0


def _lonlat(x: float, y: float) -> tuple[float, float]:
    """Inverse of LocalProjection for the test box (x east, y south of the NW corner, metres)."""
    scale = np.cos(np.radians((SOUTH + NORTH) / 2))
    return (WEST + np.degrees(x / (osm.EARTH_RADIUS_M * scale)), NORTH - np.degrees(y / osm.EARTH_RADIUS_M))


def _osm_xml(ways: list[tuple[list[tuple[float, float]], dict[str, str]]], node_tags: dict[int, dict]) -> str:
    """An .osm document: every way's points become nodes (ids in order), closed rings reuse their first node."""
    nodes, way_xml, ids = [], [], {}
    for points, tags in ways:
        refs = []
        for xy in points:
            if xy not in ids:
                ids[xy] = len(ids) + 1
                lon, lat = _lonlat(*xy)
                extra = "".join(f'<tag k="{k}" v="{v}"/>' for k, v in node_tags.get(ids[xy], {}).items())
                nodes.append(f'<node id="{ids[xy]}" version="1" lat="{lat:.9f}" lon="{lon:.9f}">{extra}</node>')
            refs.append(ids[xy])
        body = "".join(f'<nd ref="{r}"/>' for r in refs) + "".join(f'<tag k="{k}" v="{v}"/>' for k, v in tags.items())
        way_xml.append(f'<way id="{len(way_xml) + 1}" version="1">{body}</way>')
    return '<?xml version="1.0"?><osm version="0.6">' + "".join(nodes) + "".join(way_xml) + "</osm>"


def _square(x0, y0, x1, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)]


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    ways = [
        (_square(20.0, 20.0, 60.0, 60.0), {"building": "yes"}),
        (_square(150.0, 20.0, 190.0, 60.0), {"building": "yes", "layer": "-1"}),
        (_square(150.0, 150.0, 210.0, 210.0), {"leisure": "park"}),
        ([(80.0, 80.0), (140.0, 80.0)], {"highway": "footway"}),
        ([(200.0, 20.0), (200.0, 120.0)], {"highway": "footway", "tunnel": "yes"}),
        ([(0.0, 130.0), (60.0, 130.0), (222.0, 130.0)], {"highway": "secondary", "lanes": "4", "sidewalk": "no"}),
        ([(0.0, 180.0), (140.0, 180.0)], {"highway": "residential", "lanes": "1", "sidewalk": "no"}),
        ([(110.0, 140.0), (110.0, 222.0)], {"highway": "residential"}),
        ([(40.0, 0.0), (40.0, 40.0), (40.0, 80.0), (80.0, 80.0)], {"highway": "footway"}),
    ]
    path = tmp_path_factory.mktemp("osm") / "tiny.osm"
    # the node at (60, 130) is the crossing: ids are assigned in order of first appearance
    points = [p for pts, _ in ways for p in pts]
    order = list(dict.fromkeys(points))
    crossing_id = order.index((60.0, 130.0)) + 1
    path.write_text(_osm_xml(ways, {crossing_id: {"highway": "crossing"}}))
    projection = osm.LocalProjection(WEST, SOUTH, EAST, NORTH)
    return osm.read_extract(path, projection, RES, "tiny")


def _at(smap, x, y):
    r, c = smap.frame.world_to_cell(np.array([x, y]))
    return int(smap.labels[r, c])


def test_projection_is_metric():
    proj = osm.LocalProjection(WEST, SOUTH, EAST, NORTH)
    width, height = proj.size_m
    assert width == pytest.approx(222.4, abs=0.5) and height == pytest.approx(222.4, abs=0.5)
    assert np.allclose(proj.project([_lonlat(123.0, 45.0)]), [[123.0, 45.0]], atol=1e-6)


def test_known_geometry_gives_known_cells(synthetic):
    smap, _ = synthetic
    assert _at(smap, 40, 30) == label_id("building")  # the building, away from the footway through it
    assert _at(smap, 170, 40) == label_id("rough_terrain")  # below-ground building dropped: open ground
    assert _at(smap, 180, 195) == label_id("grass")
    assert _at(smap, 110, 80) == label_id("sidewalk")  # footway
    assert _at(smap, 200, 90) == label_id("rough_terrain")  # tunnel footway dropped
    assert _at(smap, 60, 130) == label_id("crosswalk")  # crossing node on the 4-lane road
    assert _at(smap, 150, 130) == label_id("road")


def test_road_width_follows_lanes(synthetic):
    smap, _ = synthetic
    col = smap.frame.world_to_cell(np.array([30.0, 0.0]))[1]
    column = smap.labels[:, col]
    four_lanes = int(np.sum(column[110:150] == label_id("road")))
    one_lane = int(np.sum(column[170:190] == label_id("road")))
    assert abs(four_lanes - 12) <= 1 and abs(one_lane - 3) <= 1


def test_sidewalks_derived_along_untagged_roads(synthetic):
    smap, _ = synthetic
    row = smap.labels[smap.frame.world_to_cell(np.array([0.0, 205.0]))[0]]
    road = np.flatnonzero(row == label_id("road"))
    assert 5 <= road.size <= 7 and abs(road.mean() - 110) <= 1.5
    assert row[road.min() - 1] == label_id("sidewalk") and row[road.max() + 1] == label_id("sidewalk")
    tagged_no = smap.labels[smap.frame.world_to_cell(np.array([0.0, 180.0]))[0] - 3, 20]
    assert tagged_no != label_id("sidewalk")  # sidewalk=no: none beside the one-lane road


def test_network_obeys_drop_rules_and_hard_cells(synthetic):
    smap, network = synthetic
    assert np.linalg.norm(network.xy - [200.0, 70.0], axis=1).min() > 10  # no tunnel nodes
    points, _ = edge_samples(network.xy, network.edges, RES / 4)
    cells = smap.frame.world_to_cell(points)
    assert smap.frame.contains(cells).all()
    assert not constraint_mask(smap.labels[cells[:, 0], cells[:, 1]], "hard").any()
    # the footway through the building keeps only its parts outside the building
    on_footway = network.xy[np.abs(network.xy[:, 0] - 40.0) < 0.05]
    assert len(on_footway) and not ((on_footway[:, 1] > 20) & (on_footway[:, 1] < 60)).any()


def test_drop_rules():
    assert osm.dropped({"highway": "footway", "tunnel": "building_passage"})
    assert osm.dropped({"highway": "footway", "indoor": "yes"})
    assert osm.dropped({"highway": "footway", "covered": "yes"})
    assert osm.dropped({"building": "yes", "layer": "-2"})
    assert not osm.dropped({"highway": "footway", "layer": "1", "covered": "no"})


def test_unknown_city_names_the_choices(tmp_path):
    with pytest.raises(ValueError, match="helsinki, kouvola, monaco"):
        osm.load_city(tmp_path, "paris", 1.0)


def test_missing_extract_is_a_data_error(tmp_path):
    from navlab.core.io import DataError

    with pytest.raises(DataError, match="data build"):
        osm.load_city(tmp_path, "helsinki", 1.0)


def test_helsinki_has_plausible_proportions(smoke_data):
    smap = osm.load_city(smoke_data, "helsinki", 2.0)
    frac = np.bincount(smap.labels.ravel(), minlength=9) / smap.labels.size
    width_m = smap.labels.shape[1] * 2.0
    height_m = smap.labels.shape[0] * 2.0
    assert 900 < width_m < 1100 and 1550 < height_m < 1750  # ~1.0 x 1.65 km of central Helsinki
    assert 0.08 < frac[label_id("sidewalk")] < 0.35
    assert 0.002 < frac[label_id("crosswalk")] < 0.03
    assert 0.04 < frac[label_id("road")] < 0.2
    assert 0.15 < frac[label_id("building")] < 0.5
    assert 0.03 < frac[label_id("grass")] < 0.25
