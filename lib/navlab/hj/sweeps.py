"""Sensitivity sweeps of the HJ closed-loop tables (issue 26): one setting the paper does not state is
changed, the whole cell re-run, and each point cached on disk.

Why: three of the paper's closed-loop claims turn on a setting its text leaves out. "TTR succeeds more
often than Dist in the Long Hallway" and "only TTR + BRT clears the Dense Room" depend on how much search
each re-plan may spend (the paper's robot had a time budget, not stated); "FI-BRT avoids the head-on
contacts FS-BRT does not" on how often the car re-plans and how noisy the human's observed position is.
A single table point cannot say whether a claim is wrong or sits at another setting; a curve can.

- ``budget`` points: Table VIII (both rooms, its four heuristic x pruner rows) with ANA* given that many
  expansions per re-plan (``hj.dynamic.closed_loop.max_expansions``); everything else as Table VIII.
- ``loop`` points: Table VI (Face-to-Face and Zig-Zag, FI-BRT / FS-BRT / OBS, its seeded runs) at one
  re-planning rate, one observed-human noise and one human-prediction horizon (0: the humans pruned where
  seen, as the paper's text has it; ours predicts them along their observed velocity, which may be what
  lets FS-BRT pass the head-on test); everything else as Table VI.

A point's result is a JSON file under ``artifacts/hj_sensitivity`` named by the sha256 of the code it runs,
the HJ parameters with the point's change applied, and the stored grids it reads: a changed input re-runs
exactly the points it affects, and an interrupted sweep resumes. Points run in ``workers`` processes; a
point's numbers do not depend on how many (each is a pure function of its settings and seeds).

Two loop points are Table VI itself: at the table's own rate and noise, the paper's rows at its horizon and
its prediction-variant rows at theirs (``table_rows``). Their runs are the very calls Table VI makes (same
``ClosedLoop`` settings, rows and seeds; tested), so they are not run a second time: the sweep takes their
rows from Table VI's report (about a third of the loop points' runs).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from tqdm.auto import tqdm

from navlab.core.fingerprint import code_fingerprint, files_fingerprint
from navlab.core.io import DataError, write_json
from navlab.core.params import Params
from navlab.hj.brt_margin import MARGINS_SUBDIR
from navlab.hj.closed_loop import summarise_runs, summarise_trips
from navlab.hj.scenarios import HUMAN_ROWS, ROOM_COMBOS, ROOM_NAMES, ClosedLoop, human_rows

SWEEP_SUBDIR = "hj_sensitivity"
SCENARIOS = ("Face-to-Face", "Zig-Zag")  # a loop point's cells, in its rows' order


@dataclasses.dataclass(frozen=True)
class Point:
    """One sweep point: ``kind`` "budget" (``value`` = expansions per re-plan) or "loop" (``value`` =
    (re-plan Hz, observed-human noise std in m, human-prediction horizon in s))."""

    kind: str
    value: int | tuple[float, float, float]

    @property
    def name(self) -> str:
        """A readable name, unique within a sweep ("budget-500", "loop-12hz-0.1m-1.5s"): what
        ``hj.sensitivity.only`` lists and what each queued DVC experiment is called after."""
        if self.kind == "budget":
            return f"budget-{int(self.value)}"
        hz, noise, ahead = self.value
        return f"loop-{hz:g}hz-{noise:g}m-{ahead:g}s"


def sweep_points(params: Params) -> list[Point]:
    """The points params.yaml ``hj.sensitivity`` asks for: every budget; for Table VI each re-planning rate,
    noise level and prediction horizon with the other two at the table's own (a shared point runs once)."""
    s, d = params.hj.sensitivity, params.hj.dynamic
    hz, noise, ahead = d.closed_loop.replan_hz, d.table6.human_noise_m, d.closed_loop.human_prediction_s
    triples = [(h, noise, ahead) for h in s.replan_hz] + [(hz, n, ahead) for n in s.human_noise_m]
    triples += [(hz, noise, a) for a in s.human_prediction_s]
    loops = dict.fromkeys(tuple(float(v) for v in t) for t in triples)
    return [Point("budget", int(b)) for b in s.budgets] + [Point("loop", t) for t in loops]


