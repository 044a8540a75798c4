"""Lax-Friedrichs numerical Hamiltonian (Crandall & Lions 1984; Osher & Shu 1991).

For ∂V/∂τ = H(x, ∇V) the monotone flux is

    Ĥ(x, p⁻, p⁺) = H(x, (p⁻ + p⁺)/2) + Σ_i α_i(x) (p⁺_i − p⁻_i)/2,   α_i(x) ≥ max |∂H/∂p_i|,

the central Hamiltonian plus a dissipation that vanishes where the one-sided derivatives agree.
With α_i evaluated per point ('local') the smearing is no larger than each state needs; 'global' takes
the grid-wide maximum per axis.
"""

from __future__ import annotations

import torch

from navlab.reach.finite_differences import scheme as finite_difference_scheme
from navlab.reach.grid import Grid


def dissipation_coefficients(dynamics, grid: Grid, state, kind: str) -> list:
    """α_i per axis: broadcastable tensors (local) or floats (global)."""
    alphas = dynamics.partial_max_magnitudes(state)
    if kind == "global":
        return [float(torch.as_tensor(a).max()) for a in alphas]
    return alphas


def max_rate(alphas, grid: Grid) -> float:
    """max_x Σ_i α_i(x)/h_i: the fastest a characteristic crosses cells, for the CFL condition."""
    rate = sum(a / h for a, h in zip(alphas, grid.spacing))
    return float(torch.as_tensor(rate).max())


def lax_friedrichs_numerical_hamiltonian(
    dynamics, grid: Grid, state, values: torch.Tensor, alphas, scheme: str
) -> torch.Tensor:
    """Ĥ at every grid point: the right-hand side of ∂V/∂τ = H, one axis at a time."""
    left_right = finite_difference_scheme(scheme).left_right
    central, dissipation = [], None
    for dim in range(grid.ndim):
        left, right = left_right(values, dim, grid.spacing[dim], grid.periodic[dim])
        jump = right.sub_(left)  # in place: a fresh grid-sized tensor costs more than the op on CPU
        central.append(left.add_(jump, alpha=0.5))  # (p⁻ + p⁺)/2 = p⁻ + (p⁺ − p⁻)/2
        jump.mul_(alphas[dim])
        if dissipation is None:
            dissipation = jump
        else:
            dissipation += jump
        del left, right, jump
    hamiltonian = dynamics.hamiltonian(state, central)
    del central
    return hamiltonian.add_(dissipation, alpha=0.5)
