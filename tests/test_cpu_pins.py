"""The CPU code-path pins of ``python -m navlab`` (navlab.core.cpu).

Why a test: a pin that a library does not read, or that is set after the library loaded, silently leaves a
trained artefact machine-dependent (benchmarks/pacer_reproducibility.py measures what each path changes).
"""

import json
import subprocess
import sys

from navlab.core.cpu import OPENCV_AVX512, cpu_flags, pins

PROBE = """
import json, os, runpy, sys
sys.argv = ["navlab", "params", "show", "--profile", "smoke"]
try:
    runpy.run_module("navlab", run_name="__main__")
except SystemExit:
    pass
import cv2, torch
import ctypes, glob, numpy
cores = []  # the kernels NumPy's bundled OpenBLAS chose (numpy.libs holds it in PyPI's wheels)
for path in glob.glob(os.path.join(os.path.dirname(numpy.__file__), os.pardir, "numpy.libs", "*openblas*")):
    lib = ctypes.CDLL(path)
    for name in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename", "openblas_get_corename64_",
                 "openblas_get_corename"):
        if hasattr(lib, name):
            getattr(lib, name).restype = ctypes.c_char_p
            cores.append(getattr(lib, name)().decode())
            break
print(json.dumps({"env": {k: os.environ.get(k) for k in ("ATEN_CPU_CAPABILITY", "ONEDNN_MAX_CPU_ISA",
                  "NPY_DISABLE_CPU_FEATURES", "OPENCV_CPU_DISABLE", "OPENBLAS_CORETYPE")},
                  "aten": torch.backends.cpu.get_cpu_capability(), "opencv": cv2.getCPUFeaturesLine(),
                  "openblas": cores}))
"""


def test_the_pins_cap_each_library_at_avx2_only_on_x86():
    avx2 = pins({"avx2", "fma"})
    assert avx2["ATEN_CPU_CAPABILITY"] == "avx2" and avx2["ONEDNN_MAX_CPU_ISA"] == "AVX2"
    assert avx2["OPENBLAS_CORETYPE"] == "Haswell"
    assert "OPENBLAS_CORETYPE" not in pins({"sse2", "avx"})  # a forced Haswell kernel would not run there
    assert "OPENCV_CPU_DISABLE" not in avx2  # OpenCV warns about disabling what the CPU lacks
    assert pins({"avx2", "avx512f"})["OPENCV_CPU_DISABLE"] == "AVX512F"
    skx = {"avx2", *OPENCV_AVX512["AVX512-SKX"]}
    assert pins(skx)["OPENCV_CPU_DISABLE"].split(",") == ["AVX512F", "AVX512-COMMON", "AVX512-SKX"]
    # a Zen 4 (every set but the Xeon Phi ones): naming KNL or KNM would print OpenCV's warning on every start
    zen4 = skx | {"avx512ifma", "avx512vbmi", "avx512_vnni", "avx512_vbmi2", "avx512_bitalg", "avx512_vpopcntdq"}
    assert set(pins(zen4)["OPENCV_CPU_DISABLE"].split(",")) == set(OPENCV_AVX512) - {"AVX512-KNL", "AVX512-KNM"}
    assert pins({"avx512f"}, machine="aarch64") == {}


def test_cpu_flags_read_the_first_cpu(tmp_path):
    info = tmp_path / "cpuinfo"
    info.write_text("processor\t: 0\nflags\t\t: fpu sse2 avx2 fma\n\nprocessor\t: 1\nflags\t\t: fpu avx512f\n")
    assert cpu_flags(info) == {"fpu", "sse2", "avx2", "fma"}
    assert cpu_flags(tmp_path / "missing") == set()


def test_python_m_navlab_sets_the_pins_before_torch_and_opencv_load():
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, check=True)
    found = json.loads(out.stdout.strip().splitlines()[-1])
    assert found["env"] == {**{k: None for k in found["env"]}, **pins(cpu_flags())}
    if pins(cpu_flags()):  # x86-64: torch runs its AVX2 kernels, whatever wider ones the CPU has
        assert found["aten"] == "AVX2"
        assert all(core == "Haswell" for core in found["openblas"]), found["openblas"]
    # OpenCV marks each feature set it may not dispatch to with "?": every AVX-512 one, pinned or absent
    assert all(token.endswith("?") for token in found["opencv"].split() if "AVX512" in token)
    assert "unknown CPU feature" not in out.stderr and "unavailable CPU feature" not in out.stderr
