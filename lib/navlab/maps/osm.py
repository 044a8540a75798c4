"""OpenStreetMap extracts -> semantic rasters and walkable networks (SuReNav Sec. VI-A).

The paper converts OSM tiles into bird's-eye semantic maps with MIA; we rasterise the tags directly.

Frame: an equirectangular projection about the centre of the city's box (``LocalProjection``): metres
east (x) and south (y, so rows grow with y as in ``core.grid``) of the box's north-west corner. Over
a few kilometres its scale error is below 0.1 %, far under one cell.

What each label comes from, painted in this order (later wins, so hard regions and roads come out on top):

1. untagged open ground -> ``rough_terrain``: its surface is unknown (yards, verges, wasteland), so it
   is soft and the last thing a planner should relax, never free;
2. the sea, from ``natural=coastline`` (sea lies right of the way's direction, OSM's convention);
3. grass (parks, gardens, pitches, lawns, meadows) and rough terrain (scrub, wood, beach, construction),
   larger areas first so that a scrub patch inside a park stays visible;
4. water areas and rivers/canals/streams;
5. parking areas (surface parking only);
6. sidewalks: sidewalks along roads from their ``sidewalk=*`` tags, *derived on both sides of
   primary..residential roads that carry no sidewalk tag* (Kouvola maps almost no footways; a road
   tagged ``sidewalk=no|separate`` gets none), pedestrian areas and squares, piers, and every
   footway/path/pedestrian street/steps/shared cycleway/track line;
7. roads, buffered by their ``width`` tag, else ``lanes`` x 3 m, else a width per highway class;
   living streets get their own label; bridges win over water here;
8. crosswalks, on road cells only: ``footway=crossing`` ways and a stripe across the road at every
   ``highway=crossing`` node, and at every ``highway=traffic_signals`` node tagged ``crossing=*`` (not
   ``no``): the older combined tagging of a signalled crossing, common in North American extracts;
9. buildings.

Any extract, not only the three shipped cities: ``read_city`` / ``load_city`` take a shipped city's name
or the path of an ``.osm`` / ``.osm.pbf`` / ``.osm.bz2`` / ``.osm.gz`` file; a header without a bounding
box takes the nodes' extent. Tags a user's extract may lack do not fail silently: an extract without
buildings, without any sidewalk or footway, or without crossings gets one warning each
(``MissingTagsWarning``) naming the fallback the raster then uses.

Dropped everywhere, raster and network alike: indoor, tunnel (incl. building passages), covered and
below-ground (``layer<0``, ``location=underground``) features, so no route passes under a building.
"""

from __future__ import annotations

import math
import re
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import cv2
import numpy as np
import osmium

from navlab.core.grid import RasterFrame
from navlab.core.io import require
from navlab.core.labels import label_id
from navlab.maps.draw import fill, stroke
from navlab.maps.network import WalkableNetwork, restrict_to_map
from navlab.maps.semantic_map import SemanticMap

CITIES = ("helsinki", "kouvola", "monaco")
# (west, south, east, north) in degrees; None: the extract's own header box. Monaco's extract holds its
# French hinterland and kilometres of open sea, so we keep the principality and its harbours.
CITY_BOXES: dict[str, tuple[float, float, float, float] | None] = {
    "helsinki": None,
    "kouvola": None,
    "monaco": (7.405, 43.722, 7.442, 43.753),
}
EARTH_RADIUS_M = 6_371_008.8

LANE_WIDTH_M = 3.0
SIDEWALK_WIDTH_M = 2.0
CROSSWALK_WIDTH_M = 3.0
ROAD_WIDTH_M = {
    "motorway": 14.0, "trunk": 12.0, "primary": 10.0, "secondary": 9.0, "tertiary": 8.0,
    "unclassified": 6.0, "residential": 6.0, "service": 4.0, "road": 6.0, "busway": 6.0,
    "motorway_link": 6.0, "trunk_link": 6.0, "primary_link": 6.0, "secondary_link": 6.0, "tertiary_link": 6.0,
    "living_street": 5.0,
}
PATH_WIDTH_M = {
    "footway": 2.0, "path": 1.5, "pedestrian": 5.0, "steps": 2.0, "cycleway": 2.5, "bridleway": 2.0,
    "track": 3.0, "platform": 3.0,
}
WATERWAY_WIDTH_M = {"river": 12.0, "canal": 8.0, "stream": 2.0}
PIER_WIDTH_M = 3.0
SIDEWALK_DERIVED_ON = {"primary", "secondary", "tertiary", "unclassified", "residential"}
NO_FOOT_ROADS = {"motorway", "motorway_link", "trunk", "trunk_link"}

