"""The synthetic expert of the SuReNav benchmark: a context-aware pedestrian and its demonstrations.

Public API: ``demonstrate`` (one demonstration), ``map_environments`` (static + semi-static per map),
``build_demos`` (the `demos` data step), ``load_demos`` (read them back), ``demo_graph``
(the region graph a demonstration's relaxed superpixels refer to).
"""

from navlab.surenav.experts.environments import Demonstration, map_environments
from navlab.surenav.experts.pedestrian import CostCache, demonstrate, relaxed_cells
from navlab.surenav.experts.personas import PERSONAS, Persona
from navlab.surenav.experts.store import MapDemos, build_demos, demo_graph, load_demos

__all__ = ["PERSONAS", "CostCache", "Demonstration", "MapDemos", "Persona", "build_demos", "demo_graph",
           "demonstrate", "load_demos", "map_environments", "relaxed_cells"]
