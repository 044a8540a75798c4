"""The superpixel region-adjacency graph G = (V, E) of SuReNav (Sec. IV-A/B, Eq. 5-7).

Nodes are superpixels of free+soft space; an edge joins two superpixels whose shared boundary (the
"portal" a walker passes through) is at least τ metres long — the boundary affinity H of Eq. (5).
Node features are f_SR = [one-hot label, start indicator, goal indicator] (Eq. 7) and f_GR = the
centroid in metres; an edge carries the centroid distance d(r_i, r_j).

Superpixel ids in the raster need not be 0..N-1: an incremental update keeps the ids of untouched
regions, so node ``i`` is the raster id ``region_ids[i]`` (sorted).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.core.labels import NUM_LABELS
from navlab.core.params.surenav_graph import GraphParams
from navlab.graphs.superpixels import HARD, label_consistent_slic


@dataclass(frozen=True)
class RegionGraph:
    superpixels: np.ndarray  # (rows, cols) int32 raster ids, HARD (-1) outside free+soft space
    frame: RasterFrame
    region_ids: np.ndarray  # (N,) sorted raster id of each node
    node_label: np.ndarray  # (N,) core.labels id of each node
    centroid: np.ndarray  # (N, 2) world (x, y) metres
    anchor: np.ndarray  # (N, 2) world point of the node's cell nearest its centroid (inside the node)
    area: np.ndarray  # (N,) square metres
    edges: np.ndarray  # (E, 2) node indices, i < j
    edge_length: np.ndarray  # (E,) centroid distance, metres
    edge_affinity: np.ndarray  # (E,) shared boundary length, metres
    portal: np.ndarray  # (E, 2) world point on the shared boundary, nearest its mean
    start_node: int = -1
    goal_node: int = -1

    @property
    def num_nodes(self) -> int:
        return len(self.region_ids)

    @cached_property
    def node_raster(self) -> np.ndarray:
        """(rows, cols) node index of every cell, -1 in hard space (computed once per graph)."""
        out = np.full(self.superpixels.shape, -1, dtype=np.int64)
        inside = self.superpixels != HARD
        out[inside] = np.searchsorted(self.region_ids, self.superpixels[inside])
        return out

    def node_at(self, xy: np.ndarray) -> np.ndarray:
        """Node index of each world point (…, 2); -1 for hard space or outside the map."""
        rc = self.frame.world_to_cell(xy)
        inside = self.frame.contains(rc)
        out = np.full(rc.shape[:-1], -1, dtype=np.int64)
        sp = self.superpixels[rc[inside][:, 0], rc[inside][:, 1]]
        nodes = np.searchsorted(self.region_ids, sp)
        out[inside] = np.where(sp == HARD, -1, nodes)
        return out

    def with_endpoints(self, start_xy: np.ndarray, goal_xy: np.ndarray) -> RegionGraph:
        """The same graph with start and goal nodes set (the indicators of Eq. 7)."""
        start, goal = int(self.node_at(np.asarray(start_xy))), int(self.node_at(np.asarray(goal_xy)))
        for name, node, xy in (("start", start, start_xy), ("goal", goal, goal_xy)):
            if node < 0:
                raise ValueError(f"{name} {tuple(np.round(xy, 2))} lies in a hard region or outside the map; "
                                 f"pick a {name} on free or soft ground")
        return replace(self, start_node=start, goal_node=goal)

    @property
    def features(self) -> np.ndarray:
        """(N, NUM_LABELS + 2) float32 f_SR of Eq. (7)."""
        x = np.zeros((self.num_nodes, NUM_LABELS + 2), dtype=np.float32)
        x[np.arange(self.num_nodes), self.node_label] = 1.0
        if self.start_node >= 0:
            x[self.start_node, NUM_LABELS] = 1.0
        if self.goal_node >= 0:
            x[self.goal_node, NUM_LABELS + 1] = 1.0
        return x

    def neighbours(self) -> list[np.ndarray]:
        """Adjacency lists (node -> sorted neighbour indices)."""
        both = np.concatenate([self.edges, self.edges[:, ::-1]])
        both = both[np.lexsort((both[:, 1], both[:, 0]))]
        return np.split(both[:, 1], np.searchsorted(both[:, 0], np.arange(1, self.num_nodes)))

    def to_pyg(self):
        """A torch_geometric ``Data``: x = f_SR, pos = centroids, both edge directions, edge_attr = length."""
        import torch
        from torch_geometric.data import Data

        both = np.concatenate([self.edges, self.edges[:, ::-1]]).T
        length = np.concatenate([self.edge_length, self.edge_length])
        return Data(x=torch.from_numpy(self.features), pos=torch.from_numpy(self.centroid.astype(np.float32)),
                    edge_index=torch.from_numpy(np.ascontiguousarray(both, dtype=np.int64)),
                    edge_attr=torch.from_numpy(length.astype(np.float32)[:, None]),
                    label=torch.from_numpy(self.node_label.astype(np.int64)))


def build_region_graph(superpixels: np.ndarray, labels: np.ndarray, frame: RasterFrame,
                       tau: float) -> RegionGraph:
    """The graph of a superpixel raster (label_consistent_slic or an incremental update of one)."""
    if superpixels.shape != labels.shape or superpixels.shape != frame.shape:
        raise ValueError(f"superpixels {superpixels.shape}, labels {labels.shape} and frame {frame.shape} "
                         "must have one shape")
    res = frame.resolution
    inside = superpixels != HARD
    region_ids, node_of = np.unique(superpixels[inside], return_inverse=True)
    n = len(region_ids)
    nodes = np.full(superpixels.shape, -1, dtype=np.int64)
    nodes[inside] = node_of

    rows, cols = np.nonzero(inside)
    node_idx = nodes[rows, cols]
    count = np.bincount(node_idx, minlength=n).astype(float)
    centre_rc = np.stack([np.bincount(node_idx, rows, n), np.bincount(node_idx, cols, n)], axis=1) / count[:, None]
    node_label = np.zeros(n, dtype=np.int64)
    node_label[node_idx] = labels[rows, cols]
    # anchor: the node's own cell closest to its centroid (the centroid of a bent region may lie outside it)
    d2 = (rows - centre_rc[node_idx, 0]) ** 2 + (cols - centre_rc[node_idx, 1]) ** 2
    order = np.lexsort((d2, node_idx))
    first = order[np.searchsorted(node_idx[order], np.arange(n))]
    anchor = frame.cell_to_world(np.stack([rows[first], cols[first]], axis=1))

    edges, affinity, portal = _shared_boundaries(nodes, frame)
    keep = affinity >= tau - 1e-9
    edges, affinity, portal = edges[keep], affinity[keep], portal[keep]
    centroid = np.stack([frame.origin[0] + (centre_rc[:, 1] + 0.5) * res,
                         frame.origin[1] + (centre_rc[:, 0] + 0.5) * res], axis=1)
    length = np.linalg.norm(centroid[edges[:, 0]] - centroid[edges[:, 1]], axis=1)
    return RegionGraph(superpixels=superpixels.astype(np.int32), frame=frame, region_ids=region_ids.astype(np.int64),
                       node_label=node_label, centroid=centroid, anchor=anchor, area=count * res * res,
                       edges=edges, edge_length=length, edge_affinity=affinity, portal=portal)


def _shared_boundaries(nodes: np.ndarray, frame: RasterFrame):
    """Every pair of 4-adjacent nodes: (E, 2) pairs i < j, boundary length (m), portal point (E, 2)."""
    res = frame.resolution
    pairs, mids = [], []
    for a, b, dr, dc in ((nodes[:, :-1], nodes[:, 1:], 0, 1), (nodes[:-1, :], nodes[1:, :], 1, 0)):
        cut = (a >= 0) & (b >= 0) & (a != b)
        r, c = np.nonzero(cut)
        pairs.append(np.stack([np.minimum(a[cut], b[cut]), np.maximum(a[cut], b[cut])], axis=1))
        mids.append(np.stack([r + 0.5 + 0.5 * dr, c + 0.5 + 0.5 * dc], axis=1))  # (row, col) of the shared edge
    pairs, mids = np.concatenate(pairs), np.concatenate(mids)
    if len(pairs) == 0:
        return np.zeros((0, 2), dtype=np.int64), np.zeros(0), np.zeros((0, 2))
    n = int(nodes.max()) + 1
    edges, inv, counts = np.unique(pairs[:, 0] * n + pairs[:, 1], return_inverse=True, return_counts=True)
    edges = np.stack([edges // n, edges % n], axis=1)
    mean = np.stack([np.bincount(inv, mids[:, 0]), np.bincount(inv, mids[:, 1])], axis=1) / counts[:, None]
    d2 = ((mids - mean[inv]) ** 2).sum(axis=1)
    order = np.lexsort((d2, inv))
    nearest = mids[order[np.searchsorted(inv[order], np.arange(len(edges)))]]
    portal = np.stack([frame.origin[0] + nearest[:, 1] * res, frame.origin[1] + nearest[:, 0] * res], axis=1)
    return edges, counts * res, portal


def superpixel_graph(labels: np.ndarray, frame: RasterFrame, settings: GraphParams) -> RegionGraph:
    """SLIC + graph in one call, with the `surenav.graph` settings of params.yaml."""
    superpixels = label_consistent_slic(labels, settings.target_nodes, settings.compactness)
    return build_region_graph(superpixels, labels, frame, settings.tau_m)
