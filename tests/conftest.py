"""Shared fixtures: a smoke-profile dataset and artefacts, built once per test session."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from navlab.core.params import load_params

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session", autouse=True)
def _in_checkout():
    os.chdir(ROOT)


@pytest.fixture(autouse=True)
def _torch_state_stays_in_its_test():
    """A test (or the library code it calls: training sets its thread count) may change torch's global
    state; restore it, so no test's numbers depend on which tests ran before it."""
    import torch

    threads, deterministic = torch.get_num_threads(), torch.are_deterministic_algorithms_enabled()
    rng = torch.get_rng_state()
    yield
    torch.set_num_threads(threads)
    torch.use_deterministic_algorithms(deterministic)
    torch.set_rng_state(rng)


@pytest.fixture(scope="session")
def smoke_params():
    return load_params("smoke")


@pytest.fixture(scope="session")
def smoke_data(tmp_path_factory, smoke_params) -> Path:
    """data/ built with the smoke profile into a temporary folder (downloads are cached)."""
    from navlab.pipeline.steps import data_steps
    from navlab.pipeline import dataset

    return dataset.build(tmp_path_factory.mktemp("smoke") / "data", smoke_params, data_steps(), log=lambda m: None)


@pytest.fixture(scope="session")
def smoke_artifacts(tmp_path_factory, smoke_params, smoke_data) -> Path:
    """Every artefact step (HJ grids, trained models) for the smoke profile."""
    from navlab.pipeline.steps import artifact_steps

    out = tmp_path_factory.mktemp("smoke_artifacts")
    for _, step in artifact_steps():
        step(smoke_params, smoke_data, out)
    return out
