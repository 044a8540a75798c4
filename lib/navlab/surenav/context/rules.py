"""The context demonstrator's rules: a relaxation cost Psi (metres) per region, decided from context.

Stated before any measurement, from the paper's own examples (SuReNav Sec. VII, Figs. 3 and 6) and
``shared/notes/anchors.md`` section D. A region gets the first rule that applies:

1. Free ground costs nothing; a crosswalk costs nothing either: 89% of 70,000 observed crossings were
   at marked crosswalks at intersections (FHWA-HRT-13-098).
2. Any soft region bordering a *new* obstacle: ``bypass_m`` (1-4 m). People step round a blocked
   sidewalk onto whatever borders it rather than retrace their steps (MUTCD 6D.01); 87% of parents
   stepped into the road around pavement parking (Living Streets 2021). Paper Fig. 6b: the parking lot
   next to the new obstacle is the one relaxed, not the nearest cheap label.
3. Road with no sidewalk within 12 m: a street one walks along (routers: residential 1.1-1.2x per
   metre without a sidewalk, BRouter / GraphHopper) — surface cost only.
   Road where a sidewalk ends at it or beside a crosswalk (within 8 m): ``crossing_point_m`` (2-6 m),
   the place to cross (paper Fig. 3, left: "crosses a road at the end of a sidewalk").
   Any other road with a sidewalk alongside is mid-block: ``crossing_budget_m`` (60-250 m). Graph A*
   then walks to a farther crossing point unless that detour exceeds the budget, and jaywalks beyond
   it (paper Fig. 3, right; crossings every 80-100 m, mid-block crossing beyond ~180 m between
   signals or ~3 minutes of detour; "pedestrians rarely go out of their way", FHWA-HRT-05-107).
4. Living street: surface cost only (shared space; GraphHopper 1.2).
5. Grass, parking, rough ground: a patch under ``small_patch_m2`` (150-600 m²) is cut through at
   ``small_patch_m`` (2-6 m); in a larger patch, a region touching the walkway is a corner to cut at
   ``corner_cut_m`` (10-30 m) and a region inside it is crossed only as a last resort at ``interior_m``
   (150-400 m) — "cut a small lawn corner but not a large lawn" (paper Fig. 3, middle; desire paths
   cut corners and small patches, Helbing et al. 1997; no area threshold was measured: ours is an
   assumption). Rough ground (untagged yards, scrub, wasteland) pays x2 on the last two: its surface
   is unknown and slower (Tobler 0.6x speed, Kowalsky 2021).

On top, every soft region pays its surface: (multiplier - 1) x its diameter sqrt(area), the mild
per-metre multipliers of real routers (``SURFACE``). Persona tolerances (``personas``) set the ranges.
"""

from __future__ import annotations

import numpy as np

from navlab.core.labels import LABELS, SOFT_IDS, label_id
from navlab.surenav.context.personas import ContextPersona
from navlab.surenav.context.regions import CROSSWALK, LIVING_STREET, ROAD, RegionContext

# cost per metre relative to a sidewalk (anchors D: Valhalla, GraphHopper, BRouter, OSRM foot; Tobler)
SURFACE = {"sidewalk": 1.0, "crosswalk": 1.0, "road": 1.2, "living_street": 1.2, "parking": 1.2, "grass": 1.2,
           "rough_terrain": 1.6}
SURFACE_TABLE = np.array([SURFACE.get(lab.name, np.inf) for lab in LABELS])  # per label id, inf on hard
ROUGH = label_id("rough_terrain")
ROUGH_FACTOR = 2.0  # rule 5: unknown, slower surface


def relaxation_costs(ctx: RegionContext, persona: ContextPersona) -> np.ndarray:
    """(N,) Psi >= 0 of every region under the rules of this module's docstring."""
    soft = np.isin(ctx.label, SOFT_IDS)
    road, grass_like = ctx.label == ROAD, soft & ~np.isin(ctx.label, [ROAD, CROSSWALK, LIVING_STREET])
    factor = np.where(ctx.label == ROUGH, ROUGH_FACTOR, 1.0)
    patch_cost = np.where(ctx.patch_m2 < persona.small_patch_m2, persona.small_patch_m,
                          factor * np.where(ctx.on_walkway, persona.corner_cut_m, persona.interior_m))
    road_cost = np.where(~ctx.by_sidewalk, 0.0,
                         np.where(ctx.crossing_point, persona.crossing_point_m, persona.crossing_budget_m))
    rule = np.select([~soft | (ctx.label == CROSSWALK), ctx.beside_obstacle, road, grass_like],
                     [0.0, persona.bypass_m, road_cost, patch_cost], default=0.0)  # living street: surface only
    surface = np.where(soft, (SURFACE_TABLE[ctx.label] - 1.0) * np.sqrt(ctx.area_m2), 0.0)
    return rule + surface