GRASS = {
    "landuse": {"grass", "meadow", "village_green", "recreation_ground", "cemetery", "allotments", "flowerbed"},
    "leisure": {"park", "garden", "pitch", "playground", "dog_park", "common", "golf_course"},
    "natural": {"grassland"},
}
ROUGH = {
    "landuse": {"forest", "construction", "brownfield", "greenfield", "farmland", "quarry", "orchard", "vineyard"},
    "natural": {"scrub", "wood", "heath", "sand", "beach", "bare_rock", "scree", "shingle", "wetland"},
}
WATER = {
    "natural": {"water", "bay"}, "waterway": {"riverbank", "dock"}, "landuse": {"basin", "reservoir"},
    "leisure": {"swimming_pool"}, "amenity": {"fountain"},
}
EXTRACT_SUFFIXES = (".osm", ".osm.pbf", ".pbf", ".osm.bz2", ".osm.gz")  # what osmium reads by name
KEYS = ("highway", "building", "natural", "landuse", "leisure", "amenity", "waterway", "man_made", "place",
        "public_transport")


@dataclass(frozen=True)
class LocalProjection:
    """Equirectangular metres about the box centre; origin at the box's north-west corner, y south."""

    west: float
    south: float
    east: float
    north: float

    def project(self, lonlat: np.ndarray) -> np.ndarray:
        lonlat = np.asarray(lonlat, dtype=np.float64).reshape(-1, 2)
        # math.cos (libm) rather than np.cos: numpy may take a SIMD (SVML) cosine a few ulp off on some
        # CPUs, and these metres are stored in the network files that data.dvc pins
        scale = math.cos(math.radians((self.south + self.north) / 2))
        x = EARTH_RADIUS_M * scale * np.radians(lonlat[:, 0] - self.west)
        y = EARTH_RADIUS_M * np.radians(self.north - lonlat[:, 1])
        return np.stack([x, y], axis=1)

    @property
    def size_m(self) -> tuple[float, float]:
        """(width, height) of the box in metres."""
        corner = self.project(np.array([[self.east, self.south]]))[0]
        return float(corner[0]), float(corner[1])


@dataclass
class OsmFeatures:
    """What the rasteriser and the network need from one extract, already projected and filtered."""

    lines: list[tuple[dict[str, str], np.ndarray, np.ndarray]] = field(default_factory=list)  # tags, xy, node ids
    areas: list[tuple[dict[str, str], list[np.ndarray]]] = field(default_factory=list)  # tags, rings
    crossings: dict[int, np.ndarray] = field(default_factory=dict)  # node id -> xy


def _number(text: str | None) -> float | None:
    match = re.match(r"\s*(-?\d+(?:\.\d+)?)", text or "")
    return float(match.group(1)) if match else None


def dropped(tags: dict[str, str]) -> bool:
    """Indoor, tunnel, covered or below-ground: not part of the open-air map."""
    if tags.get("highway") == "corridor" or tags.get("location") in ("underground", "indoor"):
        return True
    if any(tags.get(key, "no") != "no" for key in ("indoor", "tunnel", "covered")):
        return True
    return (_number(tags.get("layer")) or 0) < 0


def area_label(tags: dict[str, str]) -> str | None:
    """The label an OSM area paints, or None for areas the map ignores."""
    if tags.get("building", "no") not in ("no", "roof"):
        return "building"
    if any(tags.get(k) in v for k, v in WATER.items()):
        return "water"
    if tags.get("amenity") == "parking" and tags.get("parking") not in ("underground", "multi-storey", "rooftop"):
        return "parking"
    if ((tags.get("highway") in ("pedestrian", "footway", "platform") and tags.get("area") == "yes")
            or tags.get("place") == "square" or tags.get("man_made") == "pier"
            or tags.get("public_transport") == "platform"):
        return "sidewalk"
    if any(tags.get(k) in v for k, v in GRASS.items()):
        return "grass"
    if any(tags.get(k) in v for k, v in ROUGH.items()):
        return "rough_terrain"
    return None


