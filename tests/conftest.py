"""Shared fixtures: a smoke-profile dataset and artefacts, built once per test session."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from navlab.core.allocator import keep_freed_memory
from navlab.core.params import load_params

ROOT = Path(__file__).resolve().parents[1]
keep_freed_memory()  # as `python -m navlab` does for every stage; papermill's kernels inherit it (core.allocator)


@pytest.fixture(scope="session", autouse=True)
def _in_checkout():
    os.chdir(ROOT)


def _torch_baseline() -> tuple[int, bool, bool]:
    import torch

    return (torch.get_num_threads(), torch.are_deterministic_algorithms_enabled(),
            torch.is_deterministic_algorithms_warn_only_enabled())


TORCH_BASELINE = _torch_baseline()  # taken at collection, before any fixture trains a model


@pytest.fixture(autouse=True)
def _torch_state_is_the_baseline():
    """Every test starts from the process's own torch state, and its RNG state is put back after it: the
    library's training sets the thread count (in session fixtures too, which run before any function
    fixture), and no test's numbers may depend on which tests ran before it."""
    import torch

    def reset():
        threads, deterministic, warn_only = TORCH_BASELINE
        torch.set_num_threads(threads)
        torch.use_deterministic_algorithms(deterministic, warn_only=warn_only)

    rng = torch.get_rng_state()
    reset()
    yield
    reset()
    torch.set_rng_state(rng)


@pytest.fixture
def single_thread():
    """One intra-op thread: small models and grids run faster on one, and on a busy 2-core machine OpenMP's
    second thread spins against the other load (a tiny training step measured 60x slower with two)."""
    import torch

    torch.set_num_threads(1)
    yield  # the autouse fixture above puts the baseline back


@pytest.fixture(scope="session")
def smoke_params():
    return load_params("smoke")


@pytest.fixture(scope="session")
def smoke_data(tmp_path_factory, smoke_params) -> Path:
    """data/ built with the smoke profile into a temporary folder (downloads are cached)."""
    from navlab.pipeline import dataset
    from navlab.pipeline.steps import data_steps

    return dataset.build(tmp_path_factory.mktemp("smoke") / "data", smoke_params, data_steps(), log=lambda m: None)


@pytest.fixture(scope="session")
def smoke_artifacts(tmp_path_factory, smoke_params, smoke_data) -> Path:
    """Every artefact step (HJ grids, trained models) for the smoke profile."""
    from navlab.pipeline.steps import artifact_steps

    out = tmp_path_factory.mktemp("smoke_artifacts")
    for _, step in artifact_steps():
        step(smoke_params, smoke_data, out)
    return out
