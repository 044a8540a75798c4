"""Closed-form Hamiltonians against brute force over sampled inputs, and their dissipation bounds."""

import dataclasses
import math

import pytest
import torch
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.reach.dynamics import DubinsCar4D, HumanRobotRelative
from reach_dynamics_support import DoubleIntegrator, SingleIntegratorPursuitEvasion

CAR = DubinsCar4D(v_max=1.0, a_min=-1.5, a_max=0.8, omega_max=1.2)
# the reversing car (paper Sec. VII-A: "a slight reversal followed by a precise reorientation")
REVERSING = DubinsCar4D(v_max=1.0, a_min=-1.5, a_max=0.8, omega_max=1.2, v_min=-0.5)
HUMAN = HumanRobotRelative(v_max=1.0, a_min=-1.5, a_max=0.8, omega_max=1.2, human_speed=0.8, v_min=-0.5)
finite = st.floats(-3, 3)


def _inputs(lo, hi, n=9):
    return torch.linspace(lo, hi, n, dtype=torch.float64)


def _t(*xs):
    return [torch.tensor([x], dtype=torch.float64) for x in xs]


def _car_brute_force(car, state, grad, mode):
    v = float(state[2])
    a_lo = 0.0 if v <= car.v_min else car.a_min
    a_hi = 0.0 if v >= car.v_max else car.a_max
    best = None
    for a in _inputs(a_lo, a_hi):
        for w in _inputs(-car.omega_max, car.omega_max):
            f = car.velocity(state, (a.reshape(1), w.reshape(1)))
            value = sum(p * fi for p, fi in zip(grad, f))
            best = (
                value
                if best is None
                else (torch.maximum(best, value) if mode == "max" else torch.minimum(best, value))
            )
    return best


@settings(max_examples=30, deadline=None)
@given(
    x=finite,
    y=finite,
    v=st.sampled_from([-0.5, -0.2, 0.0, 0.3, 1.0]),
    th=st.floats(-math.pi, math.pi),
    p=st.tuples(finite, finite, finite, finite),
    mode=st.sampled_from(["min", "max"]),
    v_min=st.sampled_from([0.0, -0.5]),
)
def test_car_hamiltonian_and_optimal_control_match_brute_force(x, y, v, th, p, mode, v_min):
    """Forward-only (v_min = 0, speeds below it clamp to it) and reversing."""
    car = DubinsCar4D(CAR.v_max, CAR.a_min, CAR.a_max, CAR.omega_max, control_mode=mode, v_min=v_min)
    state, grad = _t(x, y, max(v, v_min), th), _t(*p)
    brute = _car_brute_force(car, state, grad, mode)
    assert float(car.hamiltonian(state, grad)) == pytest.approx(float(brute), abs=1e-9)
    f = car.velocity(state, car.optimal_control(state, grad))
    assert float(sum(g * fi for g, fi in zip(grad, f))) == pytest.approx(float(brute), abs=1e-9)
    bounds = car.partial_max_magnitudes(state)
    for a in _inputs(-2, 2):
        for w in _inputs(-CAR.omega_max, CAR.omega_max, 3):
            lo, hi = car.acceleration_bounds(state[2])
            a_in = a.clamp(float(lo), float(hi)).reshape(1)
            for fi, bound in zip(car.velocity(state, (a_in, w.reshape(1))), bounds):
                assert float(fi.abs()) <= float(torch.as_tensor(bound)) + 1e-12


def test_speed_limits_make_the_speed_axis_invariant():
    lo, hi = CAR.acceleration_bounds(torch.tensor([0.0, 0.5, 1.0], dtype=torch.float64))
    assert lo.tolist() == [0.0, -1.5, -1.5] and hi.tolist() == [0.8, 0.8, 0.0]
    # reversing: braking through 0 is allowed, only v_min stops it
    lo, hi = REVERSING.acceleration_bounds(torch.tensor([-0.5, -0.2, 0.0, 1.0], dtype=torch.float64))
    assert lo.tolist() == [0.0, -1.5, -1.5, -1.5] and hi.tolist() == [0.8, 0.8, 0.8, 0.0]


@pytest.mark.parametrize("mode", ["min", "max"])
@pytest.mark.parametrize("model", [CAR, REVERSING, HUMAN],
                         ids=["forward", "reversing", "human-robot reversing"])
