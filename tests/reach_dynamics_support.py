"""Test systems with closed-form value functions (single/double integrators, pursuit-evasion).

They exercise the HJ solver against analytic answers; no navlab experiment uses them, so they live with
the tests rather than in ``navlab.reach.dynamics``.
"""

from __future__ import annotations

from dataclasses import dataclass

import torch

from navlab.reach.dynamics import Dynamics, Mode, _sign, box_argopt


@dataclass(frozen=True)
class SingleIntegrator(Dynamics):
    """ẋ = u with |u| ≤ speed (a disk), in any dimension: H = ±speed·|p|; a test system."""

    speed: float
    ndim: int = 2
    control_mode: Mode = "min"

    def hamiltonian(self, state, grad):
        return _sign(self.control_mode) * self.speed * torch.sqrt(sum(g * g for g in grad))

    def partial_max_magnitudes(self, state):
        return [self.speed] * self.ndim

    def optimal_control(self, state, grad):
        norm = torch.sqrt(sum(g * g for g in grad)).clamp(min=1e-12)
        return tuple(_sign(self.control_mode) * self.speed * g / norm for g in grad)

    def velocity(self, state, control, disturbance=()):
        return list(control)


@dataclass(frozen=True)
class SingleIntegratorPursuitEvasion(Dynamics):
    """Relative position z = x_evader − x_pursuer of two single integrators: ż = u − d, |u| ≤ v_e, |d| ≤ v_p.

    The evader (control, 'max') avoids capture |z| ≤ r; H = (v_e − v_p)|p|, so the capture set grows
    at v_p − v_e when the pursuer is faster; a test system with a closed-form BRT.
    """

    evader_speed: float
    pursuer_speed: float
    control_mode: Mode = "max"

    def hamiltonian(self, state, grad):
        speed = self.evader_speed - self.pursuer_speed
        return _sign(self.control_mode) * speed * torch.sqrt(grad[0] ** 2 + grad[1] ** 2)

    def partial_max_magnitudes(self, state):
        # ∂H/∂p = (v_e − v_p) p/|p|: the inputs' own bound v_e + v_p would over-smear the front
        return [abs(self.evader_speed - self.pursuer_speed)] * 2

    def optimal_control(self, state, grad):
        norm = torch.sqrt(grad[0] ** 2 + grad[1] ** 2).clamp(min=1e-12)
        return tuple(_sign(self.control_mode) * self.evader_speed * g / norm for g in grad)

    def velocity(self, state, control, disturbance=()):
        return [control[0] - disturbance[0], control[1] - disturbance[1]]


@dataclass(frozen=True)
class DoubleIntegrator(Dynamics):
    """ẋ = v, v̇ = u with |u| ≤ u_max; state (x, v); the minimum-time problem has a closed form."""

    u_max: float = 1.0
    control_mode: Mode = "min"

    def hamiltonian(self, state, grad):
        _, v = state
        px, pv = grad
        return px * v + _sign(self.control_mode) * self.u_max * pv.abs()

    def partial_max_magnitudes(self, state):
        _, v = state
        return [v.abs(), self.u_max]

    def optimal_control(self, state, grad):
        return (box_argopt(grad[1], -self.u_max, self.u_max, self.control_mode),)

    def velocity(self, state, control, disturbance=()):
        return [state[1], control[0]]
