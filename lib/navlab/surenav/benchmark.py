"""The SuReNav benchmark's executor, outcomes and summaries (Table I, Fig. 4), and the per-label control's methods.

``run_episode`` walks one method on one environment and ``table1_rows`` / ``fig4_rows`` summarise the
outcomes, for the context benchmark (``surenav.context``: Table I, Fig. 4, Fig. 5) and the per-label
control alike; ``Learned``, ``benchmark_runs`` and ``run_all`` run the per-label control's methods
(``surenav.tables``). Each environment plays inside its window (``episodes.window``: the start-goal box grown by the
executor's margin, as the expert planned), doubled while the method finds no plan inside it
(``windows.walk``, the same rule for every method); the walker of ``surenav.semi_static`` believes the
prior map and navigates in the true one. Per episode we keep the outcome (status, SR, SPL, total risk, the
human-likeness metrics where a demonstration exists, per-re-plan times); the summaries give every
mean its 95% bootstrap interval over environments and every success rate its Wilson interval.
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from multiprocessing import get_context
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

from navlab.core.params.surenav import SuReNavParams
from navlab.core.params.surenav_benchmark import BenchmarkParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.core.seeding import rng
from navlab.graphs.incremental import resegment
from navlab.metrics.frechet import normalised_frechet
from navlab.metrics.intervals import bootstrap_mean_ci, wilson_ci
from navlab.metrics.navigation import path_length, risk_table, spl, success, total_risk
from navlab.metrics.relaxation import relaxed_regions, set_iou
from navlab.surenav.baselines import ClassOrderedPolicy, DStarLitePolicy, ExpertPolicy, RCRPolicy
from navlab.surenav.baselines.rcr import risk_table as rcr_risk_table
from navlab.surenav.demo_priors import class_order, dstar_label_costs, load_training_traversal
from navlab.surenav.episodes import Environment
from navlab.surenav.experts.personas import PERSONAS
from navlab.surenav.experts.store import load_demos
from navlab.surenav.policy import SuReNavPolicy, learned_policy, scored_cost
from navlab.surenav.semi_static import Policy
from navlab.surenav.windows import PlanningWindow, WindowedPolicy, shortest_in_windows, walk

BASELINES = ("D* Lite", "COA*", "RCR")
EXPERT = "Expert (reference)"
SURENAV = "SuReNav"
SURENAV_RCR = "SuReNav with RCR scoring (ablation)"  # RCR's scoring function in place of the learned Psi
SURENAV_MPNN = "SuReNav, MPNN only (ablation)"  # the estimator without global attention
VARIANT = {SURENAV: "gps", SURENAV_MPNN: "mpnn"}  # trained methods -> surenav_estimator folder
NOT_RUN = {
    SURENAV: ("SuReNav was not run in this call (it needs the trained estimators of the surenav_estimator stage): "
              "its rows are null."),
    "ViPlanner^OSRM": "ViPlanner needs a photoreal 3D simulator and a vision model: out of scope, not run.",
}
_SEED = " [seed "


def seed_run(method: str, seed: int) -> str:
    """The run name of one training seed of a learned method (``method_of`` inverts it)."""
    return f"{method}{_SEED}{seed}]"


def method_of(run: str) -> str:
    """The method a run belongs to: "SuReNav [seed 1]" -> "SuReNav"; a baseline is its own method."""
    return run.split(_SEED)[0]


def seed_of(run: str) -> int:
    """The training seed of a ``seed_run`` name."""
    return int(run[len(method_of(run)) + len(_SEED):-1])


def surenav_runs(seeds, ablation_seeds) -> list[str]:
    """SuReNav on every training seed, the RCR-scoring ablation (no training: one run) and the MPNN-only
    ablation on ``ablation_seeds``."""
    return [*(seed_run(SURENAV, s) for s in seeds), SURENAV_RCR, *(seed_run(SURENAV_MPNN, s) for s in ablation_seeds)]


@dataclass(frozen=True)
class Learned:
    """What the methods take from the TRAINING demonstrations: the baselines' priors (``demo_priors``)
    and, for SuReNav, where its trained estimators are (``surenav_estimator`` stage) and its settings."""
    dstar_costs: np.ndarray  # (NUM_LABELS,) D* Lite cost per metre
    class_order: np.ndarray  # COA*: soft labels, most critical first
    artifacts_dir: str | None = None  # holds surenav/{gps,mpnn}/seed<k>/model.pt
    surenav: SuReNavParams | None = None

    @classmethod
    def from_training(cls, data_dir: str | Path, settings: BenchmarkParams, artifacts_dir: str | Path | None = None,
                      surenav: SuReNavParams | None = None) -> Learned:
        traversal = load_training_traversal(data_dir)
        return cls(dstar_label_costs(traversal, settings.dstar_cost_floor), class_order(traversal),
                   None if artifacts_dir is None else str(artifacts_dir), surenav)


_FACTORIES: dict = {}  # (artifacts_dir, variant, seed) -> policy factory: each estimator loads once per process


def surenav_policy(run: str, learned: Learned, settings: BenchmarkParams, scale: int = 1) -> Policy:
    """A fresh SuReNav policy for a run of ``surenav_runs``, its node window ``scale`` times the configured
    margin (``windows.PlanningWindow.scale``)."""
    if learned.artifacts_dir is None or learned.surenav is None:
        raise ValueError(f"{run!r} needs the trained estimators: build Learned.from_training(..., artifacts_dir=, "
                         "surenav=params.surenav)")
    s = learned.surenav
    method = method_of(run)
    if method == SURENAV_RCR:
        score = RCRPolicy(rcr_risk_table(settings.rcr.label_risk), settings.rcr.goal_weight).score
        return SuReNavPolicy(scored_cost(score, s.planner.rcr_scale_m), s.planner.mode,
                             s.model.window_margin_m * scale)
    policy = _surenav_factory(learned, method, seed_of(run))()
    policy.margin *= scale  # a fresh instance: its node window widens with the planning window
    return policy


def _surenav_factory(learned: Learned, method: str, seed: int):
    key = (learned.artifacts_dir, VARIANT[method], seed)
    if key not in _FACTORIES:
        _FACTORIES[key] = learned_policy(learned.artifacts_dir, learned.surenav, VARIANT[method], seed)
    return _FACTORIES[key]


def benchmark_runs(learned: Learned) -> tuple[list[str], list[str]]:
    """(runs to execute, methods to report) of Table I and Fig. 4: the baselines, SuReNav on every
    training seed, its two ablations (the MPNN one on the first ``train.ablation_seeds`` seeds) and the
    expert reference. Every estimator is loaded here, once (worker processes inherit them), so a missing
    one stops before any episode runs, naming the stage that builds it."""
    if learned.surenav is None or learned.artifacts_dir is None:
        raise ValueError("benchmark_runs needs Learned.from_training(..., artifacts_dir=, surenav=params.surenav)")
    seeds = list(learned.surenav.train.seeds)
    runs = [*BASELINES, EXPERT, *surenav_runs(seeds, seeds[:learned.surenav.train.ablation_seeds])]
    for run in runs:
        if method_of(run) in VARIANT:
            _surenav_factory(learned, method_of(run), seed_of(run))
    return runs, [*BASELINES, SURENAV, SURENAV_RCR, SURENAV_MPNN, EXPERT]


def make_policy(method: str, env: Environment, learned: Learned, settings: BenchmarkParams, scale: int = 1) -> Policy:
    """A fresh policy for one episode; ``method`` is a baseline, the expert or a SuReNav run
    (``surenav_runs``). ``scale``: the planning window's widening (``windows.PlanningWindow.scale``), applied
    to a method's own query window (the Expert's search box, SuReNav's node window)."""
    res = env.prior.frame.resolution
    if method == "D* Lite":
        return DStarLitePolicy(learned.dstar_costs)
    if method == "COA*":
        return ClassOrderedPolicy(learned.class_order)
    if method == "RCR":
        return RCRPolicy(rcr_risk_table(settings.rcr.label_risk), settings.rcr.goal_weight)
    if method == EXPERT:
        return ExpertPolicy(PERSONAS[env.persona], int(np.ceil(settings.executor.window_margin_m * scale / res)))
    if method_of(method) in (*VARIANT, SURENAV_RCR) and (method == SURENAV_RCR or _SEED in method):
        return surenav_policy(method, learned, settings, scale)
    raise ValueError(f"unknown method {method!r}; methods are {', '.join((*BASELINES, EXPERT))} and the SuReNav "
                     f"runs {seed_run(SURENAV, 0)!r}, {SURENAV_RCR!r}, {seed_run(SURENAV_MPNN, 0)!r}")


