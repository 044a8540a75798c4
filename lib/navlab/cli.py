"""``python -m navlab``: build and verify the dataset, run notebooks with a profile, index the reports.

Every subcommand has ``--help``. Errors in parameters or data stop with one line and exit code 2.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

from navlab.core.io import DataError, folder_lock
from navlab.core.params import PROFILES, ParamsError, load_params, repo_root


def data_steps():
    """The steps of ``data build``, in order; each writes under its own folder of data/."""
    from navlab.maps.dataset import build_maps
    from navlab.pipeline.sources import build_raw
    from navlab.surenav.experts import build_demos

    return [("raw", build_raw), ("maps", build_maps), ("demos", build_demos)]


def artifact_steps():
    """The artefact builders (DVC stage outputs under artifacts/), by name, in dependency order.

    Each is ``fn(params, data_dir, artifacts_dir)``; `dvc repro` runs them one stage each
    (``artifacts build --only NAME``) and the notebook smoke tests run them all for ``smoke``.
    """
    from navlab.pacer.artifacts import artifact_steps as pacer_steps
    from navlab.reach.precompute import build_hj_grids
    from navlab.surenav.artifacts import artifact_steps as surenav_steps
    from navlab.surenav.episodes import build_episodes

    return [
        ("hj_grids", build_hj_grids),
        ("surenav_episodes", build_episodes),
        *pacer_steps(),  # pacer_phase1..3, pacer_sterling, pacer_classifier
        *surenav_steps(),  # surenav_estimator (GPS and MPNN-ablation seeds)
    ]


def _artifacts_build(args) -> int:
    params = load_params(args.profile)
    steps = artifact_steps()
    names = [n for n, _ in steps]
    unknown = sorted(set(args.only or []) - set(names))
    if unknown:
        raise ParamsError(f"--only {unknown[0]}: no such artefact step; steps are {', '.join(names) or 'none'}")
    artifacts_dir = Path(args.artifacts_dir)
    with folder_lock(artifacts_dir / ".build.lock", f"{artifacts_dir}/"):
        for name, step in steps:
            if args.only and name not in args.only:
                continue
            print(f"[artifacts] {name} ({params.profile})")
            step(params, Path(args.data_dir), artifacts_dir)
    return 0


def _data_build(args) -> int:
    from navlab.pipeline import dataset

    root = repo_root()
    params = load_params(args.profile)
    data_dir = Path(args.data_dir)
    lock_file = root / "dvc.lock"
    # dvc.lock speaks for the checkout's data/ (however --data-dir spells it) in the recorded profile only
    checked = data_dir.resolve() == (root / "data").resolve() and params.profile == dataset.RECORDED_PROFILE
    if args.record and not checked:  # said before a build of several minutes, not after it
        raise DataError(f"dvc.lock records {root / 'data'} built with the {dataset.RECORDED_PROFILE!r} profile; "
                        f"rerun with --profile {dataset.RECORDED_PROFILE} and without --data-dir")
    steps = data_steps()
    if checked and not (args.force or args.record):
        ok, msg = dataset.verify(data_dir, lock_file)
        if ok and dataset.check(data_dir, params, steps)[0]:
            print(f"{msg}; nothing to do")
            return 0
    dataset.build(data_dir, params, steps)
    if args.record:
        _dvc_commit(root)
        print(f"recorded {data_dir}/ in dvc.lock ({dataset.recorded_digest(lock_file)}); commit dvc.lock")
        return 0
    if not checked:
        print(f"built {data_dir}/ with profile {params.profile!r} (dvc.lock records only "
              f"{dataset.RECORDED_PROFILE!r} builds of data/; not checked)")
        return 0
    ok, msg = dataset.verify(data_dir, lock_file)
    print(msg)
    if ok:
        _dvc_commit(root)
    return 0 if ok else 1


def _dvc_commit(root: Path) -> None:
    """Record data/ (and the generator code and params it was built by) as the ``data`` stage in dvc.lock."""
    from navlab.pipeline.dataset import STAGE

    subprocess.run([sys.executable, "-m", "dvc", "commit", "-q", "-f", STAGE], cwd=root, check=True)


def _data_check(args) -> int:
    from navlab.pipeline import dataset

    ok, msg = dataset.check(args.data_dir, load_params(args.profile), data_steps())
    print(msg, file=sys.stdout if ok else sys.stderr)
    return 0 if ok else 2


def _data_verify(args) -> int:
    from navlab.pipeline import dataset

    ok, msg = dataset.verify(args.data_dir, repo_root() / "dvc.lock")
    print(msg)
    return 0 if ok else 1


def _notebook_run(args) -> int:
    from navlab.pipeline.notebooks import run_notebook

    profile = load_params(args.profile).profile
    reports_dir = args.reports_dir
    if reports_dir is None:  # the tracked reports/ hold the pipeline's profile only; others go beside artefacts
        reports_dir = "reports" if profile == load_params().profile else str(Path(args.artifacts_dir) / "reports" / profile)
    out = run_notebook(args.notebook, profile=profile, output=args.output, data_dir=args.data_dir,
                       artifacts_dir=args.artifacts_dir, reports_dir=reports_dir)
    print(f"ran {args.notebook} ({profile}) -> {out}; reports in {reports_dir}/")
    return 0


def lab_command(*options: str, notebooks: str | Path | None = None) -> list[str]:
    """JupyterLab on notebooks/, on loopback only: what `make lab` runs (and the browser test starts).

    Kernels start in each notebook's folder; the notebooks find the checkout's data/, artifacts/ and
    reports/ themselves (navlab.pipeline.notebooks.resolve_parameters). ``options`` go to ``jupyter lab``.
    """
    notebooks = Path(notebooks) if notebooks is not None else repo_root() / "notebooks"
    root_user = ["--ServerApp.allow_root=True"] if os.geteuid() == 0 else []  # containers, CI: loopback only
    return [sys.executable, "-m", "jupyter", "lab", "--ServerApp.ip=127.0.0.1",
            f"--ServerApp.root_dir={notebooks}", *root_user, *options]


def _lab(args) -> int:
    cmd = lab_command(*args.options)
    os.execv(cmd[0], cmd)  # jupyter takes over the process (and Ctrl-C: it asks before shutting down)


def _reports_index(args) -> int:
    from navlab.pipeline.reports import write_index

    print(f"wrote {write_index(args.reports_dir)}")
    return 0


def _reports_diff(args) -> int:
    import json

    from navlab.pipeline.report_diff import diff_reports
    from navlab.pipeline.reports import read_table

    root, reports_dir = repo_root(), Path(args.reports_dir)
    if not reports_dir.is_dir():
        raise DataError(f"{reports_dir}/ does not exist; pass the folder of regenerated reports with --reports-dir")
    moved, compared = [], 0
    for path in sorted(reports_dir.glob("*/*.json")):
        rel = path.resolve().relative_to(root).as_posix() if path.resolve().is_relative_to(root) else \
            f"reports/{path.parent.name}/{path.name}"
        shown = subprocess.run(["git", "show", f"{args.rev}:{rel}"], cwd=root, capture_output=True, text=True,
                               check=False)
        if shown.returncode != 0:
            print(f"{rel}: not in {args.rev} (new table)")
            continue
        compared += 1
        moved += diff_reports(json.loads(shown.stdout), read_table(path))
    for m in moved:
        print(m)
    print(f"{compared} tables compared with {args.rev}: {len(moved)} numbers moved")
    return 1 if moved else 0


def _params_show(args) -> int:
    import dataclasses
    import json

    print(json.dumps(dataclasses.asdict(load_params(args.profile)), indent=2, default=str))
    return 0


def _params_check(args) -> int:
    from navlab.pipeline.profile_check import check_profile

    problems = []
    for profile in [args.profile] if args.profile else PROFILES:
        try:
            found, notes = check_profile(load_params(profile, args.params))
        except ParamsError as err:
            found, notes = [str(err)], []
        for note in notes:
            print(f"[{profile}] {note}")
        problems += [f"[{profile}] {p}" for p in found]
    for problem in problems:
        print(f"error: {problem}", file=sys.stderr)
    print(f"{len(problems)} problem(s)" if problems else "every profile fits")
    return 2 if problems else 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m navlab", description=__doc__.splitlines()[0])
    groups = parser.add_subparsers(dest="group", required=True, metavar="{data,artifacts,notebook,lab,reports,params}")

    def profile_arg(p):
        p.add_argument("--profile", choices=PROFILES, default=None,
                       help="parameter profile (default: the `profile` key of params.yaml)")

    def folder_args(p, *names):
        for name in names:
            p.add_argument(f"--{name}-dir", default=name, help=f"the {name} folder (default: {name})")

    data = groups.add_parser("data", help="build or verify the dataset snapshot in data/")
    data_cmds = data.add_subparsers(dest="cmd", required=True)
    b = data_cmds.add_parser("build", help="build data/ from packages and seeded generators (resumable)")
    profile_arg(b)
    folder_args(b, "data")
    b.add_argument("--force", action="store_true", help="rebuild even if data/ already matches dvc.lock")
    b.add_argument("--record", action="store_true", help="record the new build in dvc.lock (dvc commit data)")
    b.set_defaults(func=_data_build)
    c = data_cmds.add_parser("check", help="refuse a data/ built by another profile or older generator code "
                                           "(the `data` stage of dvc.yaml)")
    profile_arg(c)
    folder_args(c, "data")
    c.set_defaults(func=_data_check)
    v = data_cmds.add_parser("verify", help="check data/ against the digest dvc.lock records")
    folder_args(v, "data")
    v.set_defaults(func=_data_verify)

    art = groups.add_parser("artifacts", help="build DVC stage outputs: HJ grids, trained models")
    art_cmds = art.add_subparsers(dest="cmd", required=True)
    a = art_cmds.add_parser("build", help="build artefacts (all, or those named with --only)")
    profile_arg(a)
    a.add_argument("--only", action="append", metavar="STEP", help="build only this step (repeatable)")
    folder_args(a, "data", "artifacts")
    a.set_defaults(func=_artifacts_build)

    nb = groups.add_parser("notebook", help="run notebooks headlessly with papermill")
    nb_cmds = nb.add_subparsers(dest="cmd", required=True)
    r = nb_cmds.add_parser("run", help="execute one notebook with a profile")
    r.add_argument("notebook", help="path of the notebook, e.g. notebooks/00_quickstart.ipynb")
    profile_arg(r)
    r.add_argument("--output", default=None, help="executed copy (default: artifacts/notebooks/<same path>)")
    folder_args(r, "data", "artifacts")
    r.add_argument("--reports-dir", default=None, help="report folder (default: reports for the profile of "
                                                       "params.yaml, else artifacts/reports/<profile>)")
    r.set_defaults(func=_notebook_run)

    lab = groups.add_parser("lab", help="JupyterLab on notebooks/ (loopback); profile for Run All: $NAVLAB_PROFILE")
    lab.add_argument("options", nargs=argparse.REMAINDER, help="passed to `jupyter lab`, e.g. --port 9999")
    lab.set_defaults(func=_lab)

    rep = groups.add_parser("reports", help="report files")
    rep_cmds = rep.add_subparsers(dest="cmd", required=True)
    i = rep_cmds.add_parser("index", help="write reports/README.md from every report JSON")
    folder_args(i, "reports")
    i.set_defaults(func=_reports_index)

    d = rep_cmds.add_parser("diff", help="compare regenerated reports with the committed ones; flag every number "
                                         "outside its interval")
    folder_args(d, "reports")
    d.add_argument("--rev", default="HEAD", help="git revision holding the committed reports (default: HEAD)")
    d.set_defaults(func=_reports_diff)

    par = groups.add_parser("params", help="show or check validated parameters")
    par_cmds = par.add_subparsers(dest="cmd", required=True)
    s = par_cmds.add_parser("show", help="print the resolved parameters of a profile")
    profile_arg(s)
    s.set_defaults(func=_params_show)
    k = par_cmds.add_parser("check", help="dry-run each profile's stage shapes on the CPU: model sizes, aerial "
                                          "vs test-map sizes, patch vs image sizes, HJ grids vs memory")
    k.add_argument("--profile", choices=PROFILES, default=None, help="check one profile (default: all)")
    k.add_argument("--params", default=None, help="params.yaml to check (default: the checkout's)")
    k.set_defaults(func=_params_check)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ParamsError, DataError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
