"""params.yaml `hj`: parameters of the hj track (HJ reachability-guided search).

`hj.grids` fixes everything the precomputed value functions depend on: the robot and human models, the
solver scheme, and per value function the grid shape, extent and horizon. The grids are rebuilt by the
`hj_grids` DVC stage whenever this section changes (their metadata records it; see reach.precompute).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from navlab.core.params.fields import between
from navlab.core.params.hj_dynamic import DynamicParams, SensitivityParams


@dataclass(frozen=True)
class RobotParams:
    """4D Dubins car (x, y, v, θ), controls a ∈ [accel_min, accel_max], ω ∈ [-omega_max, omega_max]."""

    radius_m: float = between(0.01, 2.0)
    v_max: float = between(0.01, 10.0)
    accel_min: float = between(-10.0, 0.0)
    accel_max: float = between(0.0, 10.0)
    omega_max: float = between(0.01, 10.0)


@dataclass(frozen=True)
class HumanParams:
    """A point mass moving at a constant speed in a direction it chooses (paper Eq. 20)."""

    speed: float = between(0.0, 5.0)
    radius_m: float = between(0.0, 2.0)


@dataclass(frozen=True)
class SolverParams:
    scheme: Literal["upwind1", "eno2", "weno5"]
    rk_order: int = between(1, 3)
    cfl: float = between(0.05, 1.0)


@dataclass(frozen=True)
class TTRGridParams:
    """General goal-centred TTR: goal disc at the origin, square domain of half-width half_extent_m."""

    shape: tuple[int, ...] = between(2, length=4)  # (x, y, v, θ)
    half_extent_m: float = between(0.5, 50.0)
    goal_radius_m: float = between(0.01, 5.0)
    horizon_s: float = between(0.1, 120.0)  # unreached states get this lower bound
    stall_s: float = between(0.01, 120.0)  # stop once nothing new was reached for this long


@dataclass(frozen=True)
class StaticBRTGridParams:
    """Static-map avoid BRT over a whole room (bounds from the room), run to convergence or the horizon."""

    shape: tuple[int, ...] = between(2, length=4)  # (x, y, v, θ)
    horizon_s: float = between(0.1, 120.0)  # the most we march; convergence usually stops it earlier
    band_m: float = between(0.001, 10.0)  # converged when the values with |V| < band_m ...
    tolerance_m: float = between(1e-6, 1.0)  # ... move by less than this ...
    window_s: float = between(0.01, 10.0)  # ... over this much horizon


@dataclass(frozen=True)
class HumanBRTGridParams:
    """Human-robot BRT in the robot-centric relative frame, square of half-width half_extent_m."""

    shape: tuple[int, ...] = between(2)  # relative state, as the human-robot dynamics order it
    half_extent_m: float = between(0.5, 50.0)
    horizon_s: float = between(0.1, 30.0)


@dataclass(frozen=True)
class MapTTRGridParams:
    """The map-based TTR of Fig. 2: one reach-avoid solve for one goal in one room (static_brt grid shape)."""

    room: Literal["simulation", "long_hallway", "dense_room"]
    goal_xy: tuple[float, ...] = between(0.0, 20.0, length=2)


@dataclass(frozen=True)
class GridsParams:
    device: Literal["cpu", "cuda"]  # where the hj_grids stage solves (not part of a grid's identity)
    compile: bool  # torch.compile the numerical Hamiltonian (same values to round-off; not identity either)
    robot: RobotParams
    human: HumanParams
    solver: SolverParams
    rooms: tuple[Literal["simulation", "long_hallway", "dense_room"], ...]
    ttr: TTRGridParams
    static_brt: StaticBRTGridParams
    human_brt: HumanBRTGridParams
    map_ttr: MapTTRGridParams


@dataclass(frozen=True)
class LatticeParams:
    """The Dubins lattice (search.dubins_lattice): every a·dt must be a whole number of speed levels."""

    dt_s: float = between(0.05, 2.0)
    accelerations: tuple[float, ...] = between(-10.0, 10.0)
    turn_rates: tuple[float, ...] = between(-10.0, 10.0)
    speed_levels: int = between(2, 101)
    samples_per_step: int = between(1, 32)
    cell_m: float = between(0.01, 1.0)
    heading_bins: int = between(4, 720)


@dataclass(frozen=True)
class FIBRTParams:
    """Appendix A, Table X: the forward-invariant human pruner (Eq. 14-18)."""

    dt_s: float = between(0.01, 2.0)
    margin: float = between(-1.0, 1.0)
    gamma_min: float = between(0.0, 100.0)
    gamma_max: float = between(0.0, 100.0)
    k_theta: float = between(0.0, 100.0)
    w_theta: float = between(0.0, 1.0)
    w_dist: float = between(0.0, 1.0)
    d_threshold_m: float = between(0.01, 10.0)


@dataclass(frozen=True)
class TaskSetParams:
    """One start, one goal, several initial headings (degrees) in one room (Tables I-IV)."""

    room: Literal["simulation", "long_hallway", "dense_room"]
    start_xy: tuple[float, ...] = between(0.0, 20.0, length=2)
    goal_xy: tuple[float, ...] = between(0.0, 20.0, length=2)
    headings_deg: tuple[float, ...] = between(-360.0, 360.0)


@dataclass(frozen=True)
class RandomTasksParams:
    """Table V: random start-goal pairs, separated by an obstacle or at least min_distance_m apart."""

    room: Literal["simulation", "long_hallway", "dense_room"]
    pairs: int = between(1, 10000)
    min_distance_m: float = between(0.0, 20.0)


@dataclass(frozen=True)
class ComputeParams:
    """Table VII: calls per component and the paper's input sizes."""

    calls: int = between(1, 10**7)
    heuristic_states: int = between(1, 10000)
    pruner_states: int = between(1, 10000)


@dataclass(frozen=True)
class PlannerParams:
    """HJ-guided lattice search and the static-planning experiments (paper Sec. VII-A..C, VII-E)."""

    lattice: LatticeParams
    goal_tolerance_astar_m: float = between(0.01, 2.0)
    goal_tolerance_anastar_m: float = between(0.01, 2.0)
    goal_max_speed: float = between(0.0, 10.0)
    cost_weight: float = between(0.0, 1000.0)  # Nav2-style state cost: dt · (1 + w · exp(-decay · clearance))
    cost_decay_per_m: float = between(0.0, 100.0)
    astar_max_expansions: int = between(1)
    anastar_max_expansions: int = between(1)
    brt_margin_refine: tuple[int, ...] = between(1, 8, length=4)
    fi_brt: FIBRTParams
    table1: TaskSetParams
    table2: TaskSetParams
    table3: TaskSetParams
    table4: TaskSetParams
    table5: RandomTasksParams
    table7: ComputeParams


@dataclass(frozen=True)
class HJParams:
    seed: int = between(0)
    workers: int = between(1, 64)  # processes running closed-loop runs and sweep points (results do not depend on it)
    grids: GridsParams
    planner: PlannerParams
    dynamic: DynamicParams
    sensitivity: SensitivityParams