def test_optimal_controls_keep_the_speed_in_its_range(model, mode):
    """For any gradient the optimal acceleration points into [v_min, v_max] at its ends (a >= 0 at v_min,
    a <= 0 at v_max): the grid's speed axis is invariant, a reversing car's as the forward one's."""
    model = dataclasses.replace(model, control_mode=mode)
    gen = torch.Generator().manual_seed(0)
    v = torch.linspace(model.v_min, model.v_max, 7, dtype=torch.float64).repeat_interleave(64)
    state = [torch.randn(len(v), generator=gen, dtype=torch.float64) for _ in model.state_names]
    state[2] = v
    grad = [torch.randn(len(v), generator=gen, dtype=torch.float64) for _ in model.state_names]
    a = model.optimal_control(state, grad)[0]
    assert (a[v == model.v_min] >= 0).all() and (a[v == model.v_max] <= 0).all()
    assert (a[v == model.v_min] > 0).any() and (a[v == model.v_max] < 0).any()  # it does move off them
    inside = (v > model.v_min) & (v < model.v_max)
    assert (a[inside] < 0).any() and (a[inside] > 0).any()


@settings(max_examples=30, deadline=None)
@given(px=finite, py=finite, v=st.sampled_from([-0.5, -0.2, 0.0, 0.6, 1.0]), g=st.tuples(finite, finite, finite))
def test_human_robot_hamiltonian_is_the_max_min_over_robot_and_human_inputs(px, py, v, g):
    """With a reversing robot (v_min = -0.5; the forward-only one is its restriction to v >= 0)."""
    state, grad = _t(px, py, v), _t(*g)
    betas = torch.linspace(-math.pi, math.pi, 721, dtype=torch.float64)
    a_lo = 0.0 if v <= HUMAN.v_min else HUMAN.a_min
    a_hi = 0.0 if v >= HUMAN.v_max else HUMAN.a_max
    best = -math.inf
    for a in _inputs(a_lo, a_hi, 5):
        for w in _inputs(-HUMAN.omega_max, HUMAN.omega_max, 5):
            f = HUMAN.velocity(state, (a.reshape(1), w.reshape(1)), (betas,))
            worst = float(sum(gi * fi for gi, fi in zip(grad, f)).min())
            best = max(best, worst)
    h = float(HUMAN.hamiltonian(state, grad))
    assert h <= best + 1e-9  # sampled β: the sampled minimum is above the true one
    assert h >= best - 0.8 * math.hypot(g[0], g[1]) * (1 - math.cos(math.pi / 720)) - 1e-9
    f = HUMAN.velocity(state, HUMAN.optimal_control(state, grad), HUMAN.optimal_disturbance(state, grad))
    assert float(sum(gi * fi for gi, fi in zip(grad, f))) == pytest.approx(h, abs=1e-9)
    bounds = HUMAN.partial_max_magnitudes(state)
    for w in (-HUMAN.omega_max, HUMAN.omega_max):
        f = HUMAN.velocity(
            state, (torch.zeros(1, dtype=torch.float64), torch.tensor([w], dtype=torch.float64)), (betas,)
        )
        for fi, bound in zip(f, bounds):
            assert float(fi.abs().max()) <= float(torch.as_tensor(bound).max()) + 1e-12


def test_pursuit_evasion_and_double_integrator_hamiltonians():
    grad = _t(3.0, 4.0)
    assert float(SingleIntegratorPursuitEvasion(0.5, 1.0).hamiltonian(_t(0, 0), grad)) == pytest.approx(-2.5)
    assert float(DoubleIntegrator(2.0).hamiltonian(_t(0.0, -1.5), grad)) == pytest.approx(-4.5 - 8.0)


def test_bad_bounds_are_rejected_with_the_rule():
    with pytest.raises(ValueError, match="a_min < 0 < a_max"):
        DubinsCar4D(v_max=1.0, a_min=0.5, a_max=1.0, omega_max=1.0)
    with pytest.raises(ValueError, match="control_mode"):
        DubinsCar4D(v_max=1.0, a_min=-1.0, a_max=1.0, omega_max=1.0, control_mode="avoid")
