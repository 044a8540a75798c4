"""The true state lattice (issue 26 item 2): primitives end exactly on lattice states and are feasible
for the paper's car, the table is D4-symmetric, A* with any admissible heuristic returns Dijkstra's cost,
and every accepted primitive clears the obstacles by the robot radius under a dense check."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from navlab.core.params import load_params
from navlab.hj.pruners import clearance_field, field_error
from navlab.maps.rooms import Disc, Rect, Room
from navlab.search.lattice_fields import wrap
from navlab.search.state_lattice import (
    ANGLES,
    D4,
    HEADINGS,
    Car,
    Clearance,
    Goal,
    Lattice,
    LatticeSettings,
    build_primitives,
    dist_heuristic,
    heading_index,
    sample_paths,
)

ROBOT = load_params().hj.grids.robot
CAR = Car.from_params(load_params())
SETTINGS = LatticeSettings(CAR)
PRIMS = build_primitives(SETTINGS)
GOAL_TOL, GOAL_SPEED = 0.2, 0.25


def _rows(p):
    return PRIMS.samples[PRIMS.sample_off[p]:PRIMS.sample_off[p + 1]]


def test_headings_are_grid_aligned_and_sorted():
    assert len(HEADINGS) == 16
    assert np.all(np.diff(np.unwrap(ANGLES)) > 0)
    for m in D4:  # the symmetry group maps the heading set onto itself
        assert sorted(heading_index(m @ d) for d in HEADINGS) == list(range(16))


def test_every_primitive_ends_exactly_on_a_lattice_state():
    speeds = np.asarray(SETTINGS.speeds)
    for p in range(len(PRIMS.cost)):
        rows = _rows(p)
        np.testing.assert_allclose(rows[0, :2], 0.0, atol=1e-12)
        assert rows[0, 2] == speeds[PRIMS.s0[p]] and abs(wrap(rows[0, 3] - ANGLES[PRIMS.k0[p]])) < 1e-12
        np.testing.assert_allclose(rows[-1, :2], SETTINGS.cell_m * np.array([PRIMS.di[p], PRIMS.dj[p]]), atol=1e-9)
        assert abs(rows[-1, 2] - speeds[PRIMS.s1[p]]) < 1e-9
        assert abs(wrap(rows[-1, 3] - ANGLES[PRIMS.k1[p]])) < 1e-9
        assert abs(rows[-1, 4] - PRIMS.cost[p]) < 1e-9  # cost = duration


def test_every_primitive_is_dynamically_feasible():
    """Each primitive is a trajectory of the car: |ω| <= omega_max (κ · |v| on its arc), a within bounds,
    v_min <= v <= v_max, heading continuous and tangent to the motion (opposite to it reversing, v < 0);
    a turn in place only at rest."""
    for p in range(len(PRIMS.cost)):
        rows = _rows(p)
        dt = np.diff(rows[:, 4])
        turn = np.abs(wrap(np.diff(rows[:, 3])))
        assert (dt > 0).all()
        assert (turn / dt <= CAR.omega_max + 1e-9).all()  # the mean turn rate between samples
        assert (rows[:, 2] >= CAR.v_min - 1e-12).all() and (rows[:, 2] <= CAR.v_max + 1e-12).all()
        back = PRIMS.speeds[p].sum() < 0.0
        assert (rows[:, 2] <= 0.0).all() if back else (rows[:, 2] >= 0.0).all()  # no cusp within a primitive
        accel = np.diff(rows[:, 2]) / dt
        assert (accel >= CAR.accel_min - 1e-9).all() and (accel <= CAR.accel_max + 1e-9).all()
        if PRIMS.length[p] == 0.0:  # in place: at rest, one heading step at omega_max
            assert (rows[:, :3] == 0.0).all() and abs(wrap(rows[-1, 3] - rows[0, 3])) / rows[-1, 4] == \
                pytest.approx(CAR.omega_max)
            continue
        step = 2 * PRIMS.gap[p]  # arc length between samples
        assert step <= SETTINGS.sample_m + 1e-12
        chord = np.diff(rows[:, :2], axis=0)
        assert (np.hypot(*chord.T) <= step + 1e-9).all()  # chord <= arc
        # heading continuous and tangent to the motion: each chord points between its end headings
        middle = rows[:-1, 3] + 0.5 * wrap(np.diff(rows[:, 3])) + (math.pi if back else 0.0)
        assert (np.abs(wrap(np.arctan2(chord[:, 1], chord[:, 0]) - middle)) <= 0.5 * turn + 1e-9).all()
        _, straight1, radius, arc_turn, _ = PRIMS.geometry[p]
        if arc_turn != 0.0:
            assert (turn <= step / radius + 1e-9).all()
            s = np.linspace(0.0, PRIMS.length[p], len(rows))
            on_arc = (s >= straight1 - 1e-12) & (s <= straight1 + radius * abs(arc_turn) + 1e-12)
            assert (np.abs(rows[on_arc, 2]) / radius <= CAR.omega_max + 1e-9).all()  # κ · |v| <= omega_max on the arc


def test_primitive_table_is_d4_symmetric():
    index = {(PRIMS.k0[p], PRIMS.s0[p], PRIMS.k1[p], PRIMS.s1[p], PRIMS.di[p], PRIMS.dj[p]): p
             for p in range(len(PRIMS.cost))}
    assert len(index) == len(PRIMS.cost)
    for m in D4:
        for p in range(len(PRIMS.cost)):
            di, dj = m @ np.array([PRIMS.di[p], PRIMS.dj[p]])
            q = index[(heading_index(m @ HEADINGS[PRIMS.k0[p]]), PRIMS.s0[p], heading_index(m @ HEADINGS[PRIMS.k1[p]]),
                       PRIMS.s1[p], di, dj)]
            assert abs(PRIMS.cost[q] - PRIMS.cost[p]) < 1e-12
            np.testing.assert_allclose(_rows(p)[:, :2] @ m.T, _rows(q)[:, :2], atol=1e-9)


def _random_room(seed: int) -> Room:
    rng = np.random.default_rng(seed)
    obstacles = [Disc(*rng.uniform(1.0, 3.0, 2), rng.uniform(0.1, 0.3)) for _ in range(2)]
    x, y = rng.uniform(1.0, 2.6, 2)
    obstacles.append(Rect(x, y, x + rng.uniform(0.1, 0.6), y + rng.uniform(0.1, 0.6)))
    return Room(f"random{seed}", 4.0, 3.6, tuple(obstacles))


def _lattice(room: Room, start_xy) -> Lattice:
    field = clearance_field(room)
    return Lattice(SETTINGS, Clearance(field, field_error(field), ROBOT.radius_m), start_xy, PRIMS)


def _free_point(room: Room, rng) -> np.ndarray:
    while True:
        xy = np.round(rng.uniform(0.3, (room.width - 0.3, room.height - 0.3)), 1)
        if room.obstacle_distance(*xy) > ROBOT.radius_m + 0.4:
            return xy


@pytest.mark.parametrize("seed", range(6))
def test_astar_with_admissible_heuristics_returns_the_dijkstra_cost(seed):
    room, rng = _random_room(seed), np.random.default_rng(100 + seed)
    start, goal_xy = _free_point(room, rng), _free_point(room, rng)
    lat = _lattice(room, start)
    goal = Goal(tuple(goal_xy), GOAL_TOL, GOAL_SPEED)
    state = (start[0], start[1], 0.0, rng.uniform(-math.pi, math.pi))
    dist = dist_heuristic(goal, CAR.v_max)
    noise = rng.uniform(0.0, 1.0, len(lat.states))  # an inconsistent, admissible heuristic: reopening matters
    reference = lat.search(state, goal)
    assert reference.found
    to_go = lat.cost_to_go(goal)
    assert lat.excess(dist, goal, to_go) <= 1e-12  # Dist is admissible on the lattice
    assert (lat.heuristic_table(dist, goal)[lat.goal_mask(goal)] == 0.0).all()
    assert reference.cost == pytest.approx(to_go[lat.index(state)], abs=1e-9)
    for h in (dist, lambda s: 0.5 * dist(s), lambda s: noise * dist(s)):
        res = lat.search(state, goal, h)
        assert res.found
        assert res.cost == pytest.approx(reference.cost, abs=1e-9)



def test_accepted_primitives_clear_obstacles_by_the_robot_radius_densely():
    room, rng = _random_room(7), np.random.default_rng(7)
    lat = _lattice(room, (0.5, 0.5))
    cells = np.stack([rng.integers(0, lat.nx, 4000), rng.integers(0, lat.ny, 4000)], axis=1)
    ids = rng.integers(0, len(PRIMS.cost), 4000)
    kept = lat.clear(cells, ids)
    assert 0 < kept.sum() < len(kept)
    counts = np.full(kept.sum(), 400)
    dense = sample_paths(PRIMS.geometry[ids[kept]], np.abs(PRIMS.speeds[ids[kept]]), counts, CAR.omega_max)
    base = np.repeat(lat.origin + cells[kept] * SETTINGS.cell_m, counts + 1, axis=0)
    clearance = room.obstacle_distance(base[:, 0] + dense[:, 0], base[:, 1] + dense[:, 1])
    assert clearance.min() > ROBOT.radius_m


def test_the_reversing_car_backs_out_where_the_forward_one_turns_in_place():
    """params.yaml's car reverses (v_min = -0.5): its lattice has the levels -0.5 and -0.25 and every
    forward primitive driven backwards. In a dead-end corridor facing the end wall, with the goal behind,
    it backs straight out; the forward-only car (v_min = 0, the labelled variant) spins on the spot first,
    which takes longer."""
    assert SETTINGS.speeds == (-0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 1.0)
    assert (PRIMS.speeds.sum(axis=1) < 0).any()
    corridor = Room("dead end", 3.0, 0.8, ())
    field = clearance_field(corridor)
    clearance = Clearance(field, field_error(field), ROBOT.radius_m)
    start, goal = (2.5, 0.4, 0.0, 0.0), Goal((1.0, 0.4), GOAL_TOL, GOAL_SPEED)
    forward_settings = LatticeSettings(dataclasses.replace(CAR, v_min=0.0))
    assert forward_settings.speeds == (0.0, 0.25, 0.5, 0.75, 1.0)
    back = Lattice(SETTINGS, clearance, start[:2], PRIMS).search(start, goal)
    ahead = Lattice(forward_settings, clearance, start[:2]).search(start, goal)
    assert back.found and ahead.found
    assert back.states[:, 2].min() < 0.0 and ahead.states[:, 2].min() == 0.0
    assert back.cost < ahead.cost - 1.0, (back.cost, ahead.cost)