def selected_points(params: Params) -> list[Point]:
    """``sweep_points``, narrowed to ``hj.sensitivity.only`` when it names any (one queued experiment each)."""
    points, only = sweep_points(params), params.hj.sensitivity.only
    unknown = sorted(set(only) - {p.name for p in points})
    if unknown:
        raise ValueError(f"hj.sensitivity.only names {unknown[0]!r}, not a point of this sweep; its points are "
                         f"{', '.join(p.name for p in points)}")
    return [p for p in points if not only or p.name in only]


def table_rows(params: Params, point: Point) -> dict[str, str] | None:
    """For a ``loop`` point Table VI runs itself (its own re-planning rate and human noise, at a horizon each of
    the three methods has a row for: OBS never predicts), {method: Table VI's row name}; else None."""
    if point.kind != "loop":
        return None
    d = params.hj.dynamic
    hz, noise, ahead = point.value
    if (hz, noise) != (d.closed_loop.replan_hz, d.table6.human_noise_m):
        return None
    rows = human_rows(d)
    names = {m: next((n for n, r in rows.items() if r == (mode, 0.0 if mode == "obs" else ahead)), None)
             for m, mode in HUMAN_ROWS.items()}
    return None if None in names.values() else names


def points_to_run(params: Params) -> list[Point]:
    """``selected_points`` less those Table VI runs (``table_rows``): what the sweep simulates and caches."""
    return [p for p in selected_points(params) if table_rows(params, p) is None]


def from_table6(params: Params, point: Point, report: str | Path) -> dict:
    """A Table VI point's result from Table VI's report file, in ``run_point``'s row order; a missing report,
    or one of another profile or run count, is one line naming the command that writes it."""
    report = Path(report)
    fix = "run notebooks/hj/03_dynamic.ipynb first (`dvc repro hj_dynamic`)"
    if not report.is_file():
        raise DataError(f"{report} is missing: the sweep reads Table VI's own points from it; {fix}")
    runs, names, table = params.hj.dynamic.table6.runs, table_rows(params, point), json.loads(report.read_text())
    by_name = {(r["method"], r["scenario"]): r for r in table.get("rows", ())}
    rows = [{**by_name.get((names[m], s), {}), "method": m} for s in SCENARIOS for m in HUMAN_ROWS]
    if table.get("profile") != params.profile or any(r.get("runs") != runs for r in rows):
        raise DataError(f"{report} is not this profile's Table VI ({params.profile!r}, {runs} runs per cell, "
                        f"every row of point {point.name}): {fix}")
    return {"kind": point.kind, "value": list(point.value), "rows": rows, "source": "table6_dynamic"}  # as JSON reads it


def point_file(params: Params, point: Point, artifacts_dir: str | Path) -> Path:
    """Where the point's result is cached: its kind and the first 16 hex digits of its ``point_key``."""
    return Path(artifacts_dir) / SWEEP_SUBDIR / f"{point.kind}-{point_key(params, point, artifacts_dir)[:16]}.json"


def _applied(params: Params, point: Point) -> Params:
    """``params`` with the point's one change."""
    d = params.hj.dynamic
    if point.kind == "budget":
        d = dataclasses.replace(d, closed_loop=dataclasses.replace(d.closed_loop, max_expansions=int(point.value)))
    elif point.kind == "loop":
        hz, noise, ahead = point.value
        d = dataclasses.replace(d, closed_loop=dataclasses.replace(d.closed_loop, replan_hz=float(hz),
                                                                  human_prediction_s=float(ahead)),
                                table6=dataclasses.replace(d.table6, human_noise_m=float(noise)))
    else:
        raise ValueError(f"sweep point kind {point.kind!r}: use 'budget' or 'loop'")
    return dataclasses.replace(params, hj=dataclasses.replace(params.hj, dynamic=d))


