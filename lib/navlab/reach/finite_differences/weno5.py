"""Fifth-order WENO (Jiang & Peng 2000; Osher & Fedkiw, Level Set Methods, Sec. 3.4).

Three third-order ENO candidates are blended with weights from their smoothness; on smooth data the
blend is fifth-order, near a kink it falls back to the smoothest candidate. The candidates are added
one at a time so that at most four grid-sized temporaries live at once.
"""

from __future__ import annotations

import torch

from navlab.reach.boundary_conditions import padded_differences

EPSILON = 1e-6
LINEAR_WEIGHTS = (0.1, 0.6, 0.3)


def _smoothness(k, v1, v2, v3, v4, v5):
    if k == 0:
        return 13 / 12 * (v1 - 2 * v2 + v3).square_() + 0.25 * (v1 - 4 * v2 + 3 * v3).square_()
    if k == 1:
        return 13 / 12 * (v2 - 2 * v3 + v4).square_() + 0.25 * (v2 - v4).square_()
    return 13 / 12 * (v3 - 2 * v4 + v5).square_() + 0.25 * (3 * v3 - 4 * v4 + v5).square_()


def _candidate(k, v1, v2, v3, v4, v5):
    if k == 0:
        return v1 / 3 - 7 / 6 * v2 + 11 / 6 * v3
    if k == 1:
        return -v2 / 6 + 5 / 6 * v3 + v4 / 3
    return v3 / 3 + 5 / 6 * v4 - v5 / 6


def _blend(*v):
    """WENO derivative from five consecutive differences v1..v5, v3 the face on the upwind side."""
    out = total = None
    for k, linear_weight in enumerate(LINEAR_WEIGHTS):
        weight = _smoothness(k, *v).add_(EPSILON).square_().reciprocal_().mul_(linear_weight)
        term = _candidate(k, *v).mul_(weight)
        if out is None:
            out, total = term, weight
        else:
            out += term
            total += weight
            del term, weight
    return out.div_(total)


def left_right(values: torch.Tensor, dim: int, spacing: float, periodic: bool):
    n = values.shape[dim]
    d = padded_differences(values, dim, spacing, 3, periodic)  # node i: left face at i+2, right at i+3
    face = [d.narrow(dim, k, n) for k in range(6)]  # face[k] = D at padded face i+k for node i
    left = _blend(face[0], face[1], face[2], face[3], face[4])
    right = _blend(face[5], face[4], face[3], face[2], face[1])
    return left, right
