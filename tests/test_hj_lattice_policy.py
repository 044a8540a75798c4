"""The HJ-guided lattice planner as the simulator's policy: the OBS row treats a human as a disc obstacle."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.params import load_params
from navlab.hj.guidance import dist_heuristic
from navlab.hj.lattice_policy import LatticePolicy
from navlab.hj.planning import lattice_spec
from navlab.hj.pruners import obs_pruner
from navlab.hj.receding_horizon import Evasion, Observation
from navlab.maps.rooms import load_room
from navlab.search.dubins_lattice import densify, first_step, integrate

ROBOT_R, HUMAN_R = 0.285, 0.3
START, GOAL, HUMAN = np.array([0.6, 4.6, 0.0, 0.0]), (3.8, 4.6), np.array([[2.2, 5.0]])


def _policy(mode):
    spec, room = lattice_spec(load_params("smoke")), load_room("simulation")
    return spec, LatticePolicy(spec, room, lambda g: dist_heuristic(g, spec.v_max, 0.2), obs_pruner(room, ROBOT_R),
                               goal_tolerance=0.2, goal_max_speed=0.25, max_expansions=200_000, human_mode=mode)


def _gap(mode):
    """Closest approach of the densified plan to the human, along the north aisle of the simulation room."""
    spec, policy = _policy(mode)
    commands = policy(Observation(0.0, START, GOAL, HUMAN, np.zeros((1, 2))))
    assert len(commands) > 0, f"{mode}: no plan in the open aisle"
    path = densify(spec, START, commands)
    return float(np.hypot(*(path[:, :2] - HUMAN[0]).T).min())


def test_obs_mode_keeps_the_robot_disc_off_the_observed_human():
    assert _gap("none") < ROBOT_R + HUMAN_R  # ignoring the human, the straight aisle run touches it
    assert _gap("obs") > ROBOT_R + HUMAN_R


def test_a_start_in_collision_returns_no_plan_and_bad_modes_are_named():
    _, policy = _policy("obs")
    assert len(policy(Observation(0.0, np.array([2.2, 4.8, 0.0, 0.0]), GOAL, HUMAN, np.zeros((1, 2))))) == 0
    with pytest.raises(ValueError, match="human_mode"):
        _policy("sideways")
    with pytest.raises(ValueError, match="human-robot BRT"):
        _policy("fi")


def _open_policy(max_expansions=200_000):
    spec, room = lattice_spec(load_params("smoke")), load_room("open")
    return spec, room, LatticePolicy(spec, room, lambda g: dist_heuristic(g, spec.v_max, 0.2),
                                     obs_pruner(room, ROBOT_R), goal_tolerance=0.2, goal_max_speed=0.25,
                                     max_expansions=max_expansions, reuse=True)


def _stops_clear_by_replay(spec, room, state, control) -> bool:
    """The step (a, ω) held for dt from ``state``, then braking straight to rest (a > 0 reversing), densely
    replayed."""
    step = integrate(state, control[0], control[1], spec.dt, 200, spec.v_range)
    end = step[-1]
    brake = min(spec.accelerations) if end[2] >= 0.0 else max(spec.accelerations)
    stop = integrate(end, brake, 0.0, end[2] / -brake, 200, spec.v_range)
    path = np.concatenate([step, stop])
    return bool((room.signed_distance(path[:, 0], path[:, 1], ROBOT_R) > 0.0).all())


def test_without_a_plan_a_car_swerves_where_braking_straight_would_hit_the_wall():
    """``_stop`` against a dense replay, facing the east wall of the open room at 1 m/s from 0.6 to 1.4 m:
    braking straight where that stops clear, else a step after which braking does (and it does), else None
    only where no first step stops clear; the swerve case occurs."""
    spec, room, policy = _open_policy()
    kinds = set()
    for gap in np.linspace(0.6, 1.4, 30):  # steps of 2.8 cm: none on the 1 m stopping distance itself
        state = np.array([room.width - ROBOT_R - gap, 2.7, 1.0, 0.0])
        answer = policy._stop(state)
        straight = _stops_clear_by_replay(spec, room, state, (min(spec.accelerations), 0.0))
        _, controls = first_step(spec, 1.0)
        if answer is None:
            kinds.add("none")
            assert not any(_stops_clear_by_replay(spec, room, state, c) for c in controls)
        elif isinstance(answer, Evasion):
            kinds.add("swerve")
            assert not straight and _stops_clear_by_replay(spec, room, state, answer.commands[0])
        else:
            kinds.add("brake")
            assert len(answer) == 0 and straight
    assert kinds == {"none", "swerve", "brake"}


def test_a_reversing_car_brakes_forwards_to_rest_where_that_stops_clear():
    """Backing up at 0.5 m/s towards the west wall (facing east), 0.1 to 0.5 m from it: ``_stop`` brakes
    straight (a > 0, 0.25 m to rest) where that stops clear by a dense replay, else a first step after which
    braking does, else None; never a step that drives on backwards faster."""
    spec, room, policy = _open_policy()
    assert spec.v_min < 0.0  # params.yaml's car reverses
    kinds = set()
    for gap in np.linspace(0.1, 0.5, 15):
        state = np.array([ROBOT_R + gap, 2.7, -0.5, 0.0])
        answer = policy._stop(state)
        straight = _stops_clear_by_replay(spec, room, state, (max(spec.accelerations), 0.0))
        assert policy._brakes_clear(state[None]) == straight
        if answer is None:
            kinds.add("none")
            assert not any(_stops_clear_by_replay(spec, room, state, c) for c in first_step(spec, -0.5)[1])
        elif isinstance(answer, Evasion):
            kinds.add("step")
            assert not straight and answer.commands[0, 0] >= 0.0
            assert _stops_clear_by_replay(spec, room, state, answer.commands[0])
        else:
            kinds.add("brake")
            assert len(answer) == 0 and straight
    assert {"none", "brake"} <= kinds


def test_a_car_that_cannot_stop_clear_keeps_its_plan_rather_than_brake_into_the_wall():
    _, room, policy = _open_policy(max_expansions=1)  # every re-plan stops at the expansion limit
    state = np.array([room.width - ROBOT_R - 0.5, 2.7, 1.0, 0.0])
    goal = (1.0, 2.7)
    assert policy._stop(state) is None
    turn = np.array([[-0.5, 1.0]] * 8)
    object.__setattr__(policy, "_current", (goal, 0.0, turn))
    assert policy(Observation(0.1, state, goal, np.zeros((0, 2)), np.zeros((0, 2)))) is None
    object.__setattr__(policy, "_current", None)  # without a plan in force: brake (the least bad)
    assert len(policy(Observation(0.1, state, goal, np.zeros((0, 2)), np.zeros((0, 2))))) == 0