@dataclass(frozen=True)
class Outcome:
    method: str
    environment: str
    group: str
    status: str
    success: bool
    length_m: float
    shortest_m: float
    spl: float
    total_risk: float
    frechet: float | None  # human-likeness environments only
    relaxation_iou: float | None
    replan_seconds: tuple[float, ...]
    trajectory: np.ndarray  # (K, 2) world metres
    window_scale: int = 1  # the last planning window's margin / the configured one (``windows.walk``)


def reference_superpixels(env: Environment, graph: GraphParams, stored: np.ndarray) -> np.ndarray:
    """The partition the demonstration's relaxed superpixels refer to: the stored one after the
    incremental update for the perturbation (``experts.demo_graph``'s raster)."""
    demo = env.demonstration
    if demo is None or not len(demo.delta_cells):
        return stored
    changed = np.zeros(env.truth.shape, dtype=bool)
    changed.ravel()[demo.delta_cells] = True
    return resegment(stored, env.truth, changed, graph.compactness)


def run_episode(env: Environment, method: str, make: WindowedPolicy, settings: BenchmarkParams, graph: GraphParams,
                risk: np.ndarray, superpixels: np.ndarray | None = None) -> Outcome:
    """One method on one environment (``make``: a fresh policy of the method per planning window, see
    ``windows.walk``); ``superpixels``: the demonstration's partition (human-likeness)."""
    res = env.prior.frame.resolution
    ex = walk(env, make, settings.executor, graph)
    ok = ex.reached and success(ex.trajectory, env.truth, env.goal)
    length = path_length(ex.trajectory, res)
    shortest = shortest_in_windows(env.truth, env.start, env.goal,
                                   int(np.ceil(settings.executor.window_margin_m / res)), res)
    xy = env.prior.frame.cell_to_world(ex.trajectory)
    frechet = iou = None
    if env.demonstration is not None:
        demo = env.demonstration
        frechet = normalised_frechet(xy, demo.path, demo.start, demo.goal)
        if superpixels is not None:
            mine = relaxed_regions(ex.trajectory, env.truth, superpixels)
            iou = set_iou(mine, demo.relaxed_superpixels)
    return Outcome(method, env.name, env.group, ex.status, ok, length, shortest, spl(ok, length, shortest),
                   total_risk(ex.trajectory, env.truth, risk, res), frechet, iou,
                   tuple(r.seconds for r in ex.replans), xy, ex.window.scale)


