"""params.yaml `surenav.benchmark`: the SuReNav benchmark's episodes, executor, baselines and metrics
(Sec. V-VII: Algorithm 1, Table I, Fig. 4)."""

from __future__ import annotations

from typing import Annotated

from navlab.core.params.fields import between, section


@section
class EpisodeParams:
    """The safety-efficiency set: start-goal pairs per test city and the per-map aggregated perturbation."""
    per_city: Annotated[int, between(1)]  # start-goal pairs per test city (the paper: 100)
    min_distance_m: Annotated[float, between(1.0)]  # straight-line start-goal distance range (the paper: 30-200 m)
    max_distance_m: Annotated[float, between(1.0)]
    max_seeds: Annotated[int, between(1)]  # superpixel seeds perturbed along each OSRM route ("up to three")
    obstacle_probability: Annotated[float, between(0.0, 1.0)]  # new obstacle (hard) vs obfuscated prior (soft label)
    endpoint_clearance_m: Annotated[float, between(0.0)]  # no perturbation this close to a start or a goal


@section
class ExecutorParams:
    """Algorithm 1's walker."""
    sensor_radius_m: Annotated[float, between(0.0)]  # true labels within this distance are observed each step
    step_m: Annotated[float, between(0.0)]  # distance walked along the plan between two observations (< sensor radius)
    max_steps: Annotated[int, between(1)]  # step limit: a walker still under way after this many steps has failed
    window_margin_m: Annotated[float, between(0.0)]  # an episode plays in the start-goal box grown by this much


@section
class RCRParams:
    """Kim et al. 2024's rule-based scoring: a fixed label-to-risk table plus the distance to the goal."""
    label_risk: dict[str, float]  # one 0-1 risk per soft label
    goal_weight: Annotated[float, between(0.0)]  # weight of (region-to-goal distance / current-to-goal distance)


@section
class BenchmarkParams:
    seed: Annotated[int, between(0)]
    episodes: EpisodeParams
    executor: ExecutorParams
    unit_risk: dict[str, float]  # total-risk weights per free/soft label (the paper: mean LLM scores)
    risk_ratings: dict[str, dict[str, float]]  # other rating sets Fig. 4's risk claims are decided under (ours)
    dstar_cost_floor: Annotated[float, between(0.0, 1.0)]  # D* Lite: the 0-1 scaled label cost is lifted onto [floor, 1]
    rcr: RCRParams
    bootstrap_samples: Annotated[int, between(1)]  # resamples of environments for each 95% interval
    workers: Annotated[int, between(1)]  # processes running episodes side by side (the outcomes do not depend on it)
    behaviour_candidates: Annotated[int, between(1)]  # Fig. 5: first episodes per city among which the shown one is picked
