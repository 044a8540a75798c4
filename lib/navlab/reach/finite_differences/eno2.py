"""Second-order ENO (Osher & Fedkiw, Level Set Methods, Sec. 3.3).

The first-order difference is corrected by half a cell times the second difference of smaller
magnitude (the smoother of the two candidate stencils), which avoids differencing across a kink.
"""

from __future__ import annotations

import torch

from navlab.reach.boundary_conditions import padded_differences


def left_right(values: torch.Tensor, dim: int, spacing: float, periodic: bool):
    n = values.shape[dim]
    d = padded_differences(values, dim, spacing, 2, periodic)  # faces: node i has left face i+1
    dd = torch.diff(d, dim=dim)  # (D[k+1] − D[k]) = h · φ_xx at padded node k+1; node i at index i+1
    # smaller-magnitude second difference between node pairs (i−1, i) and (i, i+1)
    lower, upper = dd.narrow(dim, 0, n + 1), dd.narrow(dim, 1, n + 1)
    smooth = torch.where(lower.abs() <= upper.abs(), lower, upper)  # index j: nodes (j−1, j)
    left = d.narrow(dim, 1, n) + 0.5 * smooth.narrow(dim, 0, n)
    right = d.narrow(dim, 2, n) - 0.5 * smooth.narrow(dim, 1, n)
    return left, right