def _run_one(task) -> Outcome:
    env, method, learned, settings, graph, superpixels = task

    def make(w: PlanningWindow) -> Policy:
        return make_policy(method, env, learned, settings, w.scale)
    return run_episode(env, method, make, settings, graph, risk_table(settings.unit_risk), superpixels)


def _one_thread() -> None:
    """One torch thread per episode process. With torch's default (a thread per core) in every worker,
    the workers' OpenMP threads spin against each other: on 2 cores Fig. 4 ran 15x slower with 2 workers
    than with one thread each (``benchmarks/surenav_workers.py``). The sequential path uses one thread
    too, so the outcomes' float rounding does not depend on ``workers``."""
    torch.set_num_threads(1)


def run_all(envs: list[Environment], methods, learned: Learned, settings: BenchmarkParams, graph: GraphParams,
            data_dir: str | Path | None = None, progress: bool = True) -> list[Outcome]:
    """Every method on every environment, in (environment, method) order, on ``settings.workers``
    processes (episodes are independent and deterministic, and every process runs torch on one thread,
    so the outcomes do not depend on it). ``data_dir`` is needed for the human-likeness set: the stored
    superpixels of the test maps that the demonstrations' relaxed regions refer to."""
    stored = {}
    if any(e.demonstration is not None for e in envs):
        stored = {md.map_name: md.superpixels for md in load_demos(data_dir, "test")}
    tasks = []
    for env in envs:
        superpixels = reference_superpixels(env, graph, stored[env.group]) if env.demonstration is not None else None
        tasks += [(env, method, learned, settings, graph, superpixels) for method in methods]
    bar = {"total": len(tasks), "desc": "episodes x methods", "unit": "run", "disable": not progress}
    if settings.workers == 1:
        threads = torch.get_num_threads()
        _one_thread()
        try:
            return [_run_one(t) for t in tqdm(tasks, **bar)]
        finally:
            torch.set_num_threads(threads)
    with ProcessPoolExecutor(settings.workers, mp_context=get_context("fork"), initializer=_one_thread) as pool:
        return list(tqdm(pool.map(_run_one, tasks, chunksize=2), **bar))


def mean_ci(values, settings: BenchmarkParams, *key) -> tuple[float, list[float]]:
    """(mean, its 95% bootstrap interval over the units), the draws seeded by ``key``."""
    lo, hi = bootstrap_mean_ci(values, rng(settings.seed, "bootstrap", *key), settings.bootstrap_samples)
    return float(np.mean(values)), [round(lo, 4), round(hi, 4)]


def replan_seconds(outcomes: list[Outcome], method: str) -> np.ndarray:
    return np.array([s for o in outcomes if method_of(o.method) == method for s in o.replan_seconds])


def _per_environment(mine: list[Outcome], value) -> tuple[np.ndarray, np.ndarray]:
    """(per-environment value averaged over the method's runs — its training seeds —, per-run means)."""
    envs, runs = list(dict.fromkeys(o.environment for o in mine)), list(dict.fromkeys(o.method for o in mine))
    table = {(o.environment, o.method): float(value(o)) for o in mine}
    grid = np.array([[table[e, r] for r in runs] for e in envs])
    return grid.mean(axis=1), grid.mean(axis=0)


