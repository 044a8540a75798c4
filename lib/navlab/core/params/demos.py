"""params.yaml `data.demos`: the synthetic expert demonstrations of the SuReNav benchmark (Sec. VI-A)."""

from __future__ import annotations

from typing import Annotated

from navlab.core.params.fields import between, section


@section
class DemosParams:
    seed: Annotated[int, between(0)]
    pairs_per_map: Annotated[int, between(1)]  # train/val maps: start-goal pairs, each a static + a semi-static demo
    test_pairs_per_map: Annotated[int, between(1)]  # test maps: semi-static human-likeness environments
    min_distance_m: Annotated[float, between(1.0)]  # straight-line start-goal distance range
    max_distance_m: Annotated[float, between(1.0)]
    window_margin_m: Annotated[float, between(0.0)]  # the expert plans inside the start-goal box grown by this much
    endpoint_clearance_m: Annotated[float, between(0.0)]  # no perturbation this close to the start or the goal
    obstacle_probability: Annotated[float, between(0.0, 1.0)]  # new obstacle (hard) vs obfuscated prior (soft label)
