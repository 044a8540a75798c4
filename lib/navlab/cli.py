"""``python -m navlab``: build and verify the dataset, run notebooks with a profile, index the reports.

Every subcommand has ``--help``. Errors in parameters or data, and a full disk or a read-only folder,
stop with one line and exit code 2.
"""

from __future__ import annotations

import argparse
import errno
import os
import sys
from pathlib import Path

import yaml

from navlab.core.allocator import keep_freed_memory
from navlab.core.io import DataError, folder_lock
from navlab.core.params import PROFILES, ParamsError, load_params, repo_root
from navlab.pipeline.steps import artifact_steps, data_steps


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
    """Build data/ unless it was built by this profile, the current generator code and intact content.

    The `data` stage of dvc.yaml runs this; DVC then records data/ in dvc.lock (``data verify`` compares
    data/ with that record later). A finished build is never redone; a killed one resumes.
    """
    from navlab.pipeline import dataset

    params = load_params(args.profile)
    data_dir = Path(args.data_dir)
    steps = data_steps()
    if not args.force:
        ok, msg = dataset.check(data_dir, params, steps)
        if ok:
            print(f"{msg}; nothing to do")
            return 0
    dataset.build(data_dir, params, steps)
    print(f"built {data_dir}/ with profile {params.profile!r}")
    return 0


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


CITIES_DIR = "cities"  # `city run --out-dir`'s default (ignored by git)


