"""What surrounds each region: the context the demonstrator's rules read, from a label map alone.

Regions are the cells of one index (a superpixel of the region graph). Every feature is a property of
the region's surroundings at its own scale or larger — the patch it belongs to, the sidewalk beside
it, the place a sidewalk ends, a new obstacle next to it — so a per-region relaxation cost can
express what the rules decide, and a per-label cost cannot.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from skimage.morphology import skeletonize

from navlab.core.labels import SOFT_IDS, label_id
from navlab.graphs.region_graph import RegionGraph

SIDEWALK, CROSSWALK, ROAD = label_id("sidewalk"), label_id("crosswalk"), label_id("road")
LIVING_STREET = label_id("living_street")
WALKWAY = np.array([SIDEWALK, CROSSWALK, ROAD, LIVING_STREET])  # where people walk or step from
HARD_LABEL = label_id("building")  # what a region graph's hard space (id -1) stands for
ALONGSIDE_M = 12.0  # a sidewalk this close runs beside the road (carriageway half-width + verge)
CROSSING_POINT_M = 8.0  # road this close to a crosswalk or to a sidewalk's end is where people cross
SIDEWALK_END_AT_ROAD_M = 2.0  # a sidewalk end this close to a road ends *at* the road
BESIDE_M = 2.0  # a region this close to a new obstacle borders it
_EIGHT = np.ones((3, 3), dtype=bool)


@dataclass(frozen=True)
class RegionContext:
    label: np.ndarray  # (N,) label id
    area_m2: np.ndarray  # (N,) the region's own area
    patch_m2: np.ndarray  # (N,) area of the 8-connected same-label patch the region lies in
    by_sidewalk: np.ndarray  # (N,) bool: a sidewalk cell within ALONGSIDE_M
    crossing_point: np.ndarray  # (N,) bool: within CROSSING_POINT_M of a crosswalk or of a sidewalk's end at a road
    on_walkway: np.ndarray  # (N,) bool: touches a sidewalk, crosswalk, road or living street cell
    beside_obstacle: np.ndarray  # (N,) bool: within BESIDE_M of a new obstacle


def sidewalk_ends(labels: np.ndarray, resolution: float) -> np.ndarray:
    """Cells where a sidewalk stops at a road: ends of the sidewalk's skeleton next to road cells (the
    raster's border, where a crop cut the sidewalk, is no end)."""
    skeleton = skeletonize(labels == SIDEWALK)
    neighbours = ndimage.convolve(skeleton.astype(np.int32), _EIGHT.astype(np.int32), mode="constant") - skeleton
    ends = skeleton & (neighbours <= 1)
    ends[[0, -1], :] = ends[:, [0, -1]] = False
    return ends & (_distance_to(labels == ROAD, resolution) <= SIDEWALK_END_AT_ROAD_M)


def region_context(labels: np.ndarray, regions: np.ndarray, n_regions: int, resolution: float,
                   new_hard: np.ndarray | None = None) -> RegionContext:
    """The context of every region 0..n_regions-1 of ``regions`` (index raster, -1 in hard space) on the
    label raster ``labels``; ``new_hard``: cells that became hard since the walker's map (a new obstacle)."""
    inside = regions >= 0
    index = regions[inside]

    def nearest(mask: np.ndarray) -> np.ndarray:  # per region: metres from its closest cell to ``mask``
        out = np.full(n_regions, np.inf)
        np.minimum.at(out, index, _distance_to(mask, resolution)[inside])
        return out

    label = np.zeros(n_regions, dtype=np.int64)
    label[index] = labels[inside]
    patch = np.zeros(n_regions)
    for soft in SOFT_IDS:
        parts, _ = ndimage.label(labels == soft, structure=_EIGHT)
        size = np.bincount(parts.ravel()) * resolution**2
        here = inside & (labels == soft)
        np.maximum.at(patch, regions[here], size[parts[here]])
    obstacle = np.zeros(labels.shape, dtype=bool) if new_hard is None else new_hard
    return RegionContext(
        label=label, area_m2=np.bincount(index, minlength=n_regions) * resolution**2, patch_m2=patch,
        by_sidewalk=nearest(labels == SIDEWALK) <= ALONGSIDE_M,
        crossing_point=nearest((labels == CROSSWALK) | sidewalk_ends(labels, resolution)) <= CROSSING_POINT_M,
        on_walkway=nearest(np.isin(labels, WALKWAY)) <= 1.5 * resolution,
        beside_obstacle=nearest(obstacle) <= BESIDE_M)


def graph_context(graph: RegionGraph, new_hard: np.ndarray | None = None) -> RegionContext:
    """``region_context`` of a region graph's nodes (its hard space read as buildings)."""
    nodes = graph.node_raster
    labels = np.where(nodes >= 0, graph.node_label[np.maximum(nodes, 0)], HARD_LABEL)
    return region_context(labels, nodes, graph.num_nodes, graph.frame.resolution, new_hard)


def _distance_to(mask: np.ndarray, resolution: float) -> np.ndarray:
    """Metres from every cell to the nearest cell of ``mask`` (inf everywhere when it is empty)."""
    if not mask.any():
        return np.full(mask.shape, np.inf)
    return ndimage.distance_transform_edt(~mask) * resolution
