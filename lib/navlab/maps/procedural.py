"""Seeded OSM-like city tiles with a *structure* knob (the paper's Baltimore / Capitol Hill / Milan roles).

Streets are the edges of a Voronoi diagram of block seeds laid on a lattice. ``structure = 1`` keeps
the lattice exact (rectangular grid blocks, straight axis-aligned streets, Baltimore-like);
``structure = 0`` jitters the seeds by up to half a block, removes some (merging blocks of uneven size)
and bends every street (irregular medieval streets, Milan-like); values between mix the two.

Painting, each a vectorised raster op: block contents (perimeter buildings with courtyards, parks with
footpaths, ponds and scrub, parking lots, rough ground, plazas), an optional river, sidewalks on both
sides of every street, the carriageways (some of them living streets without sidewalks), crosswalks at
every arm of every intersection, and bridges wherever a street crosses the river.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy.spatial import Voronoi, cKDTree

from navlab.core.grid import RasterFrame
from navlab.core.labels import label_id
from navlab.core.params.maps import ProceduralParams
from navlab.core.seeding import rng as seeded_rng
from navlab.maps.draw import stroke
from navlab.maps.semantic_map import SemanticMap

SIDEWALK_WIDTH_M = (2.0, 3.5)
ROAD_WIDTHS_M = (6.0, 8.0, 10.0, 14.0)
ROAD_WIDTH_P = (0.45, 0.3, 0.15, 0.1)
LIVING_STREET_WIDTH_M = 5.0
CROSSWALK_WIDTH_M = 3.0
BUILDING_DEPTH_M = (10.0, 20.0)
LOT_SIZE_M = 18.0
GAP_WIDTH_M = 3.0  # between neighbouring buildings of a block
BUILDINGS, PARK, PARKING, ROUGH, PLAZA = range(5)  # block kinds
BLOCK_KIND_P = (0.66, 0.14, 0.09, 0.07, 0.04)




def street_network(rng: np.random.Generator, structure: float, size_m: float, block_range: tuple[float, float]):
    """Street centrelines (polylines), intersection vertices and which street meets which vertex."""
    disorder = 1.0 - structure
    bx, by = rng.uniform(*block_range, size=2) * (1.0 - 0.4 * disorder)  # old towns have smaller blocks
    margin = 2 * max(bx, by)
    gx = np.arange(-margin, size_m + margin, bx) + rng.uniform(0, bx)
    gy = np.arange(-margin, size_m + margin, by) + rng.uniform(0, by)
    seeds = np.stack(np.meshgrid(gx, gy), axis=-1).reshape(-1, 2)
    seeds = seeds + rng.uniform(-0.45, 0.45, seeds.shape) * disorder * np.array([bx, by])
    seeds = seeds + rng.uniform(-1e-3, 1e-3, seeds.shape)  # no exactly co-circular points for qhull
    seeds = seeds[rng.random(len(seeds)) >= 0.3 * disorder]
    vor = Voronoi(seeds)
    # A 4-way crossing of an exact lattice comes out as two vertices a hair apart: merge them.
    vertices = vor.vertices
    same = cKDTree(vertices).query_ball_point(vertices, r=1.0)
    merged = np.array([min(group) for group in same], dtype=np.int64)
    ridges = np.array([r for r in vor.ridge_vertices if -1 not in r], dtype=np.int64)
    ridges = merged[ridges]
    a, b = vertices[ridges[:, 0]], vertices[ridges[:, 1]]
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    near = (hi > -50).all(axis=1) & (lo < size_m + 50).all(axis=1) & (ridges[:, 0] != ridges[:, 1])
    ridges, a, b = ridges[near], a[near], b[near]
    # Bend each street: a smooth perpendicular bulge, zero at both ends so intersections stay put.
    t = np.linspace(0.0, 1.0, 9)
    chord = b - a
    normal = np.stack([-chord[:, 1], chord[:, 0]], axis=1)
    bulge = rng.normal(0.0, 0.12, len(ridges)) * disorder
    wiggle = rng.normal(0.0, 0.04, len(ridges)) * disorder
    offset = bulge[:, None] * np.sin(np.pi * t) + wiggle[:, None] * np.sin(2 * np.pi * t)
    lines = a[:, None] + t[None, :, None] * chord[:, None] + offset[..., None] * normal[:, None]
    return lines, vertices, ridges


def _blocks(labels: np.ndarray, street: np.ndarray, rng: np.random.Generator, structure: float,
            resolution: float) -> None:
    """Fill every block (a connected component of non-street cells) with its kind's contents."""
    count, block = cv2.connectedComponents((~street).astype(np.uint8), connectivity=4)
    kind = rng.choice(len(BLOCK_KIND_P), size=count, p=BLOCK_KIND_P)
    kind[0] = -1  # the street cells
    cell_kind = kind[block]
    depth_from_street = cv2.distanceTransform((~street).astype(np.uint8), cv2.DIST_L2, 5) * resolution
    rows, cols = labels.shape

    # Buildings: a perimeter ring of lots behind a setback, courtyards of grass or parking inside.
    setback = rng.uniform(0.0, 4.0, count) * structure
    depth = rng.uniform(*BUILDING_DEPTH_M, count)
    courtyard = np.where(rng.random(count) < 0.7, label_id("grass"), label_id("parking"))
    front = np.where(rng.random(count) < 0.5, label_id("grass"), label_id("sidewalk"))
    is_b = cell_kind == BUILDINGS
    d, sb, dp = depth_from_street, setback[block], depth[block]
    labels[is_b] = label_id("building")
    labels[is_b & (d < sb)] = front[block][is_b & (d < sb)]
    inner = is_b & (d >= sb + dp)
    labels[inner] = courtyard[block][inner]
    # Lot boundaries: the Voronoi edges of random lot seeds (nearest-seed labels by a distance transform)
    # open a gap between neighbouring buildings where a per-pair coin says so.
    n_lots = max(int(rows * cols * resolution**2 / LOT_SIZE_M**2), 2)
    seeds = np.ones((rows, cols), dtype=np.uint8)
    seeds[rng.integers(0, rows, n_lots), rng.integers(0, cols, n_lots)] = 0
    _, lot = cv2.distanceTransformWithLabels(seeds, cv2.DIST_L2, 5, labelType=cv2.DIST_LABEL_PIXEL)
    coin = rng.random(int(lot.max()) + 1)
    boundary = np.zeros((rows, cols), dtype=np.uint8)
    for a, b, cut in ((lot[:, 1:], lot[:, :-1], (slice(None), slice(1, None))),
                      (lot[1:, :], lot[:-1, :], (slice(1, None), slice(None)))):
        boundary[cut] |= ((a != b) & ((coin[a] + coin[b]) % 1.0 < 0.5)).astype(np.uint8)
    width_px = max(round(GAP_WIDTH_M / resolution), 1)
    gap = cv2.dilate(boundary, np.ones((width_px, width_px), np.uint8)).astype(bool)
    labels[gap & (labels == label_id("building")) & is_b] = label_id("grass")

    labels[cell_kind == PARKING] = label_id("parking")
    labels[cell_kind == ROUGH] = label_id("rough_terrain")
    labels[cell_kind == PLAZA] = label_id("sidewalk")
    is_park = cell_kind == PARK
    labels[is_park] = label_id("grass")
    _park_features(labels, block, np.flatnonzero(kind == PARK), is_park, rng, resolution)


