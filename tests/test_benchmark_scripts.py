"""Every script under benchmarks/ still runs: each one end to end on the smoke data and artefacts.

Why: the scripts are no pipeline stage, so nothing else exercises them, and they break silently when the
library moves under them (the recognition reference once raised for sessions before anyone noticed; the
target-layouts script stopped training when checkpoint selection moved to map windows). A script is run as
a user would, with arguments that make it tiny; a script that cannot run here (JAX, CUDA) is still
imported, and one added without a line below fails ``test_every_script_is_covered``.
"""

from __future__ import annotations

import os
import runpy
import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"

# script -> its arguments; {data}, {artifacts}, {out} stand for the smoke data, smoke artefacts, a temp folder
RUNS = {
    "frechet.py": ["--points", "20", "--repeats", "1"],
    "allocator_margin.py": ["--refine", "1", "1", "1", "1", "--horizon", "0.05", "--repeats", "1"],
    "region_graph.py": ["--size", "64", "--nodes", "30", "--repeats", "1"],
    "stack_replan.py": ["--profile", "smoke", "--episodes", "1", "--data-dir", "{data}", "--artifacts-dir",
                        "{artifacts}", "--out", "{out}/replan.json"],
    "grid_astar.py": ["--data-dir", "{data}", "--queries", "2", "--walks", "1"],
    "diff_astar.py": ["--data", "{data}", "--graphs", "1", "--nodes", "200", "--repeats", "1"],
    "pacer_data.py": ["--profile", "smoke", "--items", "4", "--data-dir", "{data}"],
    "pacer_inference.py": ["--repeats", "1", "--batch", "2", "--paper-batch", "1", "--threads", "1",
                           "--reports-dir", "{out}"],
    "pacer_target_layouts.py": ["--profile", "smoke", "--epochs", "1", "--street", "0", "--targets", "in_view",
                                "--data", "{data}", "--artifacts", "{artifacts}", "--out", "{out}"],
    "pacer_pretrained_cost.py": ["--profile", "smoke", "--batch", "2", "--repeats", "1", "--threads", "1"],
    "pacer_texture_towers.py": ["--profile", "smoke", "--towers", "committed", "pooled", "luminance", "both", "balanced",
                                "supervised", "pretrained", "--steps", "2",
                                "--hold-out", "box_tree", "roughcast", "stone_wall", "grey_tile", "--eval-every", "1",
                                "--data-dir", "{data}", "--artifacts-dir", "{artifacts}"],
    "pacer_matcher_readouts.py": ["--profile", "smoke", "--maps", "1", "--threads", "1", "--data-dir", "{data}",
                                  "--artifacts-dir", "{artifacts}", "--out", "{out}/readouts.json"],
    "pacer_transductive_labels.py": ["--profile", "smoke", "--maps", "1", "--threads", "1", "--data-dir", "{data}",
                                     "--artifacts-dir", "{artifacts}", "--out", "{out}/transductive.json"],
    "playground_pacer.py": ["--profile", "smoke", "--maps", "1", "--data-dir", "{data}",
                            "--artifacts-dir", "{artifacts}"],
    "playground_surenav.py": ["--profile", "smoke", "--tiles", "1", "--data-dir", "{data}",
                              "--artifacts-dir", "{artifacts}"],
    "hj_planner.py": ["--profile", "smoke", "--artifacts", "{artifacts}", "--calls", "100", "--tasks", "1",
                      "--max-expansions", "2000"],
    "hj_state_lattice.py": ["--profile", "smoke", "--artifacts", "{artifacts}", "--pairs", "2", "--tables", "1"],
    "hj_closed_loop.py": ["--profile", "smoke", "--artifacts", "{artifacts}"],
    "hj_search_rows.py": ["--profile", "smoke", "--artifacts", "{artifacts}", "--pairs", "2"],
    "hj_closed_loop_spread.py": ["--profile", "smoke", "--artifacts", "{artifacts}", "--first", "0", "--runs", "1",
                                 "--workers", "1"],
    "surenav_context.py": ["--profile", "smoke", "--data", "{data}", "--artifacts", "{artifacts}",
                           "--out", "{out}/context.json"],
    "surenav_workers.py": ["--profile", "smoke", "--every", "30", "--data", "{data}", "--artifacts", "{artifacts}"],
    "surenav_estimator_fit.py": ["train", "--epochs", "1", "--profile", "smoke", "--artifacts", "{artifacts}"],
    "pacer_reproducibility.py": ["--profile", "smoke", "--steps", "1", "--data", "{data}", "--dataset", "synthetic",
                                 "--variants",
                                 "profile's settings", "navlab's pins (python -m navlab)"],
    "hj_paper_scaling.py": ["--scales", "0.03", "0.04", "--steps", "1", "--kinds", "static_brt", "--eager"],
}
# script -> why it is only imported here
IMPORTED_ONLY = {
    "hj_solver.py": "compares against hj_reachability, which runs in its own JAX venv (requirements-hj.txt)",
    "hj_cuda_timing.py": "times CPU against CUDA: needs a GPU",
    "playground_hj.py": "minutes even on the smoke grids; tests/test_playground_hj.py drives the same widgets",
    "pacer_recognition_reference.py": "run end to end by tests/test_pacer_segmenter.py",
}


def test_every_script_is_covered():
    scripts = {p.name for p in BENCHMARKS.glob("*.py")}
    assert scripts == set(RUNS) | set(IMPORTED_ONLY), (
        f"benchmarks/ scripts without a smoke run or a reason: {sorted(scripts - set(RUNS) - set(IMPORTED_ONLY))}; "
        f"listed but missing: {sorted(set(RUNS) | set(IMPORTED_ONLY) - scripts)}")


@pytest.mark.parametrize("script", sorted(IMPORTED_ONLY))
def test_script_imports(script):
    """Its module level (the library names it imports) still resolves; main() is not run."""
    namespace = runpy.run_path(str(BENCHMARKS / script), run_name="benchmark_import_check")
    assert callable(namespace["main"])


@pytest.mark.parametrize("script", sorted(RUNS))
def test_script_runs_on_smoke_inputs(script, smoke_data, smoke_artifacts, tmp_path):
    fill = {"data": str(smoke_data), "artifacts": str(smoke_artifacts), "out": str(tmp_path)}
    command = [sys.executable, str(BENCHMARKS / script), *(arg.format(**fill) for arg in RUNS[script])]
    env = os.environ | {"OMP_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    done = subprocess.run(command, check=False, capture_output=True, text=True, timeout=600, env=env,
                          cwd=tmp_path)
    assert done.returncode == 0, f"{' '.join(command)}\n{done.stdout[-1500:]}\n{done.stderr[-3000:]}"
    assert done.stdout.strip(), f"{script} printed nothing"
