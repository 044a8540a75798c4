"""params.yaml `surenav.benchmark`: the SuReNav benchmark's episodes, executor, baselines and metrics
(Sec. V-VII: Algorithm 1, Table I, Fig. 4)."""

from __future__ import annotations

from dataclasses import dataclass

from navlab.core.params.fields import between


@dataclass(frozen=True)
class EpisodeParams:
    """The safety-efficiency set: start-goal pairs per test city and the per-map aggregated perturbation."""
    per_city: int = between(1)  # start-goal pairs per test city (the paper: 100)
    min_distance_m: float = between(1.0)  # straight-line start-goal distance range (the paper: 30-200 m)
    max_distance_m: float = between(1.0)
    max_seeds: int = between(1)  # superpixel seeds perturbed along each OSRM route ("up to three")
    obstacle_probability: float = between(0.0, 1.0)  # new obstacle (hard) vs obfuscated prior (soft label)
    endpoint_clearance_m: float = between(0.0)  # no perturbation this close to a start or a goal


@dataclass(frozen=True)
class ExecutorParams:
    """Algorithm 1's walker."""
    sensor_radius_m: float = between(0.0)  # true labels within this distance are observed each step
    step_m: float = between(0.0)  # distance walked along the plan between two observations (< sensor radius)
    max_steps: int = between(1)  # step limit: a walker still under way after this many steps has failed
    window_margin_m: float = between(0.0)  # an episode plays in the start-goal box grown by this much


@dataclass(frozen=True)
class RCRParams:
    """Kim et al. 2024's rule-based scoring: a fixed label-to-risk table plus the distance to the goal."""
    label_risk: dict[str, float]  # one 0-1 risk per soft label
    goal_weight: float = between(0.0)  # weight of (region-to-goal distance / current-to-goal distance)


@dataclass(frozen=True)
class BenchmarkParams:
    seed: int = between(0)
    episodes: EpisodeParams
    executor: ExecutorParams
    unit_risk: dict[str, float]  # total-risk weights per free/soft label (the paper: mean LLM scores)
    dstar_cost_floor: float = between(0.0, 1.0)  # D* Lite: the 0-1 scaled label cost is lifted onto [floor, 1]
    rcr: RCRParams
    bootstrap_samples: int = between(1)  # resamples of environments for each 95% interval
    workers: int = between(1)  # processes running episodes side by side (the outcomes do not depend on it)
    behaviour_candidates: int = between(1)  # Fig. 5: first episodes per city among which the shown one is picked