def _park_features(labels: np.ndarray, block: np.ndarray, parks: np.ndarray, is_park: np.ndarray,
                   rng: np.random.Generator, resolution: float) -> None:
    """Footpaths across each park (reaching its sidewalks), and scrub patches and ponds inside it."""
    if parks.size == 0:
        return
    rc = np.argwhere(is_park)
    owner = block[rc[:, 0], rc[:, 1]]
    order = np.argsort(owner, kind="stable")
    rc, owner = rc[order], owner[order]
    starts = np.searchsorted(owner, parks)
    counts = np.searchsorted(owner, parks, side="right") - starts
    sums = np.add.reduceat(rc.astype(float), starts, axis=0)
    centre = (sums / counts[:, None])[:, ::-1] * resolution + resolution / 2  # (x, y)
    radius = np.sqrt(counts * resolution**2 / np.pi)
    paths = np.zeros(labels.shape, dtype=np.uint8)
    lines, widths = [], []
    for angle_set, c, r in zip(rng.uniform(0, np.pi, (parks.size, 2)), centre, radius, strict=True):
        for angle in angle_set:
            direction = np.array([np.cos(angle), np.sin(angle)]) * 2.5 * r
            lines.append(np.stack([c - direction, c + direction]))
            widths.append(2.0)
    stroke(paths, lines, np.array(widths), 1, resolution)
    no_patch, scrub, pond = range(3)
    patches = np.zeros(labels.shape, dtype=np.uint8)
    for c, r, kind, scale in zip(centre, radius, rng.choice(3, parks.size), rng.uniform(0.15, 0.3, parks.size),
                                 strict=True):
        if kind == no_patch:
            continue
        axes = (max(int(scale * r / resolution), 1), max(int(0.7 * scale * r / resolution), 1))
        shifted = c + rng.uniform(-0.3, 0.3, 2) * r
        cv2.ellipse(patches, tuple(int(v) for v in shifted / resolution), axes, float(rng.uniform(0, 180)),
                    0, 360, int(kind), -1)
    labels[is_park & (patches == scrub)] = label_id("rough_terrain")
    labels[is_park & (patches == pond)] = label_id("water")
    labels[is_park & (paths == 1) & (patches != pond)] = label_id("sidewalk")