def _seed_sd(per_run: np.ndarray) -> float | None:
    """Standard deviation over training seeds of a method's mean (None for a single run)."""
    return round(float(np.std(per_run, ddof=1)), 4) if len(per_run) > 1 else None


def fig4_rows(outcomes: list[Outcome], methods, settings: BenchmarkParams) -> list[dict]:
    """Per method and city: SR, SPL, total risk and path length, means over episodes with 95% intervals
    (Wilson for a single run's SR, else bootstrap over episodes); a method trained on several seeds
    (``seed_run``) averages each episode over its seeds and gives the seed spread (``*_seed_sd``)."""
    rows = []
    for method in methods:
        for city in dict.fromkeys(o.group for o in outcomes):
            mine = [o for o in outcomes if method_of(o.method) == method and o.group == city]
            if not mine:
                continue
            episodes, per_run = _per_environment(mine, lambda o: o.success)
            row = {"method": method, "city": city, "episodes": len(episodes), "seeds": len(per_run),
                   "sr": float(episodes.mean())}
            if len(per_run) == 1:
                row["sr_ci"] = [round(v, 4) for v in wilson_ci(int(episodes.sum()), len(episodes))]
            else:
                row["sr_ci"] = mean_ci(episodes, settings, "fig4", method, city, "sr")[1]
            row["sr_seed_sd"] = _seed_sd(per_run)
            for col, value in (("spl", lambda o: o.spl), ("total_risk", lambda o: o.total_risk),
                               ("path_length_m", lambda o: o.length_m)):
                episodes, per_run = _per_environment(mine, value)
                row[col], row[f"{col}_ci"] = mean_ci(episodes, settings, "fig4", method, city, col)
                row[f"{col}_seed_sd"] = _seed_sd(per_run)
            rows.append(row)
    return rows


def table1_rows(outcomes: list[Outcome], methods, settings: BenchmarkParams) -> list[dict]:
    """Per method: normalised Fréchet and relaxation IoU (bootstrap over environments), and SR; several
    training seeds are averaged per environment, with the seed spread (``*_seed_sd``)."""
    rows = []
    for method in methods:
        mine = [o for o in outcomes if method_of(o.method) == method]
        if not mine:
            continue
        envs, per_run = _per_environment(mine, lambda o: o.success)
        row = {"method": method, "environments": len(envs), "seeds": len(per_run), "sr": float(envs.mean())}
        for col in ("frechet", "relaxation_iou"):
            envs, per_run = _per_environment(mine, lambda o, col=col: getattr(o, col))
            row[col], row[f"{col}_ci"] = mean_ci(envs, settings, "table1", method, col)
            row[f"{col}_seed_sd"] = _seed_sd(per_run)
        rows.append(row)
    return rows


def null_rows(method: str, keys: list[dict], columns) -> list[dict]:
    """Rows of a method that was not run: every metric null (the reason goes in the notes)."""
    return [{**k, "method": method, **{c: None for c in columns}} for k in keys]


TABLE1_COLUMNS = ["method", "environments", "seeds", "frechet", "frechet_ci", "frechet_seed_sd", "relaxation_iou",
                  "relaxation_iou_ci", "relaxation_iou_seed_sd", "sr"]
FIG4_COLUMNS = ["method", "city", "episodes", "seeds", "sr", "sr_ci", "sr_seed_sd", "spl", "spl_ci", "spl_seed_sd",
                "total_risk", "total_risk_ci", "total_risk_seed_sd", "path_length_m", "path_length_m_ci",
                "path_length_m_seed_sd"]


def replan_note(outcomes: list[Outcome], methods) -> str:
    """Per-re-plan wall time per method: median and 95th percentile, and re-plans per episode."""
    parts = []
    for m in methods:
        t = replan_seconds(outcomes, m)
        if len(t):
            episodes = sum(method_of(o.method) == m for o in outcomes)
            parts.append(f"{m} {1e3 * np.median(t):.1f} ms median / {1e3 * np.quantile(t, 0.95):.1f} ms p95 "
                         f"({len(t) / episodes:.1f} re-plans per episode)")
    return "Per re-plan time (2-core CPU): " + "; ".join(parts) + "."


def most_contrasting(outcomes: list[Outcome]) -> dict[str, str]:
    """Per group (city), the environment whose methods' path lengths differ most (relative spread):
    the episode Fig. 5 shows, chosen by a rule rather than by eye."""
    best: dict[str, tuple[float, str]] = {}
    for env in dict.fromkeys(o.environment for o in outcomes):
        mine = [o for o in outcomes if o.environment == env]
        lengths = np.array([o.length_m for o in mine])
        spread = float((lengths.max() - lengths.min()) / max(lengths.min(), 1e-9))
        group = mine[0].group
        if group not in best or spread > best[group][0]:
            best[group] = (spread, env)
    return {g: env for g, (_, env) in best.items()}