def point_key(params: Params, point: Point, artifacts_dir: str | Path) -> str:
    """sha256 of what a point's result follows from: this code, the HJ parameters the runs read (with the
    point's change), and the stored grids and margins."""
    hj = _applied(params, point).hj
    inputs = {"code": code_fingerprint(__name__), "point": dataclasses.asdict(point),
              "hj": {"seed": hj.seed, **{k: dataclasses.asdict(getattr(hj, k)) for k in ("grids", "planner", "dynamic")}},
              "grids": files_fingerprint(Path(artifacts_dir) / "hj"),
              "margins": files_fingerprint(Path(artifacts_dir) / MARGINS_SUBDIR)}
    return hashlib.sha256(json.dumps(inputs, sort_keys=True, default=str).encode()).hexdigest()


def run_point(params: Params, point: Point, artifacts_dir: str | Path) -> dict:
    """The cell at one point: Table VIII rows (``budget``) or Table VI rows (``loop``), as the tables
    summarise them."""
    params = _applied(params, point)
    loop = ClosedLoop(params, artifacts_dir, log=lambda *_: None)
    rows = []
    if point.kind == "budget":
        for room, label in ROOM_NAMES.items():
            for heuristic, pruner in ROOM_COMBOS:
                run = loop.room_patrol(room, heuristic, pruner)
                rows.append(summarise_trips(f"{heuristic} + {pruner}", label, [run]))
    else:
        runs = params.hj.dynamic.table6.runs
        for scenario, simulate in zip(SCENARIOS, (loop.face_to_face, loop.zig_zag), strict=True):
            for method in HUMAN_ROWS:
                cell = [simulate(method, r) for r in range(runs)]
                rows.append(summarise_runs(method, scenario, cell, params.hj.dynamic.seed))
    return {"kind": point.kind, "value": point.value, "rows": rows}


def build_sweep(params: Params, data_dir: str | Path, artifacts_dir: str | Path) -> None:
    """The ``hj_sweep`` artefact step: every selected point's result under ``artifacts/hj_sensitivity``."""
    run_sweep(params, artifacts_dir)


def _run_and_store(args) -> dict:
    params, point, artifacts_dir, path = args
    result = run_point(params, point, artifacts_dir)
    write_json(path, result)
    return result


def run_sweep(params: Params, artifacts_dir: str | Path, progress: bool = True,
              table6: str | Path | None = None) -> list[dict]:
    """Every point of ``selected_points``, in point order: Table VI's from its report file ``table6`` (left
    out without it), the others from the cache where its key matches, else run (in ``hj.workers`` processes) and
    stored."""
    folder = Path(artifacts_dir) / SWEEP_SUBDIR
    folder.mkdir(parents=True, exist_ok=True)
    run = points_to_run(params)
    paths = {p: point_file(params, p, artifacts_dir) for p in run}
    todo = [(params, p, artifacts_dir, path) for p, path in paths.items() if not path.exists()]
    bar = tqdm(total=len(todo), desc="HJ sensitivity points", disable=not progress or not todo)
    workers = min(params.hj.workers, len(todo))
    if workers > 1:
        with ProcessPoolExecutor(workers) as pool:
            for _ in pool.map(_run_and_store, todo):
                bar.update()
    else:
        for job in todo:
            _run_and_store(job)
            bar.update()
    bar.close()
    kept = {path.name for path in paths.values()}
    for stale in folder.glob("*.json"):  # results of points no longer asked for, or of older inputs
        if stale.name not in kept:
            stale.unlink()
    return [json.loads(paths[p].read_text()) if p in paths else from_table6(params, p, table6)
            for p in selected_points(params) if p in paths or table6 is not None]