def _river(shape: tuple[int, int], rng: np.random.Generator, resolution: float) -> np.ndarray:
    """A meandering band of water across the tile, as a mask."""
    rows, cols = shape
    size = np.array([cols, rows]) * resolution
    angle = rng.uniform(0, np.pi)
    along = np.array([np.cos(angle), np.sin(angle)])
    across = np.array([-along[1], along[0]])
    s = np.linspace(-1, 1, 64)[:, None] * size.max()
    meander = (rng.uniform(10, 40) * np.sin(s / rng.uniform(60, 150) + rng.uniform(0, 2 * np.pi)))
    centre = size / 2 + rng.uniform(-0.25, 0.25) * size.min() * across
    line = centre + s * along + meander * across
    mask = np.zeros(shape, dtype=np.uint8)
    stroke(mask, [line], np.array([rng.uniform(15, 35)]), 1, resolution)
    return mask.astype(bool)


def generate(seed: int, name: str, structure: float, params: ProceduralParams, resolution: float) -> SemanticMap:
    """One procedural tile; the same (seed, name, structure, params, resolution) gives the same map."""
    if not 0.0 <= structure <= 1.0:
        raise ValueError(f"structure = {structure}: must lie in [0, 1] (1 = grid city, 0 = irregular)")
    rng = seeded_rng(seed, "procedural", name)
    side = round(params.tile_size_m / resolution)
    shape = (side, side)
    lines, vertices, ridges = street_network(rng, structure, params.tile_size_m, tuple(params.block_size_m))
    n = len(lines)
    living = rng.random(n) < params.living_street_probability
    road_w = np.where(living, LIVING_STREET_WIDTH_M, rng.choice(ROAD_WIDTHS_M, size=n, p=ROAD_WIDTH_P))
    walk_w = np.where(living, 0.0, rng.uniform(*SIDEWALK_WIDTH_M, size=n))
    street_w = road_w + 2 * walk_w

    street = np.zeros(shape, dtype=np.uint8)
    stroke(street, list(lines), street_w, 1, resolution)
    labels = np.full(shape, label_id("rough_terrain"), dtype=np.uint8)
    _blocks(labels, street.astype(bool), rng, structure, resolution)
    if rng.random() < params.river_probability:
        labels[_river(shape, rng, resolution)] = label_id("water")

    stroke(labels, list(lines[~living]), street_w[~living], label_id("sidewalk"), resolution)
    stroke(labels, list(lines[~living]), road_w[~living], label_id("road"), resolution)
    stroke(labels, list(lines[living]), road_w[living], label_id("living_street"), resolution)
    crossing = _crosswalks(lines, ridges, road_w, walk_w, living, len(vertices), shape, resolution)
    labels[crossing & (labels == label_id("road"))] = label_id("crosswalk")
    return SemanticMap(name, labels, RasterFrame(shape, float(resolution)))


def _crosswalks(lines: np.ndarray, ridges: np.ndarray, road_w: np.ndarray, walk_w: np.ndarray,
                living: np.ndarray, n_vertices: int, shape: tuple[int, int], resolution: float) -> np.ndarray:
    """A zebra stripe across every street arm, set back from each intersection past the corner sidewalks."""
    degree = np.bincount(ridges.ravel(), minlength=n_vertices)
    widest = np.zeros(n_vertices)
    np.maximum.at(widest, ridges[:, 0], road_w / 2 + walk_w)
    np.maximum.at(widest, ridges[:, 1], road_w / 2 + walk_w)
    stripes, widths = [], []
    for end, (tip, nxt) in ((0, (0, 1)), (1, (-1, -2))):
        vertex = ridges[:, end]
        ok = (degree[vertex] >= 3) & ~living
        direction = lines[:, nxt] - lines[:, tip]
        direction /= np.maximum(np.linalg.norm(direction, axis=1, keepdims=True), 1e-9)
        setback = widest[vertex] + CROSSWALK_WIDTH_M / 2 + 0.5
        centre = lines[:, tip] + direction * setback[:, None]
        normal = np.stack([-direction[:, 1], direction[:, 0]], axis=1) * (road_w[:, None] / 2 + 1.0)
        segment = np.stack([centre - normal, centre + normal], axis=1)
        stripes.extend(segment[ok])
        widths.extend([CROSSWALK_WIDTH_M] * int(ok.sum()))
    mask = np.zeros(shape, dtype=np.uint8)
    stroke(mask, stripes, np.array(widths), 1, resolution)
    return mask.astype(bool)


def street_regularity(labels: np.ndarray) -> float:
    """Four-fold orientation coherence of the street edges in [0, 1]: 1 for a grid at any rotation,
    near 0 when street directions are spread evenly (|mean exp(4i theta)| of the edge normals)."""
    streets = np.isin(labels, [label_id("road"), label_id("living_street"), label_id("crosswalk")])
    streets = streets.astype(np.float32)
    streets = cv2.GaussianBlur(streets, (0, 0), 2.0)
    gx = cv2.Sobel(streets, cv2.CV_32F, 1, 0, ksize=3)
    gy = cv2.Sobel(streets, cv2.CV_32F, 0, 1, ksize=3)
    g = (gx + 1j * gy)[(gx != 0) | (gy != 0)]
    if g.size == 0:
        return 0.0
    weight = np.abs(g)
    return float(np.abs((g**4 / weight**3).sum()) / weight.sum())  # |g| e^{4i theta} = g^4 / |g|^3
