"""Memory budgets, by the machine a profile targets: what `params check` compares each stage's estimate with.

smoke and default run on the shared 2-core CPU machine (23 GiB RAM): 16 GiB leaves room for the OS, a
notebook kernel and a second job. gpu and paper target one single-GPU machine (an 80 GB H100 shows ~78 GiB
to torch; 128 GiB RAM, of which 3/4 for one stage).
"""

from __future__ import annotations

from navlab.core.params import Params

GIB = 2**30
CPU_MACHINE_RAM_GIB = 16.0
GPU_MACHINE_RAM_GIB = 96.0
GPU_MEMORY_GIB = 78.0


def budget_gib(params: Params, device: str) -> float:
    """Memory one stage may use on ``device`` ("cpu" or "cuda") under this profile (see the constants)."""
    if device == "cuda":
        return GPU_MEMORY_GIB
    return GPU_MACHINE_RAM_GIB if params.profile in ("gpu", "paper") else CPU_MACHINE_RAM_GIB