def line_kind(tags: dict[str, str]) -> str | None:
    """road | living_street | path | crossing | waterway | coastline | pier, or None."""
    highway = tags.get("highway")
    if highway == "living_street":
        return "living_street"
    if highway in ROAD_WIDTH_M:
        return "road"
    if highway in PATH_WIDTH_M:
        if highway == "cycleway" and tags.get("foot") == "no":
            return None
        crossing = "crossing" in (tags.get("footway"), tags.get("cycleway"), tags.get("path"))
        return "crossing" if crossing else "path"
    if tags.get("waterway") in WATERWAY_WIDTH_M:
        return "waterway"
    if tags.get("natural") == "coastline":
        return "coastline"
    if tags.get("man_made") == "pier":
        return "pier"
    return None


def walkable(tags: dict[str, str]) -> bool:
    """Whether a pedestrian may use a line (OSRM foot.lua's rule, reduced to the tags we keep)."""
    kind = line_kind(tags)
    if kind in ("path", "crossing", "living_street", "pier"):
        return tags.get("foot") != "no"
    if kind == "road":
        if tags.get("foot") in ("yes", "designated"):
            return True
        return (tags.get("highway") not in NO_FOOT_ROADS and tags.get("foot") != "no"
                and tags.get("access") not in ("no", "private"))
    return False


def road_width(tags: dict[str, str]) -> float:
    """Carriageway width: the ``width`` tag, else lanes x 3 m, else the class default."""
    width = _number(tags.get("width"))
    if width and width > 0:
        return width
    lanes = _number(tags.get("lanes"))
    if lanes and lanes > 0:
        return lanes * LANE_WIDTH_M
    return ROAD_WIDTH_M[tags["highway"]]


def sidewalk_sides(tags: dict[str, str]) -> tuple[bool, bool]:
    """(left, right): tagged sides, or both sides derived for untagged primary..residential roads."""
    value = tags.get("sidewalk")
    both, left, right = tags.get("sidewalk:both"), tags.get("sidewalk:left"), tags.get("sidewalk:right")
    if value is None and (both or left or right):
        left_yes = (left or both) == "yes"
        right_yes = (right or both) == "yes"
        return left_yes, right_yes
    if value is None:
        derived = tags.get("highway") in SIDEWALK_DERIVED_ON
        return derived, derived
    return value in ("both", "yes", "left"), value in ("both", "yes", "right")


class MissingTagsWarning(UserWarning):
    """An extract lacks a kind of feature (buildings, sidewalks, crossings) and the raster uses a fallback."""


def is_extract(city: str | Path) -> bool:
    """Whether ``city`` names an extract file by its suffix rather than a shipped city."""
    return str(city).lower().endswith(EXTRACT_SUFFIXES)


def extract_name(path: str | Path) -> str:
    """The name of an extract file without its OSM suffix ("West-Oakland.osm.bz2" -> "West-Oakland")."""
    name = Path(path).name
    return next((name[:-len(s)] for s in EXTRACT_SUFFIXES if name.lower().endswith(s)), name)


def city_path(data_dir: str | Path, city: str | Path) -> Path:
    """The extract of a shipped city (under ``data_dir``/raw/osm) or ``city`` itself when it is an extract file.

    Why both: the three shipped cities are built by ``data build``; any other city is a file the user gives
    (``docs/your_city.md``), so a loader must not refuse it."""
    if str(city) in CITIES:
        return require(data_dir, "raw", "osm", f"{city}.osm.pbf")
    path = Path(city)
    if not is_extract(path):
        raise ValueError(f"unknown city {str(city)!r}: give one of {', '.join(CITIES)} or the path of an "
                         f"OpenStreetMap extract ({', '.join(EXTRACT_SUFFIXES)})")
    if not path.is_file():
        raise ValueError(f"{path}: no such extract file; check the path (an OpenStreetMap extract, "
                         f"{', '.join(EXTRACT_SUFFIXES)})")
    return path


def nodes_box(path: str | Path) -> tuple[float, float, float, float]:
    """(west, south, east, north) of every node with a location: the box of an extract whose header has none."""
    lon, lat = [], []
    for node in osmium.FileProcessor(str(path), osmium.osm.NODE):
        if node.location.valid():
            lon.append(node.location.lon)
            lat.append(node.location.lat)
    if not lon:
        raise ValueError(f"{path}: no node with a location, so no map area; give an extract that holds the "
                         "nodes of its ways (e.g. export it again from openstreetmap.org or cut it with osmium extract)")
    if min(lon) == max(lon) or min(lat) == max(lat):
        raise ValueError(f"{path}: its nodes span no area (all on one line of longitude or latitude); give a "
                         "larger extract")
    return min(lon), min(lat), max(lon), max(lat)


