"""Dynamics as optimal Hamiltonians: H(x, p) = opt_u opt_d p · f(x, u, d), evaluated on a whole grid.

States arrive as ``state``: a list of d tensors that broadcast against each other (``Grid.mesh`` axes, or
1-D batches of states for simulation); gradients ``grad`` as a list of d tensors of the value's shape.
Nothing builds an N×d array. Control and disturbance sets are boxes or disks, so every optimum is in
closed form.

Modes as in hj_reachability: ``control_mode='max'`` for avoid problems (the control keeps the value
high, away from the failure set), ``'min'`` for reach problems (the control drives the value down into
the target); the disturbance takes the opposite mode. Sign convention of the solver: with τ the time to
go, the value evolves as ∂V/∂τ = H(x, ∇V) (Mitchell, Bayen & Tomlin 2005, written backwards in time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import torch

Mode = Literal["min", "max"]


def _check_mode(name: str, mode: str):
    if mode not in ("min", "max"):
        raise ValueError(f"{name} must be 'min' or 'max', got {mode!r}")


def box_optimum(p: torch.Tensor, lo, hi, mode: Mode) -> torch.Tensor:
    """opt over u ∈ [lo, hi] of p·u (lo, hi may be tensors broadcasting with p)."""
    up, down = (hi, lo) if mode == "max" else (lo, hi)
    return p.clamp(min=0).mul_(up).addcmul_(p.clamp(max=0), torch.as_tensor(down, dtype=p.dtype, device=p.device))


def box_argopt(p: torch.Tensor, lo, hi, mode: Mode) -> torch.Tensor:
    lo, hi = (
        torch.as_tensor(lo, dtype=p.dtype, device=p.device),
        torch.as_tensor(hi, dtype=p.dtype, device=p.device),
    )
    return torch.where((p > 0) == (mode == "max"), hi, lo)


def _check_finite(system, *bounds: float) -> None:
    """An infinite bound makes the CFL time step 0 (the solve never ends); NaN fails every comparison."""
    if not all(math.isfinite(b) for b in bounds):
        raise ValueError(f"{type(system).__name__}: every bound must be a finite number, got {system}")


def _sign(mode: Mode) -> float:
    return 1.0 if mode == "max" else -1.0


class Dynamics:
    """An optimal Hamiltonian with bounds on its partial derivatives (for Lax-Friedrichs dissipation)."""

    state_names: tuple[str, ...] = ()
    control_mode: Mode = "max"

    @property
    def disturbance_mode(self) -> Mode:
        return "min" if self.control_mode == "max" else "max"

    def hamiltonian(self, state: list[torch.Tensor], grad: list[torch.Tensor]) -> torch.Tensor:
        raise NotImplementedError

    def partial_max_magnitudes(self, state: list[torch.Tensor]) -> list:
        """Per-dimension bounds on |∂H/∂p_i| at each state (tensors broadcastable to the grid, or floats).

        For control-affine dynamics with bounded inputs, ∂H/∂p = f(x, u*, d*), so the bound is
        max over inputs of |f_i(x, u, d)| and needs no gradient: the solver evaluates it once per solve
        (usually on the broadcast mesh, a few floats per point at most) and the time step is fixed.
        """
        raise NotImplementedError

    def optimal_control(self, state: list[torch.Tensor], grad: list[torch.Tensor]) -> tuple:
        raise NotImplementedError

    def velocity(self, state: list[torch.Tensor], control: tuple, disturbance: tuple = ()) -> list:
        """f(x, u, d), for simulating trajectories."""
        raise NotImplementedError


@dataclass(frozen=True)
class DubinsCar4D(Dynamics):
    """Paper Eq. (19): ẋ = v cos θ, ẏ = v sin θ, v̇ = a, θ̇ = ω; state (x, y, v, θ).

    v ∈ [v_min, v_max] is kept by state-dependent acceleration bounds: at v ≤ v_min the car cannot slow
    down (or reverse) further, at v ≥ v_max it cannot speed up, so the speed axis of the grid is invariant.
    v_min < 0: the car reverses, as the paper's does (Sec. VII-A: "a slight reversal followed by a precise
    reorientation", Fig. 6); v_min = 0: the forward-only car.
    """

    v_max: float
    a_min: float
    a_max: float
    omega_max: float
    control_mode: Mode = "max"
    v_min: float = 0.0  # navlab.hj.grids passes hj.grids.robot.v_min
    state_names = ("x", "y", "v", "theta")

    def __post_init__(self):
        _check_mode("control_mode", self.control_mode)
        _check_finite(self, self.v_min, self.v_max, self.a_min, self.a_max, self.omega_max)
        if not (self.v_max > 0 and -self.v_max <= self.v_min <= 0 and self.a_min < 0 < self.a_max
                and self.omega_max > 0):
            raise ValueError(f"DubinsCar4D needs v_max > 0, -v_max <= v_min <= 0, a_min < 0 < a_max, "
                             f"omega_max > 0; got {self}")

    def acceleration_bounds(self, v: torch.Tensor):
        tol = 1e-6 * self.v_max
        lo = torch.where(v <= self.v_min + tol, torch.zeros_like(v), torch.full_like(v, self.a_min))
        hi = torch.where(v >= self.v_max - tol, torch.zeros_like(v), torch.full_like(v, self.a_max))
        return lo, hi

    def hamiltonian(self, state, grad):
        _, _, v, theta = state
        px, py, pv, pth = grad
        lo, hi = self.acceleration_bounds(v)
        h = box_optimum(pv, lo, hi, self.control_mode)
        h.addcmul_(px, v * torch.cos(theta)).addcmul_(py, v * torch.sin(theta))
        return h.add_(pth.abs(), alpha=_sign(self.control_mode) * self.omega_max)

    def partial_max_magnitudes(self, state):
        _, _, v, theta = state
        lo, hi = self.acceleration_bounds(v)
        return [
            (v * torch.cos(theta)).abs(),
            (v * torch.sin(theta)).abs(),
            torch.maximum(lo.abs(), hi.abs()),
            self.omega_max,
        ]

    def optimal_control(self, state, grad):
        _, _, v, _ = state
        _, _, pv, pth = grad
        lo, hi = self.acceleration_bounds(v)
        a = box_argopt(pv, lo, hi, self.control_mode)
        omega = box_argopt(pth, -self.omega_max, self.omega_max, self.control_mode)
        return a, omega

    def velocity(self, state, control, disturbance=()):
        _, _, v, theta = state
        a, omega = control
        return [v * torch.cos(theta), v * torch.sin(theta), a, omega + 0 * v]


@dataclass(frozen=True)
class HumanRobotRelative(Dynamics):
    """Paper Eq. (13, 20): a human point mass (constant speed, any direction) against the 4D car.

    State (p_x, p_y, v): the human's position in the robot's body frame (x forward, y left) and the
    robot's speed. The robot's heading drops out because the human's direction control ranges over
    all angles, so the game is rotation invariant; this 3D state is the exact reduction of Eq. (13).
    In the body frame ṗ = (ω p_y − v + s cos β, −ω p_x + s sin β), v̇ = a, with the human heading β
    relative to the robot. The robot (control, ``'max'``) avoids; the human (disturbance) pursues.
    """

    v_max: float
    a_min: float
    a_max: float
    omega_max: float
    human_speed: float
    control_mode: Mode = "max"
    v_min: float = 0.0  # the robot's speed range [v_min, v_max], as DubinsCar4D's
    state_names = ("px", "py", "v")

    def __post_init__(self):
        _check_mode("control_mode", self.control_mode)
        _check_finite(self, self.v_min, self.v_max, self.a_min, self.a_max, self.omega_max, self.human_speed)
        if not (
            self.v_max > 0 and -self.v_max <= self.v_min <= 0 and self.a_min < 0 < self.a_max
            and self.omega_max > 0 and self.human_speed >= 0
        ):
            raise ValueError(
                f"HumanRobotRelative needs v_max > 0, -v_max <= v_min <= 0, a_min < 0 < a_max, omega_max > 0, "
                f"human_speed >= 0; got {self}"
            )

    def _car(self) -> DubinsCar4D:
        return DubinsCar4D(self.v_max, self.a_min, self.a_max, self.omega_max, self.control_mode, self.v_min)

    def hamiltonian(self, state, grad):
        px, py, v = state
        gx, gy, gv = grad
        lo, hi = self._car().acceleration_bounds(v)
        sign = _sign(self.control_mode)
        h = -gx * v
        h += sign * self.omega_max * (gx * py - gy * px).abs()
        h += box_optimum(gv, lo, hi, self.control_mode)
        h -= sign * self.human_speed * torch.sqrt(gx * gx + gy * gy)
        return h

    def partial_max_magnitudes(self, state):
        px, py, v = state
        lo, hi = self._car().acceleration_bounds(v)
        return [
            self.omega_max * py.abs() + v.abs() + self.human_speed,
            self.omega_max * px.abs() + self.human_speed,
            torch.maximum(lo.abs(), hi.abs()),
        ]

    def optimal_control(self, state, grad):
        px, py, v = state
        gx, gy, gv = grad
        lo, hi = self._car().acceleration_bounds(v)
        a = box_argopt(gv, lo, hi, self.control_mode)
        omega = box_argopt(gx * py - gy * px, -self.omega_max, self.omega_max, self.control_mode)
        return a, omega

    def optimal_disturbance(self, state, grad):
        """The human's heading β (body frame): straight down the value's gradient when pursuing."""
        gx, gy, _ = grad
        beta = torch.atan2(gy, gx)
        return (beta + math.pi,) if self.disturbance_mode == "min" else (beta,)

    def velocity(self, state, control, disturbance=()):
        px, py, v = state
        a, omega = control
        (beta,) = disturbance
        s = self.human_speed
        return [omega * py - v + s * torch.cos(beta), -omega * px + s * torch.sin(beta), a + 0 * v]
