"""Lookups: exact on multilinear functions, periodic wrap, numpy == torch, transform round trips."""

import math

import numpy as np
import pytest
import torch
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.reach.grid import Grid
from navlab.reach.lookup import (
    interpolate,
    interpolate_torch,
    outside,
    to_goal_frame,
    to_robot_frame,
    wrap_angle,
)
from reach_support import from_goal_frame, from_robot_frame

GRID = Grid((-2.0, -1.0, 0.0, -math.pi), (2.0, 1.0, 1.0, math.pi), (9, 5, 4, 12), (False, False, False, True))
GRID3 = Grid((-2.0, -1.0, 0.0), (2.0, 1.0, 1.0), (9, 5, 4), (False, False, False))


def _multilinear(coef, pts):
    """A function linear in each coordinate separately: Σ_S c_S Π_{i∈S} x_i (16 terms in 4D)."""
    out = np.zeros(len(pts))
    for s, c in enumerate(coef):
        term = np.full(len(pts), c)
        for d in range(pts.shape[1]):
            if (s >> d) & 1:
                term = term * pts[:, d]
        out += term
    return out


def _on_grid(f, grid):
    mesh = np.meshgrid(*[grid.axis(d) for d in range(grid.ndim)], indexing="ij")
    return f(np.stack([m.ravel() for m in mesh], -1)).reshape(grid.shape)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-3, 3), min_size=8, max_size=8), st.integers(0, 2**31 - 1))
def test_exact_on_multilinear_functions(coef, seed):
    pts = np.random.default_rng(seed).uniform(GRID3.lo, GRID3.hi, size=(50, 3))
    values = _on_grid(lambda p: _multilinear(coef, p), GRID3)
    np.testing.assert_allclose(interpolate(values, GRID3, pts), _multilinear(coef, pts), atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_numpy_equals_torch_and_nodes_are_exact(seed):
    rng = np.random.default_rng(seed)
    values = rng.normal(size=GRID.shape)
    pts = rng.uniform(np.array(GRID.lo) - 0.5, np.array(GRID.hi) + 0.5, size=(200, 4))
    a = interpolate(values, GRID, pts)
    b = interpolate_torch(torch.from_numpy(values), GRID, torch.from_numpy(pts))
    np.testing.assert_allclose(a, b.numpy(), rtol=0, atol=1e-12)
    idx = rng.integers(0, GRID.shape, size=(30, 4))
    nodes = np.stack([GRID.axis(d)[idx[:, d]] for d in range(4)], -1)
    np.testing.assert_allclose(interpolate(values, GRID, nodes), values[tuple(idx.T)], atol=1e-12)


def test_theta_wraps_periodically_and_linearly_across_the_seam():
    values = np.zeros(GRID.shape)
    values[..., 0] = 1.0  # θ = -π node
    pts = np.array([[0.0, 0.0, 0.5, -math.pi], [0.0, 0.0, 0.5, math.pi], [0.0, 0.0, 0.5, 3 * math.pi],
                    [0.0, 0.0, 0.5, math.pi - GRID.spacing[3] / 4]])
    np.testing.assert_allclose(interpolate(values, GRID, pts), [1.0, 1.0, 1.0, 0.75], atol=1e-12)


def test_clamp_outside_and_outside_mask():
    values = _on_grid(lambda p: p[:, 0] + 10 * p[:, 2], GRID3)
    pts = np.array([[5.0, 0.0, 0.5], [-5.0, 0.0, 2.0], [0.0, 0.0, 0.5]])
    np.testing.assert_allclose(interpolate(values, GRID3, pts), [2.0 + 5.0, -2.0 + 10.0, 5.0])
    assert outside(GRID3, pts).tolist() == [True, True, False]
    assert outside(GRID3, pts, dims=(2,)).tolist() == [False, True, False]
    assert outside(GRID3, torch.from_numpy(pts)).tolist() == [True, True, False]


def test_memory_mapped_values(tmp_path):
    values = np.random.default_rng(1).normal(size=GRID3.shape)
    np.save(tmp_path / "v.npy", values)
    mm = np.load(tmp_path / "v.npy", mmap_mode="r")
    pts = np.random.default_rng(2).uniform(GRID3.lo, GRID3.hi, size=(20, 3))
    np.testing.assert_array_equal(interpolate(mm, GRID3, pts), interpolate(values, GRID3, pts))


def test_bad_shapes_are_named():
    with pytest.raises(ValueError, match=r"points must be \(N, 3\)"):
        interpolate(np.zeros(GRID3.shape), GRID3, np.zeros((4, 2)))


states = st.lists(st.floats(-20, 20), min_size=4, max_size=4)


@settings(max_examples=50, deadline=None)
@given(states, st.floats(-20, 20), st.floats(-20, 20), st.floats(-10, 10))
def test_goal_frame_round_trip_and_goal_at_origin(s, gx, gy, heading):
    state = np.array([s])
    goal = np.array([gx, gy])
    local = to_goal_frame(state, goal, heading)
    back = from_goal_frame(local, goal, heading)
    np.testing.assert_allclose(back[:, :3], state[:, :3], atol=1e-9)
    assert abs(wrap_angle(back[0, 3] - state[0, 3])) < 1e-9
    assert np.isclose(np.hypot(*local[0, :2]), np.hypot(s[0] - gx, s[1] - gy))
    at_goal = to_goal_frame(np.array([[gx, gy, 0.3, heading]]), goal, heading)
    np.testing.assert_allclose(at_goal[0], [0, 0, 0.3, 0], atol=1e-9)


@settings(max_examples=50, deadline=None)
@given(states, st.floats(-20, 20), st.floats(-20, 20))
def test_robot_frame_round_trip_numpy_and_torch(s, hx, hy):
    robot, human = np.array([s]), np.array([[hx, hy]])
    rel = to_robot_frame(robot, human)
    np.testing.assert_allclose(from_robot_frame(robot, rel), human, atol=1e-9)
    rel_t = to_robot_frame(torch.from_numpy(robot), torch.from_numpy(human))
    np.testing.assert_allclose(rel_t.numpy(), rel, atol=1e-12)


def test_robot_frame_axes():
    """A human straight ahead is at +x; one to the robot's left at +y."""
    robot = np.array([[1.0, 1.0, 0.5, math.pi / 2]] * 2)   # facing +y
    human = np.array([[1.0, 3.0], [0.0, 1.0]])
    np.testing.assert_allclose(to_robot_frame(robot, human), [[2.0, 0.0], [0.0, 1.0]], atol=1e-12)
