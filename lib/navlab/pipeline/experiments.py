"""The HJ sensitivity sweep (issue 26) on DVC's experiment queue: one queued experiment per point.

Why: a sweep point re-runs a whole closed-loop cell (minutes each); DVC's queue runs experiments in
parallel workers (``dvc queue start -j N``) and, with ``dvc exp push`` / ``dvc exp pull``, on other
machines. Each experiment is this commit with ``hj.sensitivity.only`` naming its point (set in both
params.yaml and params.resolved.yaml, so the stage's recorded params say which point it ran) and runs only
the ``hj_sweep`` stage. ``collect_sweep`` then copies each experiment's point result into the workspace's
point cache, where ``dvc repro`` finds it: a result is taken only under the file name its inputs hash to
(``hj.sweeps.point_key``: code, HJ parameters with the point's change, grids), so an experiment
run from other code or grids is never mistaken for this tree's, and the locked stages assemble the curves.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path, PurePosixPath

from navlab.core.io import DataError, write_text
from navlab.core.params import Params
from navlab.hj.sweeps import Point, point_file, points_to_run
from navlab.pipeline.dvc_yaml import RESOLVED

SWEEP_STAGE = "hj_sweep"


def experiment_name(params: Params, point: Point, artifacts_dir: str | Path) -> str:
    """The queued experiment's name: the point's name and the first 8 hex digits of its input hash."""
    return _name(point, point_file(params, point, artifacts_dir))


def _name(point: Point, path: Path) -> str:
    """``experiment_name`` from the point's cache file (whose name already holds the input hash)."""
    return f"hj-{point.name}-{path.stem.split('-')[-1][:8]}"


def queue_arguments(point: Point) -> list[str]:
    """The ``-S`` overrides of a point's experiment: the same value in params.yaml (what the stage reads)
    and params.resolved.yaml (what DVC compares)."""
    value = f"hj.sensitivity.only=[{point.name}]"
    return ["-S", f"params.yaml:{value}", "-S", f"{RESOLVED}:{value}"]


def experiment_refs(root: str | Path) -> dict[str, str]:
    """{experiment name: commit} of every finished DVC experiment in the checkout (refs/exps/XX/BASELINE/NAME)."""
    out = _git(root, "for-each-ref", "--format=%(objectname) %(refname)", "refs/exps")
    refs = {}
    for line in out.splitlines():
        sha, ref = line.split(" ", 1)
        parts = ref.split("/")
        if len(parts) == 5 and len(parts[2]) == 2:  # not the queue's own refs (refs/exps/celery/..., exec/...)
            refs[parts[4]] = sha
    return refs


def queue_sweep(params: Params, root: str | Path, artifacts_dir: str | Path) -> list[str]:
    """Queue one experiment for each point the sweep simulates (``points_to_run``: Table VI's own are read from
    its report) whose result is neither cached here nor in a finished experiment (``collect_sweep`` takes
    those); the names queued. Start them with ``dvc queue start -j N``."""
    done = experiment_refs(root)
    queued = []
    for point in points_to_run(params):
        path = point_file(params, point, artifacts_dir)  # hashes the code and the grids: once per point
        name = _name(point, path)
        if path.exists() or name in done:
            continue
        _dvc(root, "exp", "run", "--queue", "--name", name, *queue_arguments(point), SWEEP_STAGE)
        queued.append(name)
    return queued


def collect_sweep(params: Params, root: str | Path, artifacts_dir: str | Path) -> tuple[list[str], list[str]]:
    """Copy into the point cache every result a finished experiment holds under the file name this tree's
    inputs give it; (experiment names taken from, point names still missing)."""
    from dvc.api import DVCFileSystem

    root = Path(root).resolve()
    wanted = {point_file(params, p, artifacts_dir): p for p in points_to_run(params)}
    folder = next(iter(wanted)).parent.resolve()
    if not folder.is_relative_to(root):
        raise DataError(f"{folder}: the point cache must lie inside the checkout {root} to be read from experiments")
    by_name = {path.name: (path, point) for path, point in wanted.items()}
    rel = folder.relative_to(root).as_posix()
    taken = []
    for name, sha in sorted(experiment_refs(root).items()):
        fs = DVCFileSystem(str(root), rev=sha)
        if not fs.isdir(rel):
            continue
        for file in fs.ls(rel, detail=False):
            path, point = by_name.get(PurePosixPath(file).name, (None, None))
            if path is None or path.exists():
                continue
            text = fs.read_text(file)
            _check_result(json.loads(text), point, f"{name}:{file}")
            write_text(path, text)
            taken.append(name)
    missing = [p.name for path, p in wanted.items() if not path.exists()]
    return sorted(set(taken)), missing


def _check_result(result: dict, point: Point, where: str) -> None:
    """A result whose file name matches must be that point's (the name hashes its inputs; this guards the copy)."""
    if result.get("kind") != point.kind or json.dumps(result.get("value")) != json.dumps(point.value):
        raise DataError(f"{where}: holds point {result.get('kind')} {result.get('value')} under the name of "
                         f"{point.name}; delete that experiment (`dvc exp remove`) and queue it again")


def _git(root: str | Path, *args: str) -> str:
    run = subprocess.run(["git", *args], cwd=root, capture_output=True, text=True, check=False)
    if run.returncode != 0:
        raise DataError(f"`git {' '.join(args)}` failed in {root}: {run.stderr.strip()}")
    return run.stdout


def _dvc(root: str | Path, *args: str) -> None:
    run = subprocess.run([sys.executable, "-m", "dvc", *args], cwd=root, capture_output=True, text=True, check=False)
    if run.returncode != 0:
        last = run.stderr.strip().splitlines()[-1] if run.stderr.strip() else f"exit {run.returncode}"
        raise DataError(f"`dvc {' '.join(args)}` failed: {last}")
