"""params.yaml `stack`: the navigation stack that joins the three papers (issue 64) and its ablation."""

from __future__ import annotations

from typing import Annotated, Literal

from navlab.core.params.fields import between, section


@section
class StackParams:
    seed: Annotated[int, between(0)]
    episodes: Annotated[int, between(1, 10_000)]  # cycled over the five SuReNav test tiles
    route_m: tuple[float, float]  # straight-line start-goal distance range (m)
    box_margin_m: Annotated[float, between(4.0)]  # the episode's box: the walkway route's box grown by this much
    terrain_of_label: dict[str, str]  # the terrain photograph class painted on each SuReNav label
    preferences: tuple[Literal["realistic", "inverted"], ...]  # the operator's order, cycled over the episodes
    terrain_weight: Annotated[float, between(0.0)]  # w: a cell costs 1 + w c per metre (c in [0, 1], PACER's cost)
    pedestrians: Annotated[int, between(0, 20)]  # walkers on the walkway, head-on to the robot
    window_m: Annotated[float, between(4.0, 40.0)]  # side of the local planner's square window around the robot
    lookahead_m: Annotated[float, between(0.5, 20.0)]  # the local goal: this far along the route ahead
    window_resolution_m: Annotated[float, between(0.02, 0.5)]  # the local map's cells
    max_expansions: Annotated[int, between(100)]  # per local re-plan (a deterministic budget, not a time limit)
    replan_hz: Annotated[float, between(1.0, 100.0)]
    timeout_s: Annotated[float, between(1.0)]
    workers: Annotated[int, between(1, 64)]
