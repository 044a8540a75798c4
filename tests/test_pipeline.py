"""dvc.yaml covers every notebook and artefact step, and every table it lists feeds the report index."""

import subprocess
from pathlib import Path

import pytest
import yaml

from navlab.pipeline.dvc_yaml import drifted, lock_disagreements, stale_stages
from navlab.pipeline.notebooks import discover
from navlab.pipeline.results import figures_shown
from navlab.pipeline.steps import artifact_steps
from navlab.viz.playground import is_playground

STAGES = yaml.safe_load(Path("dvc.yaml").read_text(encoding="utf8"))["stages"]
COMMANDS = {name: stage["cmd"] for name, stage in STAGES.items()}


def test_every_notebook_has_a_stage():
    """Every notebook that reproduces something; a playground (notebooks/playground/) writes no report."""
    for nb in filter(lambda nb: not is_playground(nb), discover()):
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


def test_every_figure_the_results_page_shows_is_committed_by_its_stage():
    """A fresh clone has no DVC cache: the page's figures must come with git, from outs DVC does not cache."""
    committed = [next(iter(o)) for stage in STAGES.values() for o in stage.get("outs", [])
                 if isinstance(o, dict) and next(iter(o.values())).get("cache") is False]
    tracked = set(subprocess.run(["git", "ls-files", "reports"], capture_output=True, text=True, check=True).stdout.split())
    for source in (f.path for chosen in figures_shown().values() for f in chosen):
        path = f"reports/{source}"
        assert any(path == o or path.startswith(o + "/") for o in committed), f"{path}: no stage commits it"
        assert path in tracked, f"{path} is not in git: un-ignore it in .gitignore and commit it"


def test_dvc_runs_offline():
    config = Path(".dvc/config").read_text(encoding="utf8")
    assert "analytics = false" in config and "check_update = false" in config


def test_generated_pipeline_files_are_current():
    assert not drifted("."), "dvc.yaml / params.resolved.yaml are stale: run `python -m navlab pipeline write`"


def test_data_stage_builds_the_snapshot():
    assert STAGES["data"]["cmd"] == "python -m navlab data build"
    assert not Path("data.dvc").exists(), "data/ is recorded by the `data` stage in dvc.lock, not by data.dvc"


# Stages whose committed report is known to come from older code, each with the reason; the test below
# fails when any other stage is stale, and when one of these becomes current (then delete its line).
KNOWN_STALE: dict[str, str] = {}


@pytest.mark.provenance
def test_dvc_lock_describes_the_committed_tree():
    """Every stage's recorded command, code, params and committed report match the tree (outputs merely
    absent from the cache, as on a fresh clone, are fine): a report without the lock entry that made it
    cannot land. Fix: `dvc repro`, then commit the reports with dvc.lock."""
    stale = stale_stages(".")
    unexpected = [line for line in stale if line.split(":")[0] not in KNOWN_STALE]
    assert not unexpected, "dvc.lock is stale:\n" + "\n".join(unexpected)
    assert {line.split(":")[0] for line in stale} == set(KNOWN_STALE), "a known-stale stage is current now: " \
        "delete it from KNOWN_STALE"


def _lock_pair(tmp_path, upstream_md5: str, deps=("up", "lib/b.py")) -> Path:
    """A two-stage dvc.yaml (``a`` makes ``up``, ``b`` reads it) and a dvc.lock recording ``b`` as made from
    ``up`` with ``upstream_md5`` (``a`` recorded ``up`` as m1.dir)."""
    (tmp_path / "dvc.yaml").write_text(yaml.safe_dump({"stages": {
        "a": {"cmd": "make up", "deps": ["lib/a.py"], "outs": ["up"]},
        "b": {"cmd": "make b", "deps": ["up", "lib/b.py"], "metrics": [{"reports/b.json": {"cache": False}}]},
    }}))
    (tmp_path / "dvc.lock").write_text(yaml.safe_dump({"schema": "2.0", "stages": {
        "a": {"cmd": "make up", "deps": [{"path": "lib/a.py", "md5": "x"}], "outs": [{"path": "up", "md5": "m1.dir"}]},
        "b": {"cmd": "make b", "deps": [{"path": p, "md5": upstream_md5 if p == "up" else "y"} for p in deps],
              "outs": [{"path": "reports/b.json", "md5": "z"}]},
    }}))
    return tmp_path


def test_a_consistent_lock_has_no_disagreements(tmp_path):
    assert lock_disagreements(_lock_pair(tmp_path, "m1.dir")) == []


def test_a_stage_made_from_an_older_upstream_output_is_stale(tmp_path):
    """What `dvc status` cannot see on a fresh clone, where ``up`` does not exist to be hashed."""
    assert lock_disagreements(_lock_pair(tmp_path, "m0.dir")) == ["b: made from another up than stage a recorded"]


def test_a_dep_dropped_from_dvc_yaml_or_a_stage_never_run_is_stale(tmp_path):
    root = _lock_pair(tmp_path, "m1.dir", deps=("up", "lib/b.py", "lib/gone.py"))
    assert lock_disagreements(root) == ["b: dvc.lock records other deps than dvc.yaml declares"]
    lock = yaml.safe_load((root / "dvc.lock").read_text())
    del lock["stages"]["b"]
    (root / "dvc.lock").write_text(yaml.safe_dump(lock))
    assert lock_disagreements(root) == ["b: never recorded in dvc.lock"]
