"""Every random draw in navlab comes from here, keyed by a seed from params.yaml and a purpose.

Keys make streams independent: adding a new consumer never shifts the numbers another one draws.
torch is imported only by the torch helpers: the maps, graphs and data-build code that draws with
numpy would otherwise pay seconds of torch import for nothing.
"""

from __future__ import annotations

import hashlib
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import torch


def _entropy(seed: int, keys: tuple[object, ...]) -> list[int]:
    words = [int(seed)]
    for key in keys:
        digest = hashlib.sha256(repr(key).encode()).digest()
        words.append(int.from_bytes(digest[:8], "little"))
    return words


def rng(seed: int, *keys: object) -> np.random.Generator:
    """A numpy Generator for (seed, *keys), e.g. ``rng(params.data.seed, "procedural", map_index)``."""
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(_entropy(seed, keys))))


def torch_generator(seed: int, *keys: object, device: str | torch.device = "cpu") -> torch.Generator:
    """A torch Generator for (seed, *keys) on ``device``."""
    import torch

    sub = np.random.SeedSequence(_entropy(seed, keys)).generate_state(1, dtype=np.uint64)[0]
    gen = torch.Generator(device=device)
    gen.manual_seed(int(sub) & 0x7FFF_FFFF_FFFF_FFFF)
    return gen
