"""The walkable network of a map: nodes in metres (the map's world frame) and undirected edges.

Real maps take it from the same OpenStreetMap ways the rasteriser paints (``maps.osm``); procedural
maps derive it from the raster itself (the skeleton of its sidewalk and crosswalk cells). Either way
``restrict_to_map`` removes every edge that touches a hard cell or leaves the map, so a route on the
network can never cut through a building or water: the network and the raster agree on what is walkable.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from skimage.morphology import skeletonize

from navlab.core.io import load_npz, save_npz
from navlab.core.labels import constraint_mask, label_id
from navlab.maps.semantic_map import SemanticMap


@dataclass(frozen=True)
class WalkableNetwork:
    xy: np.ndarray  # (N, 2) float64 node positions, world metres
    edges: np.ndarray  # (E, 2) int64 node indices, undirected, each pair once

    @property
    def lengths(self) -> np.ndarray:
        return np.linalg.norm(self.xy[self.edges[:, 0]] - self.xy[self.edges[:, 1]], axis=1)

    def save(self, path: str | Path) -> None:
        save_npz(path, {"xy": self.xy.astype(np.float64), "edges": self.edges.astype(np.int64)})

    @classmethod
    def load(cls, path: str | Path) -> WalkableNetwork:
        arrays = load_npz(path, fix="build the dataset with `python -m navlab data build`")
        return cls(arrays["xy"], arrays["edges"])

    def subgraph(self, keep_edges: np.ndarray) -> WalkableNetwork:
        """The network with only ``keep_edges`` (bool mask) and the nodes they use, renumbered."""
        edges = self.edges[keep_edges]
        used, inverse = np.unique(edges, return_inverse=True)
        return WalkableNetwork(self.xy[used], inverse.reshape(-1, 2).astype(np.int64))


def edge_samples(xy: np.ndarray, edges: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Points every <= ``step`` metres along each edge (ends included) and the edge each point belongs to."""
    a, b = xy[edges[:, 0]], xy[edges[:, 1]]
    counts = np.maximum(np.ceil(np.linalg.norm(b - a, axis=1) / step).astype(np.int64), 1) + 1
    owner = np.repeat(np.arange(len(edges)), counts)
    starts = np.cumsum(counts) - counts
    t = (np.arange(owner.size) - starts[owner]) / (counts[owner] - 1)
    return a[owner] + t[:, None] * (b[owner] - a[owner]), owner


def restrict_to_map(network: WalkableNetwork, smap: SemanticMap) -> WalkableNetwork:
    """Drop the edges that leave ``smap`` or touch one of its hard cells (and nodes left without edges)."""
    if len(network.edges) == 0:
        return network
    points, owner = edge_samples(network.xy, network.edges, smap.frame.resolution / 4)
    cells = smap.frame.world_to_cell(points)
    inside = smap.frame.contains(cells)
    bad = ~inside
    rows, cols = cells[inside, 0], cells[inside, 1]
    bad[inside] = constraint_mask(smap.labels[rows, cols], "hard")
    blocked = np.zeros(len(network.edges), dtype=bool)
    np.logical_or.at(blocked, owner, bad)
    return network.subgraph(~blocked)


def clip(network: WalkableNetwork, x0: float, y0: float, width: float, height: float) -> WalkableNetwork:
    """The edges with both ends inside the box, shifted so that the box corner becomes the origin."""
    inside = ((network.xy[:, 0] >= x0) & (network.xy[:, 0] < x0 + width)
              & (network.xy[:, 1] >= y0) & (network.xy[:, 1] < y0 + height))
    keep = inside[network.edges].all(axis=1)
    sub = network.subgraph(keep)
    return WalkableNetwork(sub.xy - np.array([x0, y0]), sub.edges)


def network_from_raster(smap: SemanticMap) -> WalkableNetwork:
    """The 8-connected skeleton of the sidewalk and crosswalk cells, one node per skeleton cell.

    The skeleton runs along the middle of every sidewalk and across every crosswalk, which is where a
    pedestrian router should send people; it is connected wherever the walkable cells are.
    """
    walkable = np.isin(smap.labels, [label_id("sidewalk"), label_id("crosswalk")])
    skeleton = skeletonize(walkable)
    index = np.full(skeleton.shape, -1, dtype=np.int64)
    rc = np.argwhere(skeleton)
    index[rc[:, 0], rc[:, 1]] = np.arange(len(rc))
    pairs = []
    rows, cols = skeleton.shape
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        a = index[0:rows - dr, max(0, -dc):cols - max(0, dc)]
        b = index[dr:rows, max(0, dc):cols - max(0, -dc)]
        both = (a >= 0) & (b >= 0)
        if dr and dc:  # a diagonal step may not cut a corner: both cells beside it must be walkable too
            both &= walkable[0:rows - dr, max(0, dc):cols - max(0, -dc)] & walkable[dr:rows, max(0, -dc):cols - max(0, dc)]
        pairs.append(np.stack([a[both], b[both]], axis=1))
    edges = np.concatenate(pairs).astype(np.int64)
    return WalkableNetwork(smap.frame.cell_to_world(rc), edges)
