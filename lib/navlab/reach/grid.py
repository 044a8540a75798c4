"""Dense state grids for level-set methods: axes, spacing, periodic dimensions (e.g. heading θ).

Nodes sit at ``lo + i * spacing``. A periodic axis spans ``[lo, hi)`` (``hi`` is ``lo`` again, not a
node); a non-periodic axis spans ``[lo, hi]`` with both ends as nodes. States are never materialised
as an N×d array: ``axes`` are 1-D and broadcast with ``mesh``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch


@dataclass(frozen=True)
class Grid:
    lo: tuple[float, ...]
    hi: tuple[float, ...]
    shape: tuple[int, ...]
    periodic: tuple[bool, ...]

    def __post_init__(self):
        n = len(self.shape)
        if not (len(self.lo) == len(self.hi) == len(self.periodic) == n):
            raise ValueError(f"Grid: lo, hi, shape and periodic need one entry per dimension ({n})")
        if not all(math.isfinite(b) for b in (*self.lo, *self.hi)):
            raise ValueError(f"Grid: bounds must be finite numbers, got lo={self.lo}, hi={self.hi}")
        if any(s < 2 for s in self.shape) or any(h <= lo for lo, h in zip(self.lo, self.hi)):
            raise ValueError(f"Grid: need shape >= 2 and hi > lo per dimension, got {self}")

    @property
    def ndim(self) -> int:
        return len(self.shape)

    @property
    def spacing(self) -> tuple[float, ...]:
        return tuple(
            (h - lo) / (s if p else s - 1) for lo, h, s, p in zip(self.lo, self.hi, self.shape, self.periodic)
        )

    def axis(self, dim: int) -> np.ndarray:
        return self.lo[dim] + np.arange(self.shape[dim]) * self.spacing[dim]

    def axes(self, device: str | torch.device = "cpu", dtype=torch.float32) -> list[torch.Tensor]:
        return [torch.as_tensor(self.axis(d), device=device, dtype=dtype) for d in range(self.ndim)]

    def mesh(self, dim: int, device: str | torch.device = "cpu", dtype=torch.float32) -> torch.Tensor:
        """Coordinate ``dim`` as a tensor broadcastable to ``shape`` (size 1 on the other axes)."""
        view = [1] * self.ndim
        view[dim] = self.shape[dim]
        return self.axes(device, dtype)[dim].reshape(view)
