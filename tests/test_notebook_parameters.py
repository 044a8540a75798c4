"""resolve_parameters: given values win, then $NAVLAB_*, then the checkout's folders, from any directory."""

import pytest

from navlab.core.params import ParamsError, load_params, repo_root
from navlab.pipeline.notebooks import ENVIRONMENT, resolve_parameters


@pytest.fixture
def clean_env(monkeypatch):
    for var in ENVIRONMENT.values():
        monkeypatch.delenv(var, raising=False)
    return monkeypatch


def test_defaults_come_from_the_checkout_whatever_the_working_directory(clean_env):
    root = repo_root()
    clean_env.chdir(root / "notebooks" / "pacer")
    profile, data, artifacts, reports = resolve_parameters()
    assert profile == load_params().profile  # params.yaml's `profile` key, what `dvc repro` runs
    assert (data, artifacts, reports) == (root / "data", root / "artifacts", root / "reports")


def test_environment_then_given_values(clean_env, tmp_path):
    root = repo_root()
    clean_env.setenv("NAVLAB_PROFILE", "smoke")
    clean_env.setenv("NAVLAB_DATA_DIR", str(tmp_path / "d"))
    clean_env.setenv("NAVLAB_REPORTS_DIR", "elsewhere/reports")  # relative: from the checkout root
    clean_env.chdir(tmp_path)
    assert resolve_parameters() == ("smoke", tmp_path / "d", root / "artifacts", root / "elsewhere" / "reports")
    given = resolve_parameters("paper", tmp_path / "x", str(tmp_path / "y"), "z")
    assert given == ("paper", tmp_path / "x", tmp_path / "y", root / "z")


def test_bad_profile_in_the_environment_names_the_variable(clean_env):
    clean_env.setenv("NAVLAB_PROFILE", "smok")
    with pytest.raises(ParamsError, match="NAVLAB_PROFILE='smok': allowed profiles are smoke"):
        resolve_parameters()
    with pytest.raises(ParamsError, match="profile = 'big'"):
        resolve_parameters("big")
