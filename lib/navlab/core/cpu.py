"""One CPU code path for every machine: the numerical libraries' kernels pinned to the AVX2 level.

Why: torch (ATen's vector kernels, oneDNN's convolutions), OpenCV, NumPy and OpenBLAS each choose their kernels
by the CPU's instruction sets when they load, and kernels of another vector width round differently. On one
machine, capping oneDNN at AVX instead of AVX2 gives other PACER weights after four training steps, OpenCV without
its AVX2 paths renders other training items, and ATen's generic kernels draw other ``torch.randn`` numbers
(``benchmarks/pacer_reproducibility.py``); NumPy's and SciPy's OpenBLAS runs its SkylakeX kernels on an AVX-512
CPU and its Haswell ones on an AVX2 Zen, and that alone gave PACER's phase 3 (D_synthetic's items) other weights
on a Zen 4 than on a Zen 1 (benchmarks/README.md). So an artefact trained on an AVX-512 machine cannot be rebuilt
bit for bit on an AVX2 one, and every stage downstream of it must re-run whenever it is rebuilt.

``python -m navlab`` (every DVC stage, notebook run and JupyterLab kernel it starts) therefore caps each library
at AVX2, the level of the x86-64 machines this pipeline runs on, before any of them loads. On an AVX2 machine
that changes nothing; on an AVX-512 one it gives up the wider kernels. A variable the user has set wins.
Not pinned: MKL (``MKL_CBWR`` changes none of torch's results here: its products run in oneDNN) and numba
(LLVM neither reassociates nor contracts floating point without ``fastmath``).
"""

from __future__ import annotations

import os
import platform
from collections.abc import MutableMapping
from pathlib import Path

# OpenCV's AVX-512 feature sets (cv::getHardwareFeatureName) -> the /proc/cpuinfo flags each needs, as OpenCV's
# own CPU detection combines them (core/src/system.cpp): disabling a set the CPU lacks prints a warning per name
_COMMON = ("avx512f", "avx512cd")
_SKX = (*_COMMON, "avx512bw", "avx512dq", "avx512vl")
OPENCV_AVX512: dict[str, tuple[str, ...]] = {
    "AVX512F": ("avx512f",),
    "AVX512-COMMON": _COMMON,
    "AVX512-SKX": _SKX,
    "AVX512-KNL": (*_COMMON, "avx512er", "avx512pf"),
    "AVX512-KNM": (*_COMMON, "avx512er", "avx512pf", "avx512_4fmaps", "avx512_4vnniw", "avx512_vpopcntdq"),
    "AVX512-CNL": (*_SKX, "avx512ifma", "avx512vbmi"),
    "AVX512-CLX": (*_SKX, "avx512_vnni"),
    "AVX512-ICL": (*_SKX, "avx512ifma", "avx512vbmi", "avx512_vnni", "avx512_vbmi2", "avx512_bitalg",
                   "avx512_vpopcntdq"),
}


def pins(cpu_flags: set[str], machine: str = "x86_64") -> dict[str, str]:
    """The environment that keeps torch, oneDNN, NumPy, OpenBLAS and OpenCV at the AVX2 level on a CPU with
    ``cpu_flags`` (/proc/cpuinfo's names). The other pins are caps, but OpenBLAS's is a choice that would run
    AVX2 kernels on a CPU without AVX2, so it is set only where the CPU has AVX2 and FMA. OpenCV warns on
    stderr about disabling a feature set the CPU lacks (an AVX-512 Zen 4 has no Xeon Phi KNL set), which would
    break every one-line error message, so only the sets this CPU has are named; none of this applies off
    x86-64."""
    if machine.lower() not in ("x86_64", "amd64"):
        return {}
    env = {"ATEN_CPU_CAPABILITY": "avx2", "ONEDNN_MAX_CPU_ISA": "AVX2",
           "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR"}
    if cpu_flags.issuperset(("avx2", "fma")):
        env["OPENBLAS_CORETYPE"] = "Haswell"
    present = [name for name, needs in OPENCV_AVX512.items() if cpu_flags.issuperset(needs)]
    if present:
        env["OPENCV_CPU_DISABLE"] = ",".join(present)
    return env


def cpu_flags(cpuinfo: str | Path = "/proc/cpuinfo") -> set[str]:
    """The instruction-set flags of the first CPU in ``cpuinfo`` (an empty set where there is none)."""
    try:
        text = Path(cpuinfo).read_text()
    except OSError:
        return set()
    line = next((row for row in text.splitlines() if row.startswith("flags")), "")
    return set(line.partition(":")[2].split())


def pin_code_paths(environ: MutableMapping[str, str] = os.environ) -> dict[str, str]:
    """Set ``pins`` for this machine in ``environ`` where unset; call it before torch, cv2 or numpy load.
    Returns what is in force."""
    wanted = pins(cpu_flags(), platform.machine())
    for name, value in wanted.items():
        environ.setdefault(name, value)
    return {name: environ[name] for name in wanted}
