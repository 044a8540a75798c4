"""Total-variation-diminishing Runge-Kutta steps (Shu & Osher 1988), orders 1-3.

Each stage is a forward-Euler step of ∂V/∂τ = L(V); the higher orders are convex combinations of such
steps, so they keep the monotonicity of the Lax-Friedrichs scheme under the same CFL limit.
"""

from __future__ import annotations

from collections.abc import Callable

import torch

Rate = Callable[[torch.Tensor], torch.Tensor]


def euler_step(rate: Rate, values: torch.Tensor, dt) -> torch.Tensor:
    """``dt``: a float or a 0-d tensor (a tensor keeps a compiled step from recompiling per dt)."""
    return values + rate(values).mul_(dt)


def first_order_total_variation_diminishing_runge_kutta(rate: Rate, values: torch.Tensor, dt):
    return euler_step(rate, values, dt)


def second_order_total_variation_diminishing_runge_kutta(rate: Rate, values: torch.Tensor, dt):
    stage = euler_step(rate, values, dt)
    stage.add_(rate(stage).mul_(dt))
    return stage.mul_(0.5).add_(values, alpha=0.5)


def third_order_total_variation_diminishing_runge_kutta(rate: Rate, values: torch.Tensor, dt):
    stage = euler_step(rate, values, dt)
    stage.add_(rate(stage).mul_(dt))
    stage.mul_(0.25).add_(values, alpha=0.75)
    stage.add_(rate(stage).mul_(dt))
    return stage.mul_(2 / 3).add_(values, alpha=1 / 3)


RUNGE_KUTTA = {
    1: first_order_total_variation_diminishing_runge_kutta,
    2: second_order_total_variation_diminishing_runge_kutta,
    3: third_order_total_variation_diminishing_runge_kutta,
}
