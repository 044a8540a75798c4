"""navlab.graphs: SLIC superpixel region-adjacency graphs, path <-> region projection, incremental updates.

Public API: ``label_consistent_slic``, ``build_region_graph``/``superpixel_graph`` -> ``RegionGraph``
(``features``, ``to_pyg()``), ``path_to_regions``, ``regions_to_waypoints``, ``update_graph``.
"""

from navlab.graphs.incremental import update_graph
from navlab.graphs.projection import path_to_regions, regions_to_waypoints, trace_cells
from navlab.graphs.region_graph import RegionGraph, build_region_graph, superpixel_graph
from navlab.graphs.superpixels import HARD, label_consistent_slic, traversable_mask

__all__ = ["HARD", "RegionGraph", "build_region_graph", "label_consistent_slic", "path_to_regions",
           "regions_to_waypoints", "superpixel_graph", "trace_cells", "traversable_mask", "update_graph"]
