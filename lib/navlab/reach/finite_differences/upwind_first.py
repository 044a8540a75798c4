"""First-order upwind differences: φ_x⁻ = (φ_i − φ_{i−1})/h, φ_x⁺ = (φ_{i+1} − φ_i)/h."""

from __future__ import annotations

import torch

from navlab.reach.boundary_conditions import padded_differences


def left_right(values: torch.Tensor, dim: int, spacing: float, periodic: bool):
    d = padded_differences(values, dim, spacing, 1, periodic)
    n = values.shape[dim]
    return d.narrow(dim, 0, n), d.narrow(dim, 1, n).clone()  # the views overlap: one gets its own copy
