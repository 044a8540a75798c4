"""Small hand-built semantic maps for unit tests (the real and procedural maps come from navlab.maps)."""

from __future__ import annotations

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.core.labels import label_id
from navlab.maps.semantic_map import SemanticMap

L = {name: label_id(name) for name in ("sidewalk", "crosswalk", "road", "living_street", "parking", "grass",
                                       "rough_terrain", "building", "water")}


def city(size: int = 120, resolution: float = 1.0) -> SemanticMap:
    """A 3x3-block town: 8 m roads, 3 m sidewalks, crosswalks at some crossings, a lawn, a small grass
    corner, a parking lot, rough ground, a pond; everything else buildings."""
    lab = np.full((size, size), L["building"], dtype=np.uint8)
    step = size // 3
    for k in range(4):
        c = min(k * step, size - 1)
        lo, hi = max(c - 7, 0), min(c + 7, size)
        lab[lo:hi, :] = np.where(lab[lo:hi, :] == L["road"], L["road"], L["sidewalk"])
        lab[:, lo:hi] = L["sidewalk"]
    for k in range(4):
        c = min(k * step, size - 1)
        lo, hi = max(c - 4, 0), min(c + 4, size)
        lab[lo:hi, :] = L["road"]
        lab[:, lo:hi] = L["road"]
    # crosswalks on two of the crossings only
    for r, c in ((step, step), (2 * step, 2 * step)):
        lab[r - 4:r + 4, c + 8:c + 11] = L["crosswalk"]
        lab[r + 8:r + 11, c - 4:c + 4] = L["crosswalk"]
    b = step // 2
    lab[step + 8:2 * step - 7, step + 8:2 * step - 7] = L["grass"]  # the centre block: a lawn
    lab[7:16, step + 8:step + 17] = L["grass"]  # a small corner patch
    lab[2 * step + 8:3 * step - 7, 8:b + 8] = L["parking"]
    lab[8:step - 7, 2 * step + 8:2 * step + 20] = L["rough_terrain"]
    lab[2 * step + 12:2 * step + 20, 2 * step + 12:2 * step + 22] = L["water"]
    return SemanticMap("test_city", lab, RasterFrame((size, size), resolution))


def grass_corner(side: int, leg: int = 1) -> SemanticMap:
    """An L of sidewalk (``leg`` wide) around a ``side``-metre square of grass; buildings elsewhere.

    Walking the L costs 2*side; cutting across the grass about sqrt(2)*side*grass_cost, so a fixed
    grass cost makes the same choice at every size, while a person cuts a small corner but not a lawn.
    """
    n = side + leg + 2
    lab = np.full((n, n), L["building"], dtype=np.uint8)
    lab[1:n - 1, 1:1 + leg] = L["sidewalk"]  # left leg
    lab[1:1 + leg, 1:n - 1] = L["sidewalk"]  # top leg
    lab[1 + leg:n - 1, 1 + leg:n - 1] = L["grass"]
    return SemanticMap(f"grass_corner_{side}", lab, RasterFrame((n, n), 1.0))


def blobs(seed: int, size: int = 80, resolution: float = 1.0) -> SemanticMap:
    """Random smooth label blobs over every label (hard ones included): irregular shapes and islands."""
    from scipy import ndimage

    gen = np.random.default_rng(seed)
    fields = ndimage.gaussian_filter(gen.standard_normal((len(L), size, size)), sigma=(0, 4, 4))
    lab = np.argmax(fields, axis=0).astype(np.uint8)
    return SemanticMap(f"blobs_{seed}", lab, RasterFrame((size, size), resolution, (10.0, -5.0)))


ZEBRAS = (2, 9)  # band columns of ``zebra_band`` painted as crosswalks


def zebra_band(rows: int = 8, cols: int = 12, block: int = 3) -> tuple[SemanticMap, np.ndarray]:
    """Sidewalk above and below a two-block band of grass with crosswalks at columns ``ZEBRAS``, one
    building block on the upper sidewalk; superpixels are the ``block`` x ``block`` squares (-1 on the
    building). Returns (map, superpixel raster)."""
    block_label = np.full((rows, cols), L["sidewalk"])
    block_label[3:5] = L["grass"]
    block_label[3:5, list(ZEBRAS)] = L["crosswalk"]
    block_label[1, 5] = L["building"]
    labels = np.repeat(np.repeat(block_label, block, 0), block, 1).astype(np.uint8)
    sp = np.repeat(np.repeat(np.arange(rows * cols).reshape(rows, cols), block, 0), block, 1).astype(np.int32)
    sp[labels == L["building"]] = -1
    return SemanticMap("zebra_band", labels, RasterFrame(labels.shape, 1.0)), sp
