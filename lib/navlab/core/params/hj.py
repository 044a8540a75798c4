"""params.yaml `hj`: parameters of the hj track (HJ reachability-guided search).

`hj.grids` fixes everything the precomputed value functions depend on: the robot and human models, the
solver scheme, and per value function the grid shape, extent and horizon. The grids are rebuilt by the
`hj_grids` DVC stage whenever this section changes (their metadata records it; see navlab.hj.grids).
"""

from __future__ import annotations

from typing import Annotated, Literal

from navlab.core.params.fields import between, section
from navlab.core.params.hj_dynamic import DynamicParams, SensitivityParams


@section
class RobotParams:
    """4D Dubins car (x, y, v, θ), v ∈ [v_min, v_max], controls a ∈ [accel_min, accel_max],
    ω ∈ [-omega_max, omega_max]. v_min < 0: the car reverses (paper Sec. VII-A, Fig. 6); 0: forward only."""

    radius_m: Annotated[float, between(0.01, 2.0)]
    # above -v_max (constraints.cross_section_problems): |v| <= v_max keeps Dist and the human BRT's bound valid
    v_min: Annotated[float, between(-10.0, 0.0)]
    v_max: Annotated[float, between(0.01, 10.0)]
    # strictly signed: the lattice's speed changes divide by each (search.state_lattice), the grids need both
    accel_min: Annotated[float, between(-10.0, -0.01)]
    accel_max: Annotated[float, between(0.01, 10.0)]
    omega_max: Annotated[float, between(0.01, 10.0)]


@section
class HumanParams:
    """A point mass moving at a constant speed in a direction it chooses (paper Eq. 20)."""

    speed: Annotated[float, between(0.0, 5.0)]
    radius_m: Annotated[float, between(0.0, 2.0)]


@section
class SolverParams:
    scheme: Literal["upwind1", "eno2", "weno5"]
    rk_order: Annotated[int, between(1, 3)]
    cfl: Annotated[float, between(0.05, 1.0)]


@section
class TTRGridParams:
    """General goal-centred TTR: goal disc at the origin, square domain of half-width half_extent_m."""

    shape: Annotated[tuple[int, ...], between(2, length=4)]  # (x, y, v, θ)
    half_extent_m: Annotated[float, between(0.5, 50.0)]
    goal_radius_m: Annotated[float, between(0.01, 5.0)]
    horizon_s: Annotated[float, between(0.1, 120.0)]  # unreached states get this lower bound
    stall_s: Annotated[float, between(0.01, 120.0)]  # stop once nothing new was reached for this long


@section
class StaticBRTGridParams:
    """Static-map avoid BRT over a whole room (bounds from the room), run to convergence or the horizon."""

    shape: Annotated[tuple[int, ...], between(2, length=4)]  # (x, y, v, θ)
    horizon_s: Annotated[float, between(0.1, 120.0)]  # the most we march; convergence usually stops it earlier
    band_m: Annotated[float, between(0.001, 10.0)]  # converged when the values with |V| < band_m ...
    tolerance_m: Annotated[float, between(1e-6, 1.0)]  # ... move by less than this ...
    window_s: Annotated[float, between(0.01, 10.0)]  # ... over this much horizon


@section
class HumanBRTGridParams:
    """Human-robot BRT in the robot-centric relative frame, square of half-width half_extent_m."""

    shape: Annotated[tuple[int, ...], between(2, length=3)]  # relative (x, y, robot speed), as the dynamics order it
    half_extent_m: Annotated[float, between(0.5, 50.0)]
    horizon_s: Annotated[float, between(0.1, 30.0)]


@section
class MapTTRGridParams:
    """The map-based TTR of Fig. 2: one reach-avoid solve for one goal in one room (static_brt grid shape)."""

    room: Literal["simulation", "long_hallway", "dense_room"]
    goal_xy: Annotated[tuple[float, ...], between(0.0, 20.0, length=2)]


@section
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


@section
class LatticeParams:
    """The Dubins lattice (search.dubins_lattice): speed_levels from hj.grids.robot.v_min to v_max, 0 among
    them, and every a·dt a whole number of levels."""

    dt_s: Annotated[float, between(0.05, 2.0)]
    accelerations: Annotated[tuple[float, ...], between(-10.0, 10.0)]
    turn_rates: Annotated[tuple[float, ...], between(-10.0, 10.0)]
    speed_levels: Annotated[int, between(2, 101)]
    samples_per_step: Annotated[int, between(1, 32)]
    cell_m: Annotated[float, between(0.01, 1.0)]
    heading_bins: Annotated[int, between(4, 720)]


@section
class FIBRTParams:
    """Appendix A, Table X: the forward-invariant human pruner (Eq. 14-18)."""

    dt_s: Annotated[float, between(0.01, 2.0)]
    margin: Annotated[float, between(-1.0, 1.0)]
    gamma_min: Annotated[float, between(0.0, 100.0)]
    gamma_max: Annotated[float, between(0.0, 100.0)]
    k_theta: Annotated[float, between(0.0, 100.0)]
    w_theta: Annotated[float, between(0.0, 1.0)]
    w_dist: Annotated[float, between(0.0, 1.0)]
    d_threshold_m: Annotated[float, between(0.01, 10.0)]


@section
class TaskSetParams:
    """One start, one goal, several initial headings (degrees) in one room (Tables I-IV)."""

    room: Literal["simulation", "long_hallway", "dense_room"]
    start_xy: Annotated[tuple[float, ...], between(0.0, 20.0, length=2)]
    goal_xy: Annotated[tuple[float, ...], between(0.0, 20.0, length=2)]
    headings_deg: Annotated[tuple[float, ...], between(-360.0, 360.0)]


@section
class RandomTasksParams:
    """Table V: random start-goal pairs, separated by an obstacle or at least min_distance_m apart."""

    room: Literal["simulation", "long_hallway", "dense_room"]
    pairs: Annotated[int, between(1, 10000)]
    min_distance_m: Annotated[float, between(0.0, 20.0)]


@section
class ComputeParams:
    """Table VII: calls per component and the paper's input sizes."""

    calls: Annotated[int, between(1, 10**7)]
    heuristic_states: Annotated[int, between(1, 10000)]
    pruner_states: Annotated[int, between(1, 10000)]


@section
class PlannerParams:
    """HJ-guided lattice search and the static-planning experiments (paper Sec. VII-A..C, VII-E)."""

    lattice: LatticeParams
    goal_tolerance_astar_m: Annotated[float, between(0.01, 2.0)]
    goal_tolerance_anastar_m: Annotated[float, between(0.01, 2.0)]
    goal_max_speed: Annotated[float, between(0.0, 10.0)]
    cost_weight: Annotated[float, between(0.0, 1000.0)]  # Nav2-style state cost: dt · (1 + w · exp(-decay · clearance))
    cost_decay_per_m: Annotated[float, between(0.0, 100.0)]
    astar_max_expansions: Annotated[int, between(1)]
    anastar_max_expansions: Annotated[int, between(1)]
    brt_margin_refine: Annotated[tuple[int, ...], between(1, 8, length=4)]
    fi_brt: FIBRTParams
    table1: TaskSetParams
    table2: TaskSetParams
    table3: TaskSetParams
    table4: TaskSetParams
    table5: RandomTasksParams
    table7: ComputeParams


@section
class HJParams:
    seed: Annotated[int, between(0)]
    workers: Annotated[int, between(1, 64)]  # processes running closed-loop runs and sweep points (results do not depend on it)
    grids: GridsParams
    planner: PlannerParams
    dynamic: DynamicParams
    sensitivity: SensitivityParams