def city_projection(path: Path, city: str | Path) -> LocalProjection:
    """The city's frame: its fixed box (Monaco), else the extract header's box, else the nodes' extent."""
    box = CITY_BOXES.get(str(city))
    if box is None:
        reader = osmium.io.Reader(str(path), osmium.osm.osm_entity_bits.NOTHING)
        try:
            header_box = reader.header().box()
        finally:
            reader.close()
        if header_box.valid():
            box = (header_box.bottom_left.lon, header_box.bottom_left.lat,
                   header_box.top_right.lon, header_box.top_right.lat)
        else:  # no <bounds> / pbf bbox: osmium's Box is "invalid location"; the nodes' extent is the map
            box = nodes_box(path)
    return LocalProjection(*box)


def is_crossing_node(tags) -> bool:
    """A crossing node: ``highway=crossing``, or ``highway=traffic_signals`` with ``crossing=*`` (not ``no``)."""
    highway = tags.get("highway")
    return highway == "crossing" or (highway == "traffic_signals" and tags.get("crossing", "no") != "no")


def read_features(path: str | Path, projection: LocalProjection) -> OsmFeatures:
    """One pass over the extract: the lines, areas and crossing nodes the map uses, projected."""
    feats = OsmFeatures()
    width, height = projection.size_m
    margin = 200.0

    def near(xy: np.ndarray) -> bool:
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        return hi[0] > -margin and hi[1] > -margin and lo[0] < width + margin and lo[1] < height + margin

    def ring_xy(ring) -> np.ndarray:
        return projection.project([(n.lon, n.lat) for n in ring if n.location.valid()])

    processor = osmium.FileProcessor(str(path)).with_areas().with_filter(osmium.filter.KeyFilter(*KEYS))
    for obj in processor:
        if obj.is_node():
            if is_crossing_node(obj.tags):
                feats.crossings[obj.id] = projection.project([(obj.location.lon, obj.location.lat)])[0]
        elif obj.is_way():
            tags = dict(obj.tags)
            if line_kind(tags) is None or dropped(tags):
                continue
            nodes = [(n.ref, n.location.lon, n.location.lat) for n in obj.nodes if n.location.valid()]
            if len(nodes) < 2:
                continue
            arr = np.array(nodes)
            xy = projection.project(arr[:, 1:])
            if near(xy):
                feats.lines.append((tags, xy, arr[:, 0].astype(np.int64)))
        elif obj.is_area():
            tags = dict(obj.tags)
            if area_label(tags) is None or dropped(tags):
                continue
            rings = []
            for outer in obj.outer_rings():
                rings.append(ring_xy(outer))
                rings.extend(ring_xy(inner) for inner in obj.inner_rings(outer))
            rings = [r for r in rings if len(r) >= 3]
            if rings and near(np.concatenate(rings)):
                feats.areas.append((tags, rings))
    return feats


def _offset(xy: np.ndarray, distance: float) -> np.ndarray:
    """The polyline shifted ``distance`` metres to its left (in the y-south frame, (dy, -dx))."""
    tangent = np.gradient(xy, axis=0)
    tangent /= np.maximum(np.linalg.norm(tangent, axis=1, keepdims=True), 1e-9)
    return xy + distance * np.stack([tangent[:, 1], -tangent[:, 0]], axis=1)


def _sea(lines: list[np.ndarray], shape: tuple[int, int], resolution: float) -> np.ndarray:
    """Cells on the sea side of the coastline: the regions it cuts off that lie right of its direction."""
    sea = np.zeros(shape, dtype=bool)
    if not lines:
        return sea
    barrier = np.zeros(shape, dtype=np.uint8)
    stroke(barrier, lines, [resolution] * len(lines), 1, resolution)
    _, component = cv2.connectedComponents((barrier == 0).astype(np.uint8), connectivity=4)
    xy = np.concatenate([ln[:-1] for ln in lines])
    d = np.concatenate([np.diff(ln, axis=0) for ln in lines])
    length = np.linalg.norm(d, axis=1)
    keep = length > 0
    xy, d, length = xy[keep], d[keep], length[keep]
    mid = xy + d / 2
    right = np.stack([-d[:, 1], d[:, 0]], axis=1) / length[:, None] * 2 * resolution
    votes = []
    for side in (mid + right, mid - right):  # sea side, land side
        rc = np.floor(side[:, ::-1] / resolution).astype(np.int64)
        ok = (rc[:, 0] >= 0) & (rc[:, 0] < shape[0]) & (rc[:, 1] >= 0) & (rc[:, 1] < shape[1])
        votes.append(np.bincount(component[rc[ok, 0], rc[ok, 1]], minlength=component.max() + 1))
    # A region is sea when the coastline faces it from the sea side at least 3 times as often as from
    # land; where a clipped coastline leaves sea and land connected, the votes cancel and nothing floods.
    is_sea = (votes[0] > 0) & (votes[0] >= 3 * votes[1])
    is_sea[0] = False  # the coastline cells themselves
    return is_sea[component]


