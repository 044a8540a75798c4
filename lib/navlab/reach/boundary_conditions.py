"""Ghost cells for one-sided finite differences: periodic axes wrap, the others extrapolate linearly.

Linear extrapolation (as in hj_reachability's ``extrapolate``) keeps the slope at the edge, so a
signed-distance-like value keeps growing outwards instead of reflecting information back into the grid.
"""

from __future__ import annotations

import torch


def pad(values: torch.Tensor, dim: int, width: int, periodic: bool) -> torch.Tensor:
    """``values`` with ``width`` ghost cells on both ends of axis ``dim``."""
    n = values.shape[dim]
    if periodic and width > n:
        raise ValueError(f"periodic axis {dim} has {n} nodes, fewer than the {width} ghost cells the scheme "
                         f"reads on each side; give that axis at least {width} nodes or use a narrower scheme")
    if periodic:
        return torch.cat([values.narrow(dim, n - width, width), values, values.narrow(dim, 0, width)], dim)
    steps_shape = [1] * values.ndim
    steps_shape[dim] = width
    steps = torch.arange(1, width + 1, device=values.device, dtype=values.dtype).reshape(steps_shape)
    first, second = values.narrow(dim, 0, 1), values.narrow(dim, 1, 1)
    last, before_last = values.narrow(dim, n - 1, 1), values.narrow(dim, n - 2, 1)
    low = first + (first - second) * steps.flip(dim)
    high = last + (last - before_last) * steps
    return torch.cat([low, values, high], dim)


def padded_differences(values: torch.Tensor, dim: int, spacing: float, width: int, periodic: bool):
    """First divided differences D[k] = (φ[k+1] − φ[k]) / h on the padded axis.

    Index k of the result is the face between padded nodes k and k+1; grid node i sits at padded
    index i + width, so its left face is D[i + width − 1] and its right face D[i + width].
    """
    padded = pad(values, dim, width, periodic)
    return torch.diff(padded, dim=dim).div_(spacing)
