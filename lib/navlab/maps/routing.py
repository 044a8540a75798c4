"""Pedestrian routing over a walkable network (the role OSRM's foot profile plays in SuReNav Sec. VI-A).

Routes give the subgoal sequences and the perturbation seeds of the benchmark. The router is networkx
Dijkstra over edge lengths; start and goal snap to their nearest network nodes. Because the network
went through ``network.restrict_to_map``, a route never enters a hard cell. ``maps.osrm`` runs OSRM
itself over the same network (for comparison with the paper's set-up); this router is the one the
benchmark uses, for real and procedural maps alike, since it needs no server.
"""

from __future__ import annotations

from dataclasses import dataclass

import networkx as nx
import numpy as np
from scipy.spatial import cKDTree

from navlab.maps.network import WalkableNetwork


@dataclass(frozen=True)
class Route:
    nodes: np.ndarray  # (K,) network node indices from start to goal
    xy: np.ndarray  # (K, 2) their world positions, metres
    length_m: float  # along the network, excluding the snaps to start and goal


class Router:
    """Shortest walking routes on one network."""

    def __init__(self, network: WalkableNetwork):
        if len(network.xy) == 0:
            raise ValueError("the walkable network is empty: the map has no sidewalk, path or crosswalk")
        self.network = network
        self.graph = nx.Graph()
        self.graph.add_nodes_from(range(len(network.xy)))
        self.graph.add_weighted_edges_from(
            zip(network.edges[:, 0].tolist(), network.edges[:, 1].tolist(), network.lengths.tolist(), strict=True))
        self._tree = cKDTree(network.xy)

    def nearest_node(self, xy: np.ndarray) -> int:
        return int(self._tree.query(np.asarray(xy, dtype=float))[1])

    def route(self, start_xy: np.ndarray, goal_xy: np.ndarray) -> Route | None:
        """The shortest route between the nodes nearest to start and goal, or None if they are not connected."""
        source, target = self.nearest_node(start_xy), self.nearest_node(goal_xy)
        try:
            length, path = nx.single_source_dijkstra(self.graph, source, target, weight="weight")
        except nx.NetworkXNoPath:
            return None
        nodes = np.asarray(path, dtype=np.int64)
        return Route(nodes, self.network.xy[nodes], float(length))

    def components(self) -> list[np.ndarray]:
        """Node indices of each connected piece of the network, largest first."""
        parts = sorted((sorted(c) for c in nx.connected_components(self.graph)), key=lambda c: (-len(c), c[0]))
        return [np.asarray(c, dtype=np.int64) for c in parts]
