"""params.yaml `hj.dynamic`: the closed-loop experiments of the HJ-search paper (Sec. VII-D, VIII; Tables VI,
VIII, IX). Coordinates the paper's text lacks are ours and carry a comment in params.yaml saying why.

Points are (x, y) in metres in the room's frame (origin at a corner, x along the 9.6 m side); a robot start
is (x, y, heading in degrees), at rest.
"""

from __future__ import annotations

from typing import Annotated, Literal

from navlab.core.params.fields import between, section

Point = tuple[float, ...]


@section
class ClosedLoopParams:
    """The receding-horizon loop (hj.receding_horizon.SimSettings) and the planner budget per re-plan."""

    replan_hz: Annotated[float, between(0.1, 100.0)]  # paper Sec. VIII-A: 12 Hz
    control_hz: Annotated[float, between(0.1, 1000.0)]  # paper: 25 Hz
    algorithm: Literal["A*", "ANA*"]  # the paper's robot runs ANA* (Sec. VIII)
    max_expansions: Annotated[int, between(1)]  # per re-plan: deterministic, so a seeded run gives the same numbers
    rest_periods: Annotated[int, between(1, 1000)]  # humans in view: a waiting car re-runs its search over this many periods (hj.lattice_policy)
    rest_bound: Annotated[float, between(1.0, 1e9)]  # none in view: a waiting car improves an ANA* plan with a larger bound
    reuse_plan: bool  # a re-plan out of budget keeps the car's plan when it re-checks safe (hj.lattice_policy)
    plan_switch_gain_s: Annotated[float, between(0.0, 60.0)]  # with reuse_plan: a new plan must arrive this much sooner
    pose_allowance_sigmas: Annotated[float, between(0.0, 10.0)]  # static pruners' threshold raised by this x pose noise std
    heuristic: Literal["Dist", "TTR"]  # Tables VI and IX (the paper's method: TTR)
    goal_tolerance_m: Annotated[float, between(0.01, 2.0)]  # a trip ends within this of its goal
    trip_timeout_s: Annotated[float, between(1.0, 3600.0)]
    deadlock_s: Annotated[float, between(0.5, 600.0)]  # no progress of deadlock_progress_m for this long: deadlock
    deadlock_progress_m: Annotated[float, between(0.01, 10.0)]
    human_noise_m: Annotated[float, between(0.0, 1.0)]  # std of each observed human position (the ZED 2 detector)
    velocity_window_s: Annotated[float, between(0.01, 10.0)]  # a human's velocity: its observed displacement over this long
    human_prediction_s: Annotated[float, between(0.0, 60.0)]  # FI/FS: humans predicted at their velocity up to this (0: frozen)
    prediction_variant_s: Annotated[float, between(0.0, 60.0)]  # Tables VI, IX: FI/FS rows predicting this far (ours; 0: none)


@section
class FaceToFaceParams:
    robot_start: Annotated[Point, between(-360.0, 360.0, length=3)]  # x, y, heading (deg)
    robot_goal: Annotated[Point, between(0.0, 20.0, length=2)]
    human_start: Annotated[Point, between(0.0, 20.0, length=2)]
    human_goal: Annotated[Point, between(0.0, 20.0, length=2)]


@section
class ZigZagParams:
    robot_start: Annotated[Point, between(-360.0, 360.0, length=3)]
    robot_goals: tuple[Point, ...]  # visited in order, then back to the first: one cycle per run
    human_start: Annotated[Point, between(0.0, 20.0, length=2)]
    human_goal: Annotated[Point, between(0.0, 20.0, length=2)]
    spawn_clear_m: Annotated[float, between(0.0, 10.0)]  # a new human enters once the robot is this far from human_start


@section
class Table6Params:
    """Sec. VII-D: non-reactive humans in an open room; FI-BRT vs FS-BRT vs OBS."""

    room: Literal["open", "simulation", "long_hallway", "dense_room"]
    runs: Annotated[int, between(1, 1000)]  # per cell (paper: 5)
    pose_noise_m: Annotated[float, between(0.0, 1.0)]  # simulation: the robot knows its pose (0)
    human_noise_m: Annotated[float, between(0.0, 1.0)]  # simulation: exact human positions (0); replaces closed_loop's
    human_start_jitter_m: Annotated[float, between(0.0, 5.0)]  # run r: the humans start up to this far along their line
    face_to_face: FaceToFaceParams
    zig_zag: ZigZagParams
    detour_lateral_m: Annotated[float, between(0.01, 2.0)]  # Fig. 8: the detour starts when the car leaves the line by this


@section
class Table8Params:
    """Sec. VIII-B: static rooms, cyclic patrols, heuristic x pruner; goals are the rooms' named goals."""

    cycles: Annotated[int, between(1, 1000)]  # paper: 3 (9 trips in the Long Hallway, 6 in the Dense Room)
    runs: Annotated[int, between(1, 1000)]  # seeded repetitions of the whole cell, pooled (paper: 1)
    pose_noise_m: Annotated[float, between(0.0, 1.0)]  # AMCL localisation on the robot
    hallway_route: tuple[str, ...]  # goal names of maps.rooms.long_hallway_room, visited cyclically
    dense_route: tuple[str, ...]
    start_heading_deg: Annotated[float, between(-360.0, 360.0)]


@section
class Table9Params:
    """Sec. VIII-C: patrolling humans (the paper's three rules); FI-BRT vs FS-BRT vs OBS."""

    room: Literal["open", "simulation", "long_hallway", "dense_room"]
    cycles: Annotated[int, between(1, 1000)]  # paper: 3 full patrol cycles
    runs: Annotated[int, between(1, 1000)]  # seeded repetitions of the whole cell (paper: 1)
    human_counts: Annotated[tuple[int, ...], between(1, 2)]
    pose_noise_m: Annotated[float, between(0.0, 1.0)]
    robot_start_heading_deg: Annotated[float, between(-360.0, 360.0)]
    robot_goals: tuple[Point, ...]  # cyclic; the run starts at the first, stopped
    human_pois: tuple[tuple[Point, ...], ...]  # per human, its points of interest (cyclic)


@section
class SensitivityParams:
    """Issue 26: the closed-loop claims whose verdict rests on settings the paper does not state, as curves.
    Every other setting is the tables' own (hj.dynamic); each point is one cached run of the whole cell."""

    budgets: Annotated[tuple[int, ...], between(1)]  # ANA* expansions per re-plan: Table VIII's rooms, its four rows
    replan_hz: Annotated[tuple[float, ...], between(0.1, 100.0)]  # Table VI's scenarios at its own (exact) sensing
    human_noise_m: Annotated[tuple[float, ...], between(0.0, 1.0)]  # Table VI's scenarios at hj.dynamic.closed_loop's rate
    human_prediction_s: Annotated[tuple[float, ...], between(0.0, 60.0)]  # Table VI: FI/FS prune the humans this far ahead
    only: tuple[str, ...]  # run just these points (Point.name); empty: all. Set by `sweep queue`, one per experiment


@section
class DynamicParams:
    seed: Annotated[int, between(0)]  # run r of a cell uses seed + r (noise draws)
    closed_loop: ClosedLoopParams
    table6: Table6Params
    table8: Table8Params
    table9: Table9Params
