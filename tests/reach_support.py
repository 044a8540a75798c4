"""Helpers shared by the reach tests: an independent multilinear interpolator."""

from __future__ import annotations

import torch

from navlab.reach.lookup import _rotate, _stack, wrap_angle


def interpolate(grid, values: torch.Tensor, points: list[torch.Tensor]) -> torch.Tensor:
    """Multilinear interpolation of grid ``values`` at a batch of states (one 1-D tensor per axis).

    Written independently of navlab's lookups on purpose: the tests should not trust the code under test.
    Periodic axes wrap; others clamp to the grid.
    """
    index, weight = [], []
    for d, x in enumerate(points):
        pos = (x - grid.lo[d]) / grid.spacing[d]
        n = grid.shape[d]
        if grid.periodic[d]:
            pos = torch.remainder(pos, n)
            i0 = torch.floor(pos).long()
            index.append((i0 % n, (i0 + 1) % n))
        else:
            pos = pos.clamp(0, n - 1)
            i0 = torch.floor(pos).long().clamp(max=n - 2)
            index.append((i0, i0 + 1))
        weight.append(pos - i0)
    out = torch.zeros_like(points[0])
    for corner in range(2**grid.ndim):
        bits = [(corner >> d) & 1 for d in range(grid.ndim)]
        w = torch.ones_like(points[0])
        for d, b in enumerate(bits):
            w = w * (weight[d] if b else 1 - weight[d])
        out += w * values[tuple(index[d][b] for d, b in enumerate(bits))]
    return out


# Inverses of navlab.reach.lookup's frame changes: only the tests that check the round trip need them.


def from_goal_frame(states, goal_xy, goal_heading=0.0):
    """Inverse of ``to_goal_frame``."""
    x, y = _rotate(states[:, 0], states[:, 1], goal_heading)
    return _stack([x + goal_xy[..., 0], y + goal_xy[..., 1], states[:, 2],
                   wrap_angle(states[:, 3] + goal_heading)])


def from_robot_frame(robot_states, rel_xy):
    """Inverse of ``to_robot_frame``: world position of a human seen at ``rel_xy`` by each robot state."""
    x, y = _rotate(rel_xy[..., 0], rel_xy[..., 1], robot_states[:, 3])
    return _stack([x + robot_states[:, 0], y + robot_states[:, 1]])
