"""params.yaml `hj`: parameters of the hj track (HJ reachability-guided search).

`hj.grids` fixes everything the precomputed value functions depend on: the robot and human models, the
solver scheme, and per value function the grid shape, extent and horizon. The grids are rebuilt by the
`hj_grids` DVC stage whenever this section changes (their metadata records it; see reach.precompute).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from navlab.core.params.fields import between


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
class HJParams:
    grids: GridsParams
