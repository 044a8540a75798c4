"""The HJ-guided lattice planner as the simulator's policy: the OBS row treats a human as a disc obstacle."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.params import load_params
from navlab.maps.rooms import load_room
from navlab.reach.guidance import dist_heuristic
from navlab.reach.planning import lattice_spec
from navlab.reach.pruners import obs_pruner
from navlab.search.dubins_lattice import densify
from navlab.sim.lattice_policy import LatticePolicy
from navlab.sim.receding_horizon import Observation

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
