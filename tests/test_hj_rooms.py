"""Room geometry: the analytic signed distance has the right sign and values at known points."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.maps.rooms import ROOMS, Disc, Rect, load_room

R = 0.285


def test_rect_and_disc_signed_distance_known_points():
    box = Rect(1.0, 1.0, 3.0, 2.0)
    pts = np.array([[2.0, 1.5], [0.0, 1.5], [4.0, 3.0], [2.0, 1.9], [1.0, 1.0]])
    np.testing.assert_allclose(box.signed_distance(pts[:, 0], pts[:, 1]), [-0.5, 1.0, np.sqrt(2), -0.1, 0.0])
    disc = Disc(0.0, 0.0, 1.0)
    np.testing.assert_allclose(disc.signed_distance(np.array([0.0, 3.0]), np.array([0.0, 4.0])), [-1.0, 4.0])


def test_room_walls_and_obstacles():
    room = load_room("simulation")
    # free point 0.8 m from the west wall, far from everything else: clearance 0.8 - r
    assert np.isclose(room.signed_distance(0.8, 2.7, R), 0.8 - R)
    # outside the room and inside the desk are collisions
    assert room.signed_distance(-0.5, 2.0, R) < 0
    assert np.isclose(room.obstacle_distance(2.6, 2.7), -0.6)   # desk centre x: 0.6 m to its side
    # next to the pillar at (5.0, 1.2), r = 0.35
    assert np.isclose(room.obstacle_distance(5.0, 2.0), 0.8 - 0.35)


@pytest.mark.parametrize("name", sorted(ROOMS))
def test_goals_are_free_and_occupancy_matches_sdf(name):
    room = load_room(name)
    for goal in room.goals.values():
        assert room.signed_distance(*goal, R) > 0.1, f"{name}: goal {goal} is too close to an obstacle"
    occ, frame = room.occupancy(0.1, R)
    assert occ.shape == (54, 96) and frame.shape == (54, 96)
    assert occ[0].all() and occ[:, 0].all()       # the inflated walls
    assert 0.15 < occ.mean() < 0.75


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 9.6), st.floats(0.0, 5.4), st.floats(0.0, 9.6), st.floats(0.0, 5.4))
def test_sdf_is_1_lipschitz(x0, y0, x1, y1):
    """A signed distance changes no faster than the distance between the points."""
    room = load_room("dense_room")
    d = room.obstacle_distance(np.array([x0, x1]), np.array([y0, y1]))
    assert abs(d[0] - d[1]) <= np.hypot(x1 - x0, y1 - y0) + 1e-9


def test_sdf_matches_brute_force_distance_in_free_space():
    """In free space the sdf equals the distance to the nearest blocked point of a fine raster."""
    room = load_room("dense_room")
    occ, frame = room.occupancy(0.02)
    rows, cols = np.nonzero(occ)
    blocked = frame.cell_to_world(np.stack([rows, cols], -1))
    rng = np.random.default_rng(0)
    pts = rng.uniform([0, 0], [9.6, 5.4], size=(40, 2))
    sdf = room.obstacle_distance(pts[:, 0], pts[:, 1])
    free = sdf > 0.05
    walls = np.min([pts[:, 0], 9.6 - pts[:, 0], pts[:, 1], 5.4 - pts[:, 1]], axis=0)[free]
    brute = np.minimum([np.min(np.hypot(*(blocked - p).T)) for p in pts[free]], walls)
    np.testing.assert_allclose(sdf[free], brute, atol=0.03)


def test_dense_room_goals_have_no_line_of_sight_and_hallway_is_narrow():
    room = load_room("dense_room")
    a, b = np.array(room.goals["A"]), np.array(room.goals["B"])
    assert 5.5 < np.linalg.norm(b - a) < 5.7
    seg = a + np.linspace(0, 1, 200)[:, None] * (b - a)
    assert (room.obstacle_distance(seg[:, 0], seg[:, 1]) < 0).any()
    hall = load_room("long_hallway")
    mid = hall.signed_distance(np.linspace(2.0, 7.5, 20), np.full(20, 2.7), R)
    assert (mid > 0).all() and (mid < 0.5).all()    # passable, but narrow once inflated


def test_unknown_room_names_the_choices():
    with pytest.raises(ValueError, match="rooms are open, simulation, long_hallway, dense_room"):
        load_room("kitchen")
