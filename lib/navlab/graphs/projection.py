"""Path <-> region-sequence projection (SuReNav Eq. 5 and the graph plan of Sec. V).

Down: a continuous path X is traced cell by cell (a 4-connected supercover, so no region is skipped
and consecutive regions share a boundary) and mapped to the sequence of regions it visits, X_G, with
consecutive repeats removed. Up: a region sequence becomes waypoints — each region's anchor (its
centroid, moved into the region when the region is bent) and, between consecutive regions, the portal
on their shared boundary.
"""

from __future__ import annotations

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.graphs.region_graph import RegionGraph
from navlab.graphs.superpixels import HARD


def trace_cells(path_xy: np.ndarray, frame: RasterFrame, passable: np.ndarray | None = None) -> np.ndarray:
    """(M, 2) row/col cells a polyline passes through, 4-connected, consecutive repeats removed.

    Where the polyline crosses a cell corner exactly, one of the two side cells is added, a
    ``passable`` one when that mask is given.
    """
    path_xy = np.asarray(path_xy, dtype=float)
    if path_xy.ndim != 2 or path_xy.shape[1] != 2 or len(path_xy) == 0:
        raise ValueError(f"path must be a (K, 2) array of world points, got shape {path_xy.shape}")
    step = frame.resolution / 4
    seg = np.diff(path_xy, axis=0)
    pieces = np.maximum(np.ceil(np.linalg.norm(seg, axis=1) / step), 1).astype(int)
    seg_of = np.repeat(np.arange(len(seg)), pieces)
    frac = (np.arange(pieces.sum()) - np.repeat(np.cumsum(pieces) - pieces, pieces)) / np.repeat(pieces, pieces)
    dense = np.concatenate([path_xy[seg_of] + seg[seg_of] * frac[:, None], path_xy[-1:]]) if len(seg) else path_xy
    cells = frame.world_to_cell(dense)
    cells = cells[np.r_[True, np.any(cells[1:] != cells[:-1], axis=1)]]
    # a diagonal step touches two cells only at a corner: pass through one of the side cells
    diagonal = np.all(cells[1:] != cells[:-1], axis=1)
    side = np.stack([cells[1:, 0], cells[:-1, 1]], axis=1)[diagonal]
    if passable is not None:
        other = np.stack([cells[:-1, 0], cells[1:, 1]], axis=1)[diagonal]
        ok = frame.contains(side)
        ok[ok] = passable[side[ok, 0], side[ok, 1]]
        side = np.where(ok[:, None], side, other)
    return np.insert(cells, np.nonzero(diagonal)[0] + 1, side, axis=0)


def path_to_regions(graph: RegionGraph, path_xy: np.ndarray) -> np.ndarray:
    """X_G of Eq. (5): node indices the path visits, in order, consecutive repeats removed.

    Raises ValueError when the path enters a hard region or leaves the map.
    """
    cells = trace_cells(path_xy, graph.frame, passable=graph.superpixels != HARD)
    inside = graph.frame.contains(cells)
    if not inside.all():
        raise ValueError(f"path leaves the map at cell {tuple(cells[~inside][0])}; clip it to the map frame")
    nodes = graph.node_raster[cells[:, 0], cells[:, 1]]
    if (nodes < 0).any():
        raise ValueError(f"path enters a hard region at cell {tuple(cells[nodes < 0][0])}")
    return nodes[np.r_[True, nodes[1:] != nodes[:-1]]]


def regions_to_waypoints(graph: RegionGraph, sequence: np.ndarray, portals: bool = True) -> np.ndarray:
    """World waypoints (M, 2) of a region sequence: anchors, with shared-boundary portals in between.

    Consecutive regions must be graph neighbours when ``portals`` is asked for.
    """
    sequence = np.asarray(sequence, dtype=np.int64)
    points = graph.anchor[sequence]
    if not portals or len(sequence) < 2:
        return points
    a, b = np.minimum(sequence[:-1], sequence[1:]), np.maximum(sequence[:-1], sequence[1:])
    n = graph.num_nodes
    keys = graph.edges[:, 0] * n + graph.edges[:, 1]
    want = a * n + b
    where = np.searchsorted(keys, want)
    found = (where < len(keys)) & (keys[np.minimum(where, len(keys) - 1)] == want)
    if not found.all():
        i = int(np.nonzero(~found)[0][0])
        raise ValueError(f"regions {sequence[i]} and {sequence[i + 1]} are not neighbours in the graph")
    out = np.empty((2 * len(sequence) - 1, 2))
    out[0::2] = points
    out[1::2] = graph.portal[where]
    return out