def rasterize(feats: OsmFeatures, shape: tuple[int, int], resolution: float) -> np.ndarray:
    """The label raster of ``feats`` (see the module docstring for the painting order)."""
    labels = np.full(shape, label_id("rough_terrain"), dtype=np.uint8)
    lines_of: dict[str, list[tuple[dict[str, str], np.ndarray, np.ndarray]]] = {}
    for line in feats.lines:
        lines_of.setdefault(line_kind(line[0]), []).append(line)
    areas_of: dict[str, list[list[np.ndarray]]] = {}
    for tags, rings in feats.areas:
        areas_of.setdefault(area_label(tags), []).append(rings)

    labels[_sea([xy for _, xy, _ in lines_of.get("coastline", [])], shape, resolution)] = label_id("water")

    ground = [(rings, label) for label in ("grass", "rough_terrain") for rings in areas_of.get(label, [])]
    ground.sort(key=lambda item: -abs(cv2.contourArea(item[0][0].astype(np.float32))))
    for rings, label in ground:
        fill(labels, rings, label_id(label), resolution)

    for rings in areas_of.get("water", []):
        fill(labels, rings, label_id("water"), resolution)
    waterways = lines_of.get("waterway", [])
    stroke(labels, [xy for _, xy, _ in waterways], [WATERWAY_WIDTH_M[t["waterway"]] for t, _, _ in waterways],
            label_id("water"), resolution)
    for rings in areas_of.get("parking", []):
        fill(labels, rings, label_id("parking"), resolution)

    sidewalk = label_id("sidewalk")
    roads = lines_of.get("road", []) + lines_of.get("living_street", [])
    both, both_w, side, side_w = [], [], [], []
    for tags, xy, _ in roads:
        left, right = sidewalk_sides(tags)
        width = road_width(tags)
        if left and right:
            both.append(xy)
            both_w.append(width + 2 * SIDEWALK_WIDTH_M)
            continue
        for flag, sign in ((left, 1.0), (right, -1.0)):
            if flag:
                side.append(_offset(xy, sign * (width + SIDEWALK_WIDTH_M) / 2))
                side_w.append(SIDEWALK_WIDTH_M)
    stroke(labels, both, both_w, sidewalk, resolution)
    stroke(labels, side, side_w, sidewalk, resolution)
    for rings in areas_of.get("sidewalk", []):
        fill(labels, rings, sidewalk, resolution)
    paths = lines_of.get("path", []) + lines_of.get("crossing", [])
    piers = lines_of.get("pier", [])
    stroke(labels, [xy for _, xy, _ in paths] + [xy for _, xy, _ in piers],
            [_number(t.get("width")) or PATH_WIDTH_M[t["highway"]] for t, _, _ in paths] + [PIER_WIDTH_M] * len(piers),
            sidewalk, resolution)

    for kind in ("road", "living_street"):
        group = lines_of.get(kind, [])
        stroke(labels, [xy for _, xy, _ in group], [road_width(t) for t, _, _ in group], label_id(kind), resolution)

    labels[_crosswalk_mask(feats, lines_of, shape, resolution) & np.isin(
        labels, [label_id("road"), label_id("living_street")])] = label_id("crosswalk")

    for rings in areas_of.get("building", []):
        fill(labels, rings, label_id("building"), resolution)
    return labels


def _crosswalk_mask(feats: OsmFeatures, lines_of: dict, shape: tuple[int, int], resolution: float) -> np.ndarray:
    """Crossing ways, plus a stripe across the road at each crossing node that lies on a road."""
    mask = np.zeros(shape, dtype=np.uint8)
    stripes = [xy for _, xy, _ in lines_of.get("crossing", [])]
    widths = [CROSSWALK_WIDTH_M] * len(stripes)
    for tags, xy, ids in lines_of.get("road", []) + lines_of.get("living_street", []):
        hits = np.flatnonzero(np.isin(ids, list(feats.crossings)))
        if hits.size == 0:
            continue
        tangent = xy[np.minimum(hits + 1, len(xy) - 1)] - xy[np.maximum(hits - 1, 0)]
        tangent /= np.maximum(np.linalg.norm(tangent, axis=1, keepdims=True), 1e-9)
        normal = np.stack([tangent[:, 1], -tangent[:, 0]], axis=1) * (road_width(tags) / 2 + 1.0)
        stripes.extend(np.stack([xy[hits] - normal, xy[hits] + normal], axis=1))
        widths.extend([CROSSWALK_WIDTH_M] * hits.size)
    stroke(mask, stripes, widths, 1, resolution)
    return mask.astype(bool)


