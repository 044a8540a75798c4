"""dvc.yaml covers every notebook and artefact step, and every table it lists feeds the report index."""

from pathlib import Path

import pytest
import yaml

from navlab.pipeline.steps import artifact_steps
from navlab.pipeline.notebooks import discover
from navlab.pipeline.dvc_yaml import drifted, stale_stages
from navlab.pipeline.stages import stage_sources, uncovered

STAGES = yaml.safe_load(Path("dvc.yaml").read_text(encoding="utf8"))["stages"]
COMMANDS = {name: stage["cmd"] for name, stage in STAGES.items()}


def test_every_notebook_has_a_stage():
    for nb in discover():
        stages = [n for n, cmd in COMMANDS.items() if f"notebook run {nb.as_posix()}" in cmd]
        assert len(stages) == 1, f"{nb}: add one dvc.yaml stage running `python -m navlab notebook run {nb}`"
        assert nb.as_posix() in STAGES[stages[0]]["deps"]


def test_every_artifact_step_has_a_stage():
    for name, _ in artifact_steps():
        assert any(cmd.endswith(f"--only {name}") for cmd in COMMANDS.values()), f"no dvc stage builds {name}"


def test_every_metric_feeds_the_index():
    index_deps = set(STAGES["reports_index"]["deps"])
    for name, stage in STAGES.items():
        for metric in stage.get("metrics", []):
            path = next(iter(metric)) if isinstance(metric, dict) else metric
            assert path in index_deps, f"{path} (stage {name}) is not a dep of reports_index"
            assert path.startswith("reports/") and path.endswith(".json")


def test_dvc_runs_offline():
    config = Path(".dvc/config").read_text(encoding="utf8")
    assert "analytics = false" in config and "check_update = false" in config


@pytest.mark.parametrize("name", sorted(STAGES))
def test_stage_deps_cover_every_module_it_runs(name):
    stage = STAGES[name]
    missing = uncovered(stage_sources(stage["cmd"], "."), stage.get("deps", []))
    assert not missing, f"dvc.yaml stage {name!r}: add to its deps: {', '.join(missing)}"


def test_generated_pipeline_files_are_current():
    assert not drifted("."), "dvc.yaml / params.resolved.yaml are stale: run `python -m navlab pipeline write`"


def test_data_stage_builds_the_snapshot():
    assert STAGES["data"]["cmd"] == "python -m navlab data build"
    assert not Path("data.dvc").exists(), "data/ is recorded by the `data` stage in dvc.lock, not by data.dvc"


def test_dvc_lock_describes_the_committed_tree():
    """Every stage's recorded command, code, params and committed report match the tree (outputs merely
    absent from the cache, as on a fresh clone, are fine): a report without the lock entry that made it
    cannot land. Fix: `dvc repro`, then commit the reports with dvc.lock."""
    stale = stale_stages(".")
    assert not stale, "dvc.lock is stale:\n" + "\n".join(line[:300] for line in stale)
