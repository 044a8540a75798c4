"""Context-dependent cost rasters of the synthetic pedestrian: what one metre of ground costs *here*.

A fixed label->cost table cannot say "cut this small corner of grass but do not cross that lawn":
the cost of a grass cell depends on how deep inside its lawn it lies (distance transform) and on
the size of its patch (connected-component area). Roads are either forbidden (the walker looks for a
crosswalk) or allowed at a persona price (the walker has decided to jaywalk); pedestrian.py decides
which, by comparing the two routes.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from navlab.core.labels import LABELS, label_id
from navlab.surenav.experts.personas import Persona

GRASS, ROAD = label_id("grass"), label_id("road")


def grass_cost(labels: np.ndarray, resolution: float, persona: Persona) -> np.ndarray:
    """Cost per metre of each grass cell (nan elsewhere): cheap near an edge or in a small patch."""
    grass = labels == GRASS
    depth = ndimage.distance_transform_edt(grass) * resolution  # metres to the nearest non-grass cell
    patches, _ = ndimage.label(grass)
    area = np.bincount(patches.ravel()) * resolution**2
    small = area[patches] < persona.small_patch_m2
    cheap = (depth <= persona.grass_edge_m) | small
    return np.where(grass, np.where(cheap, persona.grass_edge_cost, persona.lawn_cost), np.nan)


def expert_cost(labels: np.ndarray, resolution: float, persona: Persona, *, jaywalk: bool) -> np.ndarray:
    """The persona's cost per metre of every cell (inf = will not walk there)."""
    per_label = {"sidewalk": 1.0, "crosswalk": persona.crosswalk_cost,
                 "road": persona.road_cost if jaywalk else np.inf,
                 "living_street": persona.living_street_cost, "parking": persona.parking_cost,
                 "grass": np.nan, "rough_terrain": persona.rough_cost}
    table = np.array([per_label.get(lab.name, np.inf) for lab in LABELS])
    cost = table[labels]
    grass = labels == GRASS
    if grass.any():
        cost[grass] = grass_cost(labels, resolution, persona)[grass]
    return cost
