"""Keep freed memory in the process: by default glibc's malloc hands every large block back to the kernel.

Why: glibc serves an allocation above its mmap threshold (128 KiB, raised on the fly to at most 32 MiB) with a
fresh mapping that it unmaps on free, and it trims the heap's free top beyond 128 KiB. The level-set solver
(``navlab.reach``) and the trainers allocate temporaries of tens to hundreds of MB at every step, so the kernel
zero-filled them page by page again at every step: the ``hj_margins`` stage spent 1,521 s in the kernel beside
1,111 s of its own work (benchmarks/README.md, "Freed memory kept"). With both thresholds raised to 1 GiB, freed
blocks stay in the heap for the next step. The results are bit for bit the same (only where memory comes from
changes); the resident size stays near its peak instead of falling between steps.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os

M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # glibc's mallopt parameters (malloc.h)
THRESHOLD = 1 << 30  # bytes: blocks below it are served from, and freed back into, the heap
ENVIRONMENT = {"MALLOC_MMAP_THRESHOLD_": str(THRESHOLD), "MALLOC_TRIM_THRESHOLD_": str(THRESHOLD)}


def keep_freed_memory() -> bool:
    """Raise glibc's mmap and trim thresholds in this process, and through the environment in every process
    it starts (papermill's kernels, data-loader and queue workers). True where glibc took both; False where the
    C library has no ``mallopt`` or refuses (not glibc): nothing changes there but the environment, which only
    glibc reads. A value already in the environment is kept."""
    for name, value in ENVIRONMENT.items():
        os.environ.setdefault(name, value)
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
    except OSError:
        return False
    mallopt = getattr(libc, "mallopt", None)
    if mallopt is None:
        return False
    mallopt.argtypes, mallopt.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    values = {parameter: int(os.environ[name]) for parameter, name in
              ((M_MMAP_THRESHOLD, "MALLOC_MMAP_THRESHOLD_"), (M_TRIM_THRESHOLD, "MALLOC_TRIM_THRESHOLD_"))
              if os.environ[name].isdigit() and int(os.environ[name]) < 2**31}
    return len(values) == 2 and all(mallopt(parameter, value) == 1 for parameter, value in values.items())