def run_city(extract: str | Path, name: str, params, artifacts_dir: str | Path, out_root: str | Path = CITIES_DIR,
             max_tiles: int | None = None, progress: bool = True) -> list[Path]:
    """``city run``: build (or resume) the test set of ``extract`` under ``out_root/name/testset`` and write its
    Table I and Fig. 4 reports (JSON + Markdown, and the Fig. 4 figure) under ``out_root/name/reports``;
    ``max_tiles`` None keeps ``surenav.any_city.DEFAULT_MAX_TILES``.

    Why here: the test set and the evaluation are ``surenav.any_city``; the reports are written as the
    notebooks write theirs (``pipeline.reports``), which only the command layer may join to a track."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from navlab.pipeline.reports import write_table
    from navlab.surenav.any_city import DEFAULT_MAX_TILES, build_test_set, check_name, evaluate, load_test_set
    from navlab.viz.surenav_benchmark import draw_safety_efficiency

    out = Path(out_root, check_name(name))
    build_test_set(extract, name, params, out / "testset", DEFAULT_MAX_TILES if max_tiles is None else max_tiles)
    table1, fig4 = evaluate(load_test_set(out / "testset"), params, artifacts_dir, name, progress)
    reports = out / "reports"
    seeds = list(params.surenav.train.seeds)
    written = [write_table(reports, t, track="surenav", profile=params.profile, seeds=seeds) for t in (table1, fig4)]
    figure = reports / "surenav" / "figures" / "fig4_safety_efficiency.png"
    figure.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
    draw_safety_efficiency(ax, fig4.rows)
    fig.savefig(figure, dpi=120)
    plt.close(fig)
    return [*written, figure]


def _city_run(args) -> int:
    from navlab.maps.osm import city_path
    from navlab.surenav.any_city import check_name

    try:  # a bad extract or name is one line before anything runs
        city_path(None, args.extract)
        check_name(args.name)
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    params = load_params(args.profile, args.params)
    written = run_city(args.extract, args.name, params, args.artifacts_dir, args.out_dir, args.max_tiles)
    print(f"{args.name} ({params.profile}): " + ", ".join(str(p) for p in written))
    return 0


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
    from navlab.pipeline.results import write_index

    readme = args.readme  # the front door shows the committed reports only, never a scratch folder's
    if readme is None and Path(args.reports_dir).resolve() == Path("reports").resolve():
        readme = "README.md"
    print(f"wrote {write_index(args.reports_dir, readme=readme)}")
    return 0


def _reports_diff(args) -> int:
    from navlab.pipeline.report_diff import committed_reports, diff_folder

    reports_dir = Path(args.reports_dir)
    if not reports_dir.is_dir():
        raise DataError(f"{reports_dir}/ does not exist; pass the folder of regenerated reports with --reports-dir")
    found = diff_folder(reports_dir, committed_reports(repo_root(), args.rev))
    for name in found.new:
        print(f"{name}: not in {args.rev} (new table)")
    for line in [*found.unusable, *found.moved]:
        print(line)
    print(f"{found.compared} tables compared with {args.rev}: {len(found.moved)} numbers moved, "
          f"{len(found.unusable)} reports missing or unreadable")
    return 1 if found.moved or found.unusable else 0


def _params_show(args) -> int:
    import dataclasses
    import json

    print(json.dumps(dataclasses.asdict(load_params(args.profile)), indent=2, default=str))
    return 0


def _pipeline_write(args) -> int:
    from navlab.pipeline.dvc_yaml import write

    changed = write(repo_root())
    print(f"wrote {', '.join(changed)}" if changed else "dvc.yaml and params.resolved.yaml are current")
    return 0


def _pipeline_check(args) -> int:
    """Exit 1 when dvc.yaml or params.resolved.yaml drifted from the code, or dvc.lock is stale."""
    from navlab.pipeline.dvc_yaml import DvcStatusError, drifted, stale_stages

    root = repo_root()
    problems = [f"{name} differs from what the code writes; run `python -m navlab pipeline write`"
                for name in drifted(root)]
    if not problems:  # dvc status reads dvc.yaml: only meaningful once it is current
        try:
            problems = [f"stale in dvc.lock: {line}; regenerate with `dvc repro` and commit dvc.lock with the "
                        "reports" for line in stale_stages(root)]
        except DvcStatusError as e:
            problems = [str(e)]
    for line in problems:
        print(line, file=sys.stderr)
    if not problems:
        print("dvc.yaml and params.resolved.yaml are current; dvc.lock describes every stage")
    return 1 if problems else 0


def _refuse_stale_resolved_params(args) -> None:
    """Under `dvc repro` (which sets DVC_STAGE) the stage reads params.yaml, but DVC compared
    params.resolved.yaml: refuse to run when the two disagree, so no stage runs on unrecorded values."""
    if not os.environ.get("DVC_STAGE") or args.group not in ("data", "artifacts", "notebook"):
        return
    from navlab.pipeline.dvc_yaml import RESOLVED, render_resolved_params

    root = repo_root()
    resolved = root / RESOLVED
    # compared as values: a queued DVC experiment's `-S` (navlab.pipeline.experiments) rewrites the file's text
    if not resolved.is_file() or yaml.safe_load(resolved.read_text(encoding="utf8")) != yaml.safe_load(
            render_resolved_params(root)):
        raise ParamsError(f"{RESOLVED} does not match params.yaml; run `python -m navlab pipeline write` "
                          "(`make repro` does) before `dvc repro`")


def _sweep_queue(args) -> int:
    from navlab.pipeline.experiments import queue_sweep

    queued = queue_sweep(load_params(), repo_root(), args.artifacts_dir)
    for name in queued:
        print(f"queued {name}")
    print(f"{len(queued)} experiment(s) queued; run them with `dvc queue start -j 2` (`dvc queue status` follows "
          "them), then `python -m navlab sweep collect`" if queued else
          "nothing to queue: every point is cached or in a finished experiment; run `python -m navlab sweep collect`")
    return 0


def _sweep_collect(args) -> int:
    from navlab.pipeline.experiments import collect_sweep

    taken, missing = collect_sweep(load_params(), repo_root(), args.artifacts_dir)
    print(f"results taken from {len(taken)} experiment(s): {', '.join(taken) or 'none'}")
    if missing:
        print(f"{len(missing)} point(s) still missing ({', '.join(missing)}): queued experiments not finished "
              "(`dvc queue status`), or `dvc repro` runs them itself")
        return 1
    print("every point is cached; `dvc repro` assembles and locks the curves")
    return 0


def _params_file(path: str) -> str:
    """``--params``: a readable UTF-8 text file, else argparse's one line naming it (a folder or binary bytes
    would otherwise surface as an OSError or a UnicodeDecodeError from deep in the YAML loader)."""
    try:
        Path(path).read_text(encoding="utf8")
    except IsADirectoryError:
        raise argparse.ArgumentTypeError(f"{path} is a folder; name the params.yaml file in it") from None
    except FileNotFoundError:
        raise argparse.ArgumentTypeError(f"{path}: no such file") from None
    except UnicodeDecodeError:
        raise argparse.ArgumentTypeError(f"{path} is not a text file (not UTF-8); give a params.yaml") from None
    except OSError as err:
        raise argparse.ArgumentTypeError(f"{path}: {err.strerror}") from None
    return path


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
    groups = parser.add_subparsers(dest="group", required=True,
                                   metavar="{data,artifacts,notebook,city,lab,reports,params,pipeline,sweep}")

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
    b.add_argument("--force", action="store_true", help="rebuild even if data/ was built by this profile and code")
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

    city = groups.add_parser("city", help="a SuReNav test set from your own OpenStreetMap extract, evaluated "
                                          "(docs/your_city.md)")
    city_cmds = city.add_subparsers(dest="cmd", required=True)
    cr = city_cmds.add_parser("run", help="build (or resume) the test set of EXTRACT and write its Table I and "
                                          "Fig. 4 reports under OUT_DIR/NAME/reports/surenav")
    cr.add_argument("extract", help="an OpenStreetMap extract: .osm, .osm.pbf, .osm.bz2 or .osm.gz")
    cr.add_argument("--name", required=True, help="your name for the city: the folder OUT_DIR/NAME")
    profile_arg(cr)
    cr.add_argument("--params", type=_params_file, default=None, help="a params.yaml to use instead of the checkout's")
    cr.add_argument("--artifacts-dir", default=os.environ.get("NAVLAB_ARTIFACTS_DIR", "artifacts"),
                    help="where the trained models are read (default: $NAVLAB_ARTIFACTS_DIR, else artifacts)")
    cr.add_argument("--out-dir", default=CITIES_DIR, help=f"where NAME/ is written (default: {CITIES_DIR})")
    cr.add_argument("--max-tiles", type=int, default=None,
                    help="test tiles at most, the best-mapped first (default: 5, surenav.any_city.DEFAULT_MAX_TILES)")
    cr.set_defaults(func=_city_run)

    lab = groups.add_parser("lab", help="JupyterLab on notebooks/ (loopback); profile for Run All: $NAVLAB_PROFILE")
    lab.add_argument("options", nargs=argparse.REMAINDER, help="passed to `jupyter lab`, e.g. --port 9999 "
                                                                "(everything after `lab`, options included)")
    lab.set_defaults(func=_lab)

    rep = groups.add_parser("reports", help="report files")
    rep_cmds = rep.add_subparsers(dest="cmd", required=True)
    i = rep_cmds.add_parser("index", help="write reports/README.md (and README.md's results block) from "
                                                   "every report JSON")
    folder_args(i, "reports")
    i.add_argument("--readme", default=None, help="the front door whose results block is rewritten (default: "
                                                    "README.md when the reports folder is reports/)")
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
    k.add_argument("--params", default=None, type=_params_file, help="params.yaml to check (default: the checkout's)")
    k.set_defaults(func=_params_check)

    pipe = groups.add_parser("pipeline", help="dvc.yaml and params.resolved.yaml, generated from the stage registry")
    pipe_cmds = pipe.add_subparsers(dest="cmd", required=True)
    w = pipe_cmds.add_parser("write", help="write dvc.yaml and params.resolved.yaml (the active profile resolved)")
    w.set_defaults(func=_pipeline_write)
    k = pipe_cmds.add_parser("check", help="fail when the generated files drifted or dvc.lock is stale")
    k.set_defaults(func=_pipeline_check)

    sw = groups.add_parser("sweep", help="the HJ sensitivity sweep on DVC's experiment queue, one experiment per "
                                         "point (issue 26)")
    sw_cmds = sw.add_subparsers(dest="cmd", required=True)
    q = sw_cmds.add_parser("queue", help="queue a `dvc exp run` of stage hj_sweep for every point not yet cached "
                                         "(the profile of params.yaml)")
    folder_args(q, "artifacts")
    q.set_defaults(func=_sweep_queue)
    c = sw_cmds.add_parser("collect", help="copy finished experiments' point results into the point cache; "
                                           "exit 1 while points are missing")
    folder_args(c, "artifacts")
    c.set_defaults(func=_sweep_collect)
    return parser


WRITE_ERRORS = (errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES, errno.EPERM)


def parse_args(argv: list[str] | None = None) -> argparse.Namespace:
    """The parsed command line; everything after ``lab`` goes to jupyter lab untouched.

    Why: argparse's REMAINDER after a subcommand refuses a leading ``--option`` (``lab --port 9999``, the
    example of ``lab --help``), so ``lab``'s options are split off before argparse sees them.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    passed = []
    if argv[:1] == ["lab"] and argv[1:2] not in (["-h"], ["--help"]):
        argv, passed = argv[:1], argv[1:]
    args = build_parser().parse_args(argv)
    if args.group == "lab":
        args.options = passed
    return args


def write_error(err: OSError) -> str | None:
    """One line for a write refused by the system (disk full, read-only, no permission); else None."""
    if err.errno not in WRITE_ERRORS:
        return None
    where = os.fsdecode(err.filename) if isinstance(err.filename, str | bytes | os.PathLike) else "a file"
    return f"{where}: {os.strerror(err.errno)}; free space or fix its permissions, then run the command again"


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    keep_freed_memory()  # the solver's and trainers' per-step arrays stay in the heap (core.allocator)
    try:
        _refuse_stale_resolved_params(args)
        return args.func(args)
    except (ParamsError, DataError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    except OSError as err:
        line = write_error(err)
        if line is None:
            raise
        print(f"error: {line}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
