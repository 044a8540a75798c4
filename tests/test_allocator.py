"""navlab.core.allocator: freed blocks stay in the heap (far fewer page faults per step), the results stay bit for
bit the same, and the processes a stage starts inherit the setting."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

from navlab.core.allocator import ENVIRONMENT

STEPS = textwrap.dedent("""
    import hashlib, json, resource, sys
    import torch
    from navlab.core.allocator import keep_freed_memory
    tuned = keep_freed_memory() if sys.argv[1] == "tuned" else None
    torch.set_num_threads(1)
    a = torch.linspace(0, 1, 24_000_000)
    total = torch.zeros(())
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for k in range(30):  # two 96 MB temporaries per step, freed at once, as a solver step makes them
        total += (a * k + 1.0).square().mean()
    faults = resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before
    print(json.dumps({"tuned": tuned, "faults": faults, "result": float(total)}))
""")


def _run(mode: str, script: str = STEPS) -> dict:
    import json

    env = {k: v for k, v in os.environ.items() if not k.startswith("MALLOC_")}
    out = subprocess.run([sys.executable, "-c", script, mode], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_freed_blocks_stay_in_the_heap_and_the_results_do_not_move():
    plain, tuned = _run("plain"), _run("tuned")
    if not tuned["tuned"]:
        pytest.skip("this C library has no glibc mallopt: keep_freed_memory changes nothing here")
    if plain["faults"] < 30 * 2 * 1000:  # under 1,000 faults per 96 MB block: huge pages already spare the zero-fill
        pytest.skip(f"the kernel faulted {plain['faults']} times without the setting (transparent huge pages?)")
    assert tuned["faults"] * 3 < plain["faults"], (plain, tuned)
    assert tuned["result"] == plain["result"]


def test_processes_a_stage_starts_inherit_the_setting():
    child = f"import json, os; print(json.dumps({{k: os.environ.get(k) for k in {sorted(ENVIRONMENT)!r}}}))"
    script = ("import subprocess, sys\nfrom navlab.core.allocator import keep_freed_memory\nkeep_freed_memory()\n"
              f"print(subprocess.run([sys.executable, '-c', {child!r}], capture_output=True, text=True).stdout)")
    assert _run("child", script) == ENVIRONMENT
