"""The quickstart's one table: grid A* on a real OSM map, checked against an independent Dijkstra.

Why it exists: a pipeline check a new user runs first (no paper reports it); its rows say whether A*
reached every reachable query at the Dijkstra cost, which is what the shared planner must do.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from navlab.maps.semantic_map import SemanticMap
from navlab.metrics.tables import Table


def quickstart_table(city: SemanticMap, results: Sequence[dict]) -> Table:
    """One row over ``results`` (per query: ``path`` from grid A*, its Dijkstra ``reference`` cost, and the
    ``soft_fraction`` of its cells on soft-constrained labels; ``path.cells`` is None where unreached)."""
    reached = [r for r in results if r["path"].cells is not None]
    gaps = [abs(r["path"].cost - r["reference"]) / r["reference"] for r in reached]
    row = {
        "method": "grid A* (8-connected)",
        "queries": len(results),
        "reached": len(reached),
        "mean_cost": float(np.mean([r["path"].cost for r in reached])) if reached else None,
        "max_relative_gap_to_dijkstra": float(max(gaps)) if gaps else None,
        "mean_expansions": float(np.mean([r["path"].expansions for r in reached])) if reached else None,
        "mean_soft_fraction": float(np.mean([r["soft_fraction"] for r in reached])) if reached else None,
    }
    notes = (f"Real OSM map {city.name} at {city.frame.resolution} m/px; A* costs checked against MCP_Geometric "
             "Dijkstra. No paper reports this table.")
    return Table("quickstart_astar", "none (pipeline check)", list(row), [row], [], notes)
