"""params.yaml `quickstart`: the end-to-end notebook (real OSM map -> grid A* -> report)."""

from __future__ import annotations

from typing import Annotated, Literal

from navlab.core.params.fields import between, section


@section
class QuickstartParams:
    city: Literal["helsinki", "kouvola", "monaco"]
    resolution_m: Annotated[float, between(0.25, 10.0)]
    queries: Annotated[int, between(1, 1000)]
    min_distance_m: Annotated[float, between(1.0)]
    max_distance_m: Annotated[float, between(1.0)]
    soft_cost: Annotated[dict[str, float], between(1.0)]  # per soft label: cost multiplier per metre