def walkable_network(feats: OsmFeatures) -> WalkableNetwork:
    """Nodes and edges (metres) of every way a pedestrian may use, after the same drop rules."""
    ways = [(xy, ids) for tags, xy, ids in feats.lines if walkable(tags)]
    if not ways:
        return WalkableNetwork(np.zeros((0, 2)), np.zeros((0, 2), dtype=np.int64))
    ids = np.concatenate([i for _, i in ways])
    xy = np.concatenate([p for p, _ in ways])
    _, first, index = np.unique(ids, return_index=True, return_inverse=True)
    ends = np.cumsum([len(i) for _, i in ways])
    a = np.delete(np.arange(ids.size - 1), ends[:-1] - 1)
    edges = np.sort(np.stack([index[a], index[a + 1]], axis=1), axis=1)
    edges = np.unique(edges[edges[:, 0] != edges[:, 1]], axis=0)
    return WalkableNetwork(xy[first], edges.astype(np.int64))


def missing_tags(feats: OsmFeatures) -> list[str]:
    """One sentence per kind of feature the extract does not map, naming the fallback the raster uses."""
    kinds = [line_kind(tags) for tags, _, _ in feats.lines]
    labels = {area_label(tags) for tags, _ in feats.areas}
    found = []
    if "building" not in labels:
        found.append("no buildings mapped: blocks are rasterised as rough_terrain (untagged open ground), "
                     "so a walker may cut across them")
    tagged = any(sidewalk_sides(t) != (False, False) and ("sidewalk" in t or any(k.startswith("sidewalk:") for k in t))
                 for t, _, _ in feats.lines if line_kind(t) in ("road", "living_street"))
    if not tagged and "path" not in kinds and "sidewalk" not in labels:
        derived = any(t.get("highway") in SIDEWALK_DERIVED_ON for t, _, _ in feats.lines)
        found.append("no sidewalks or footways mapped: sidewalks are derived on both sides of untagged primary.."
                     "residential roads" + ("" if derived else ", and there are none, so the map has no sidewalk"))
    if not feats.crossings and "crossing" not in kinds:
        found.append("no crossings mapped (no highway=crossing node, crossing=* traffic-signals node or "
                     "footway=crossing way): the map has no crosswalk cells, roads are crossed on road cells")
    return found


def read_extract(path: str | Path, projection: LocalProjection, resolution_m: float,
                 name: str) -> tuple[SemanticMap, WalkableNetwork]:
    """Any .osm/.osm.pbf/.osm.bz2 file over ``projection``'s box: its semantic map and walkable network, the
    network restricted to the map's non-hard cells. Each kind of feature the extract lacks is a
    ``MissingTagsWarning`` naming the fallback (``missing_tags``), never a silently emptier tile."""
    feats = read_features(path, projection)
    for sentence in missing_tags(feats):
        warnings.warn(f"{name} ({Path(path).name}): {sentence}", MissingTagsWarning, stacklevel=2)
    width, height = projection.size_m
    frame = RasterFrame((int(height // resolution_m), int(width // resolution_m)), float(resolution_m))
    smap = SemanticMap(name, rasterize(feats, frame.shape, resolution_m), frame)
    return smap, restrict_to_map(walkable_network(feats), smap)


def read_city(data_dir: str | Path, city: str | Path, resolution_m: float) -> tuple[SemanticMap, WalkableNetwork]:
    """The city's semantic map and its walkable network: a shipped city's name or an extract's path
    (``city_path``); an extract's map is named after its file (``extract_name``)."""
    path = city_path(data_dir, city)
    name = str(city) if str(city) in CITIES else extract_name(path)
    return read_extract(path, city_projection(path, city), resolution_m, name)


def load_city(data_dir: str | Path, city: str | Path, resolution_m: float) -> SemanticMap:
    """The semantic map of a whole city extract (``helsinki``, ``kouvola``, ``monaco`` or an extract's path)."""
    return read_city(data_dir, city, resolution_m)[0]
