"""Closed-loop simulator mechanics (HJ-search Sec. VII-D, VIII): the humans' rules, trips, determinism."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navlab.hj.humans import HumanStream, PatrolHuman, StraightWalker
from navlab.hj.receding_horizon import SimSettings, run_patrol
from navlab.maps.rooms import load_room


class PursuitPlanner:
    """Test scaffold: turn towards the goal and drive at full speed (no search, no safety)."""

    dt = 0.5

    def __call__(self, obs):
        x, y, _, th = obs.robot
        bearing = math.atan2(obs.goal[1] - y, obs.goal[0] - x)
        turn = (bearing - th + math.pi) % (2 * math.pi) - math.pi
        return np.array([[0.5, float(np.clip(turn / self.dt, -1.0, 1.0))]])


def open_space(x, y):
    return np.full(np.shape(x), 10.0)


def test_patrol_human_never_yields_to_a_moving_robot():
    h = PatrolHuman(pois=((0.0, 0.0), (5.0, 0.0)))
    for _ in range(10):
        h.step(0.04, np.array([1.0, 0.0]), robot_speed=0.6)
        assert np.allclose(h.velocity, [0.8, 0.0])
    assert h.detours == 0


def test_patrol_human_walks_around_a_stopped_robot():
    h = PatrolHuman(pois=((0.0, 0.0), (5.0, 0.0)))
    robot = np.array([1.5, 0.0])
    gaps = []
    for _ in range(200):
        h.step(0.04, robot, robot_speed=0.0)
        gaps.append(np.hypot(*(h.position - robot)))
    assert h.detours > 0 and min(gaps) > 0.5  # it never walked into the stopped robot


def test_patrol_human_switches_when_the_robot_occupies_its_poi():
    h = PatrolHuman(pois=((0.0, 0.0), (5.0, 0.0), (0.0, 5.0)))
    h.step(0.04, np.array([5.0, 0.1]), robot_speed=0.0)  # the robot stands on POI 1
    assert h.target == 2 and h.switches == 1
    assert h.velocity[1] > 0  # now heading for (0, 5)


def test_human_stream_respawns_at_the_start():
    h = HumanStream(start=(0.0, 0.0), goal=(1.0, 0.0))
    for _ in range(60):  # 2.4 s at 0.8 m/s: one crossing of 1 m, then a new human
        h.step(0.04, np.array([9.0, 9.0]), 0.0)
    assert h.spawned == 2 and h.position[0] < 1.0


def test_a_stream_waits_to_spawn_while_the_robot_is_at_its_start():
    h = HumanStream((0.0, 0.0), (0.2, 0.0), clear_m=1.0)
    for _ in range(20):
        h.step(0.04, np.array([0.5, 0.0]), robot_speed=0.0)  # the robot stands 0.5 m from the start
    assert h.spawned == 1 and np.allclose(h.position, [0.2, 0.0]) and np.allclose(h.velocity, 0.0)
    h.step(0.04, np.array([1.5, 0.0]), robot_speed=0.0)
    assert h.spawned == 2 and np.allclose(h.position, [0.0, 0.0])


def test_human_tracks_estimate_velocity_through_noise_and_restart_on_a_jump():
    """Over 0.5 s, 5 cm of position noise leaves ~0.14 m/s of velocity error (a two-point difference at
    12 Hz: ~0.85 m/s); a human reappearing 4.6 m away starts a new track instead of a 9 m/s estimate."""
    from navlab.hj.receding_horizon import HumanTracks

    rng, tracks, errors = np.random.default_rng(0), HumanTracks(0.5, 0.8), []
    for k in range(120):
        t = k / 12
        seen = np.array([[4.8, 5.0 - 0.8 * t]]) + rng.normal(0, 0.05, (1, 2))
        v = tracks.update(t, seen)
        if k >= 6:
            errors.append(np.hypot(*(v[0] - [0.0, -0.8])))
    assert np.sqrt(np.mean(np.square(errors))) < 0.25
    v = tracks.update(120 / 12, np.array([[4.8, 5.0]]))  # the stream's next human, at the start again
    assert np.allclose(v, 0.0)
    v = tracks.update(121 / 12, np.array([[4.8, 5.0 - 0.8 / 12]]))
    assert np.allclose(v, [[0.0, -0.8]])


def test_robot_alone_reaches_each_goal_and_wall_contact_fails_the_trip():
    settings = SimSettings()
    run = run_patrol(PursuitPlanner(), open_space, np.array([0.0, 0.0, 0.0, 0.0]),
                     [(3.0, 0.0), (3.0, 3.0), (0.0, 0.0)], [], settings, np.random.default_rng(0))
    assert [t.outcome for t in run.trips] == ["success"] * 3
    room = load_room("dense_room")  # straight at goal B from A runs into the first wall
    run = run_patrol(PursuitPlanner(), room.obstacle_distance, np.array([*room.goals["A"], 0.0, 0.0]),
                     [room.goals["B"]], [], settings, np.random.default_rng(0))
    assert run.trips[0].outcome == "collision"


def test_head_on_human_contact_is_counted_once_per_contact():
    walker = StraightWalker(start=(6.0, 0.0), goal=(-2.0, 0.0))
    run = run_patrol(PursuitPlanner(), open_space, np.array([0.0, 0.0, 0.0, 0.0]), [(5.0, 0.0)],
                     [walker], SimSettings(), np.random.default_rng(0))
    assert run.trips[0].human_contacts == 1 and not run.trips[0].success


def test_simulation_is_deterministic_for_a_seed():
    def once(seed):
        human = PatrolHuman(pois=((4.0, 1.0), (4.0, -3.0)))
        settings = SimSettings(pose_noise_m=0.05, human_noise_m=0.05)
        return run_patrol(PursuitPlanner(), open_space, np.array([0.0, 0.0, 0.0, 0.0]), [(6.0, 0.0), (0.0, 0.0)],
                          [human], settings, np.random.default_rng(seed))
    a, b, c = once(1), once(1), once(2)
    assert np.array_equal(np.array(a.trajectory), np.array(b.trajectory))
    assert not np.array_equal(np.array(a.trajectory), np.array(c.trajectory))


@pytest.mark.parametrize("field,value", [("replan_hz", 0.0), ("goal_tolerance", float("nan")), ("a_min", 0.1)])
def test_bad_settings_name_the_field(field, value):
    with pytest.raises(ValueError, match=field):
        SimSettings(**{field: value})
