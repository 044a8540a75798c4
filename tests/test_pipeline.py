"""dvc.yaml covers every notebook and artefact step, and every table it lists feeds the report index."""

from pathlib import Path

import yaml

from navlab.cli import artifact_steps
from navlab.pipeline.notebooks import discover

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
