"""The HJ sensitivity sweep on DVC's experiment queue (issue 26): one experiment per point, collected by the
file name its inputs hash to. The glue is tested against a real DVC repository (experiments run with
``dvc exp run --temp``, the queue's own executor without the worker)."""

import dataclasses
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from navlab.core.io import DataError
from navlab.core.params import load_params
from navlab.hj.sweeps import Point, point_file, selected_points, sweep_points
from navlab.pipeline import experiments
from navlab.pipeline.dvc_yaml import render_resolved_params


def _with_sensitivity(params, **changes):
    return dataclasses.replace(params, hj=dataclasses.replace(
        params.hj, sensitivity=dataclasses.replace(params.hj.sensitivity, **changes)))


def test_point_names_are_unique_and_only_selects_by_them():
    params = load_params("default")
    points = sweep_points(params)
    names = [p.name for p in points]
    assert len(set(names)) == len(names) and "budget-500" in names
    assert Point("loop", (12.0, 0.1, 1.5)).name == "loop-12hz-0.1m-1.5s"
    assert selected_points(params) == points  # only = (): every point
    one = points[-1]
    assert selected_points(_with_sensitivity(params, only=(one.name,))) == [one]
    with pytest.raises(ValueError, match="budget-7.*not a point of this sweep"):
        selected_points(_with_sensitivity(params, only=("budget-7",)))


def test_queue_overrides_set_one_point_in_both_parameter_files(tmp_path):
    """What `dvc exp run -S` writes: params.yaml then selects the point, and params.resolved.yaml holds the
    same values as the resolver renders (the check every stage command makes under `dvc repro`)."""
    root = Path(__file__).resolve().parents[1]
    point = sweep_points(load_params("default"))[1]
    args = experiments.queue_arguments(point)
    assert args[0::2] == ["-S", "-S"]
    raw = yaml.safe_load((root / "params.yaml").read_text())
    resolved = yaml.safe_load(render_resolved_params(root))
    for override in args[1::2]:
        file, assignment = override.split(":", 1)
        key, value = assignment.split("=", 1)
        target = raw if file == "params.yaml" else resolved
        *path, leaf = key.split(".")
        for part in path:
            target = target[part]
        target[leaf] = yaml.safe_load(value)
    (tmp_path / "params.yaml").write_text(yaml.safe_dump(raw))
    params = load_params(path=tmp_path / "params.yaml")
    assert selected_points(params) == [point]
    assert yaml.safe_load(render_resolved_params(tmp_path)) == resolved


def _git(cwd, *args):
    subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True)


def _dvc(cwd, *args):
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    run = subprocess.run([sys.executable, "-m", "dvc", *args], cwd=cwd, capture_output=True, text=True, env=env,
                         check=False)
    assert run.returncode == 0, run.stderr


@pytest.fixture
def toy_repo(tmp_path):
    """A git + DVC repository whose one stage writes the point result that params.yaml's `pick` names
    (from results/) into artifacts/hj_sensitivity: an experiment per point, as `sweep queue` makes them."""
    root = tmp_path / "repo"
    (root / "artifacts" / "hj").mkdir(parents=True)
    (root / "artifacts" / "hj_margins").mkdir()
    (root / "artifacts" / "hj" / "grid.bin").write_bytes(b"grid")
    _git(root, "init", "-q")
    _git(root, "config", "user.email", "t@t")
    _git(root, "config", "user.name", "t")
    _dvc(root, "init", "-q")
    _dvc(root, "config", "core.analytics", "false")
    (root / "params.yaml").write_text("pick: none\n")
    script = ("import json, pathlib, shutil, yaml; p = yaml.safe_load(open('params.yaml'))['pick']; "
              "out = pathlib.Path('artifacts/hj_sensitivity'); out.mkdir(exist_ok=True); "
              "[shutil.copy(f, out) for f in pathlib.Path('results', p).glob('*.json')]")
    stage = {"cmd": f'python -c "{script}"', "deps": ["results"], "params": ["pick"],
             "outs": ["artifacts/hj_sensitivity"]}
    (root / "dvc.yaml").write_text(yaml.safe_dump({"stages": {"sweep": stage}}))
    (root / ".gitignore").write_text("/artifacts/hj\n/artifacts/hj_margins\n")
    params = _with_sensitivity(load_params("smoke"), budgets=(10, 20), replan_hz=(), human_noise_m=(),
                               human_prediction_s=())
    return root, params


def test_collect_takes_each_experiments_point_under_its_input_hash(toy_repo):
    root, params = toy_repo
    artifacts = root / "artifacts"
    a, b = sweep_points(params)
    for pick, point, value in (("a", a, a.value), ("b", b, 999), ("stale", a, a.value)):
        folder = root / "results" / pick
        folder.mkdir(parents=True)
        name = point_file(params, point, artifacts).name if pick != "stale" else "budget-0123456789abcdef.json"
        (folder / name).write_text(json.dumps({"kind": "budget", "value": value, "rows": [pick]}))
    _git(root, "add", "-A")
    _git(root, "commit", "-qm", "toy")
    _dvc(root, "exp", "run", "--temp", "--name", "exp-a", "-S", "pick=a")
    _dvc(root, "exp", "run", "--temp", "--name", "exp-stale", "-S", "pick=stale")
    assert set(experiments.experiment_refs(root)) == {"exp-a", "exp-stale"}
    assert not (artifacts / "hj_sensitivity").exists()  # the experiments ran elsewhere

    taken, missing = experiments.collect_sweep(params, root, artifacts)
    assert taken == ["exp-a"] and missing == [b.name]  # a result from other inputs is not taken
    assert json.loads(point_file(params, a, artifacts).read_text())["rows"] == ["a"]
    assert experiments.collect_sweep(params, root, artifacts) == ([], [b.name])  # nothing taken twice

    _dvc(root, "exp", "run", "--temp", "--name", "exp-b", "-S", "pick=b")  # b's file holds another point
    with pytest.raises(DataError, match="exp-b.*under the name of budget-20"):
        experiments.collect_sweep(params, root, artifacts)
    assert not point_file(params, b, artifacts).exists()  # nothing half-taken


def test_queue_skips_points_cached_or_in_a_finished_experiment(toy_repo, monkeypatch):
    root, params = toy_repo
    artifacts = root / "artifacts"
    a, b = sweep_points(params)
    point_file(params, a, artifacts).parent.mkdir(parents=True)
    point_file(params, a, artifacts).write_text("{}")
    calls = []
    monkeypatch.setattr(experiments, "_dvc", lambda cwd, *args: calls.append(args))
    monkeypatch.setattr(experiments, "experiment_refs", lambda cwd: {})
    assert experiments.queue_sweep(params, root, artifacts) == [experiments.experiment_name(params, b, artifacts)]
    assert calls == [("exp", "run", "--queue", "--name", experiments.experiment_name(params, b, artifacts),
                      *experiments.queue_arguments(b), "hj_sweep")]
    monkeypatch.setattr(experiments, "experiment_refs",
                        lambda cwd: {experiments.experiment_name(params, b, artifacts): "0" * 40})
    assert experiments.queue_sweep(params, root, artifacts) == []
