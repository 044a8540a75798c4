"""``python -m navlab``: build and verify the dataset, run notebooks with a profile, index the reports.

Every subcommand has ``--help``. Errors in parameters or data stop with one line and exit code 2.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

from navlab.core.io import DataError
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

    return [
        ("hj_grids", build_hj_grids),
        *pacer_steps(),  # pacer_phase1..3, pacer_sterling, pacer_classifier
    ]


def _artifacts_build(args) -> int:
    params = load_params(args.profile)
    steps = artifact_steps()
    names = [n for n, _ in steps]
    unknown = sorted(set(args.only or []) - set(names))
    if unknown:
        raise ParamsError(f"--only {unknown[0]}: no such artefact step; steps are {', '.join(names) or 'none'}")
    for name, step in steps:
        if args.only and name not in args.only:
            continue
        print(f"[artifacts] {name} ({params.profile})")
        step(params, Path(args.data_dir), Path(args.artifacts_dir))
    return 0


def _data_build(args) -> int:
    from navlab.pipeline import dataset

    root = repo_root()
    params = load_params(args.profile)
    data_dir = Path(args.data_dir)
    dvc_file = root / "data.dvc"
    # data.dvc speaks for the checkout's data/ (however --data-dir spells it) in the recorded profile only
    checked = data_dir.resolve() == (root / "data").resolve() and params.profile == dataset.RECORDED_PROFILE
    if args.record and not checked:  # said before a build of several minutes, not after it
        raise DataError(f"data.dvc records {root / 'data'} built with the {dataset.RECORDED_PROFILE!r} profile; "
                        f"rerun with --profile {dataset.RECORDED_PROFILE} and without --data-dir")
    if checked and not (args.force or args.record):
        ok, msg = dataset.verify(data_dir, dvc_file)
        if ok:
            print(f"{msg}; nothing to do")
            return 0
    dataset.build(data_dir, params, data_steps())
    if args.record:
        subprocess.run([sys.executable, "-m", "dvc", "add", "-q", str(data_dir.resolve())], cwd=root, check=True)
        print(f"recorded {data_dir}/ in data.dvc ({dataset.recorded_digest(dvc_file)}); commit data.dvc")
        return 0
    if not checked:
        print(f"built {data_dir}/ with profile {params.profile!r} (data.dvc records only "
              f"{dataset.RECORDED_PROFILE!r} builds of data/; not checked)")
        return 0
    ok, msg = dataset.verify(data_dir, dvc_file)
    print(msg)
    if ok:
        subprocess.run([sys.executable, "-m", "dvc", "commit", "-q", "-f", "data.dvc"], cwd=root, check=True)
    return 0 if ok else 1


def _data_verify(args) -> int:
    from navlab.pipeline import dataset

    ok, msg = dataset.verify(args.data_dir, repo_root() / "data.dvc")
    print(msg)
    return 0 if ok else 1


def _notebook_run(args) -> int:
    from navlab.pipeline.notebooks import run_notebook

    run_notebook(
        args.notebook,
        profile=load_params(args.profile).profile,
        output=args.output,
        data_dir=args.data_dir,
        artifacts_dir=args.artifacts_dir,
        reports_dir=args.reports_dir,
    )
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


def _params_show(args) -> int:
    import dataclasses
    import json

    print(json.dumps(dataclasses.asdict(load_params(args.profile)), indent=2, default=str))
    return 0


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
    b.add_argument("--force", action="store_true", help="rebuild even if data/ already matches data.dvc")
    b.add_argument("--record", action="store_true", help="record the new build in data.dvc (dvc add)")
    b.set_defaults(func=_data_build)
    v = data_cmds.add_parser("verify", help="check data/ against the digest data.dvc records")
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
    folder_args(r, "data", "artifacts", "reports")
    r.set_defaults(func=_notebook_run)

    lab = groups.add_parser("lab", help="JupyterLab on notebooks/ (loopback); profile for Run All: $NAVLAB_PROFILE")
    lab.add_argument("options", nargs=argparse.REMAINDER, help="passed to `jupyter lab`, e.g. --port 9999")
    lab.set_defaults(func=_lab)

    rep = groups.add_parser("reports", help="report files")
    rep_cmds = rep.add_subparsers(dest="cmd", required=True)
    i = rep_cmds.add_parser("index", help="write reports/README.md from every report JSON")
    folder_args(i, "reports")
    i.set_defaults(func=_reports_index)

    par = groups.add_parser("params", help="show validated parameters")
    par_cmds = par.add_subparsers(dest="cmd", required=True)
    s = par_cmds.add_parser("show", help="print the resolved parameters of a profile")
    profile_arg(s)
    s.set_defaults(func=_params_show)
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
