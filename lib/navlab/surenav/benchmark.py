"""Run every method of the SuReNav benchmark on every environment and summarise (Table I, Fig. 4).

Each environment plays inside its window (``episodes.window``: the start-goal box grown by the
executor's margin, as the expert planned); the walker of ``sim.semi_static`` believes the prior map
and navigates in the true one. Per episode we keep the outcome (status, SR, SPL, total risk, the
human-likeness metrics where a demonstration exists, per-re-plan times); the summaries give every
mean its 95% bootstrap interval over environments and every success rate its Wilson interval.
"""

from __future__ import annotations

from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from multiprocessing import get_context
from pathlib import Path

import numpy as np
from tqdm import tqdm

from navlab.core.params.surenav_benchmark import BenchmarkParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.core.seeding import rng
from navlab.graphs.incremental import resegment
from navlab.metrics.frechet import normalised_frechet
from navlab.metrics.intervals import bootstrap_mean_ci, wilson_ci
from navlab.metrics.navigation import (
    path_length,
    risk_table,
    shortest_feasible_length,
    spl,
    success,
    total_risk,
)
from navlab.metrics.relaxation import relaxed_regions, set_iou
from navlab.sim.semi_static import Policy, execute
from navlab.surenav.baselines import ClassOrderedPolicy, DStarLitePolicy, ExpertPolicy, RCRPolicy
from navlab.surenav.baselines.rcr import risk_table as rcr_risk_table
from navlab.surenav.demo_priors import class_order, dstar_label_costs, load_training_traversal
from navlab.surenav.episodes import Environment, window
from navlab.surenav.experts.personas import PERSONAS
from navlab.surenav.experts.store import load_demos

BASELINES = ("D* Lite", "COA*", "RCR")
EXPERT = "Expert (reference)"
SURENAV = "SuReNav"
NOT_RUN = {
    SURENAV: "SuReNav (the learned relaxation-cost estimator) is issue 10 and not plugged in yet: its rows are null.",
    "ViPlanner^OSRM": "ViPlanner needs a photoreal 3D simulator and a vision model: out of scope, not run.",
}


@dataclass(frozen=True)
class Learned:
    """What the baselines take from the TRAINING demonstrations (``demo_priors``)."""
    dstar_costs: np.ndarray  # (NUM_LABELS,) D* Lite cost per metre
    class_order: np.ndarray  # COA*: soft labels, most critical first

    @classmethod
    def from_training(cls, data_dir: str | Path, settings: BenchmarkParams) -> Learned:
        traversal = load_training_traversal(data_dir)
        return cls(dstar_label_costs(traversal, settings.dstar_cost_floor), class_order(traversal))


def make_policy(method: str, env: Environment, learned: Learned, settings: BenchmarkParams) -> Policy:
    """A fresh policy for one episode."""
    res = env.prior.frame.resolution
    if method == "D* Lite":
        return DStarLitePolicy(learned.dstar_costs)
    if method == "COA*":
        return ClassOrderedPolicy(learned.class_order)
    if method == "RCR":
        return RCRPolicy(rcr_risk_table(settings.rcr.label_risk), settings.rcr.goal_weight)
    if method == EXPERT:
        return ExpertPolicy(PERSONAS[env.persona], int(np.ceil(settings.executor.window_margin_m / res)))
    raise ValueError(f"unknown method {method!r}; methods are {', '.join((*BASELINES, EXPERT))}")


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


def reference_superpixels(env: Environment, graph: GraphParams, stored: np.ndarray) -> np.ndarray:
    """The partition the demonstration's relaxed superpixels refer to: the stored one after the
    incremental update for the perturbation (``experts.demo_graph``'s raster)."""
    demo = env.demonstration
    if demo is None or not len(demo.delta_cells):
        return stored
    changed = np.zeros(env.truth.shape, dtype=bool)
    changed.ravel()[demo.delta_cells] = True
    return resegment(stored, env.truth, changed, graph.compactness)


def run_episode(env: Environment, method: str, policy: Policy, settings: BenchmarkParams, graph: GraphParams,
                risk: np.ndarray, superpixels: np.ndarray | None = None) -> Outcome:
    """One method on one environment; ``superpixels``: the demonstration's partition (human-likeness)."""
    res = env.prior.frame.resolution
    box = window(env.truth.shape, env.start, env.goal, int(np.ceil(settings.executor.window_margin_m / res)))
    off = np.array([box[0].start, box[1].start])
    prior, truth = env.prior.crop(*box), env.truth[box]
    start, goal = env.start - off, env.goal - off
    ex = execute(prior, truth, start, goal, policy, settings.executor, graph, full_cells=env.prior.labels.size)
    ok = ex.reached and success(ex.trajectory, truth, goal)
    length = path_length(ex.trajectory, res)
    shortest = shortest_feasible_length(truth, start, goal, res)
    xy = prior.frame.cell_to_world(ex.trajectory)
    frechet = iou = None
    if env.demonstration is not None:
        demo = env.demonstration
        frechet = normalised_frechet(xy, demo.path, demo.start, demo.goal)
        if superpixels is not None:
            mine = relaxed_regions(ex.trajectory + off, env.truth, superpixels)
            iou = set_iou(mine, demo.relaxed_superpixels)
    return Outcome(method, env.name, env.group, ex.status, ok, length, shortest, spl(ok, length, shortest),
                   total_risk(ex.trajectory, truth, risk, res), frechet, iou,
                   tuple(r.seconds for r in ex.replans), xy)


def _run_one(task) -> Outcome:
    env, method, learned, settings, graph, superpixels = task
    policy = make_policy(method, env, learned, settings)
    return run_episode(env, method, policy, settings, graph, risk_table(settings.unit_risk), superpixels)


def run_all(envs: list[Environment], methods, learned: Learned, settings: BenchmarkParams, graph: GraphParams,
            data_dir: str | Path | None = None, progress: bool = True) -> list[Outcome]:
    """Every method on every environment, in (environment, method) order, on ``settings.workers``
    processes (episodes are independent and deterministic, so the outcomes do not depend on it).
    ``data_dir`` is needed for the human-likeness set: the stored superpixels of the test maps that
    the demonstrations' relaxed regions refer to."""
    stored = {}
    if any(e.demonstration is not None for e in envs):
        stored = {md.map_name: md.superpixels for md in load_demos(data_dir, "test")}
    tasks = []
    for env in envs:
        superpixels = reference_superpixels(env, graph, stored[env.group]) if env.demonstration is not None else None
        tasks += [(env, method, learned, settings, graph, superpixels) for method in methods]
    bar = {"total": len(tasks), "desc": "episodes x methods", "unit": "run", "disable": not progress}
    if settings.workers == 1:
        return [_run_one(t) for t in tqdm(tasks, **bar)]
    with ProcessPoolExecutor(settings.workers, mp_context=get_context("fork")) as pool:
        return list(tqdm(pool.map(_run_one, tasks, chunksize=2), **bar))


def _mean_ci(values, settings: BenchmarkParams, *key) -> tuple[float, list[float]]:
    lo, hi = bootstrap_mean_ci(values, rng(settings.seed, "bootstrap", *key), settings.bootstrap_samples)
    return float(np.mean(values)), [round(lo, 4), round(hi, 4)]


def replan_seconds(outcomes: list[Outcome], method: str) -> np.ndarray:
    return np.array([s for o in outcomes if o.method == method for s in o.replan_seconds])


def fig4_rows(outcomes: list[Outcome], methods, settings: BenchmarkParams) -> list[dict]:
    """Per method and city: SR (Wilson), SPL, total risk and path length (bootstrap), means over episodes."""
    rows = []
    for method in methods:
        for city in dict.fromkeys(o.group for o in outcomes):
            mine = [o for o in outcomes if o.method == method and o.group == city]
            if not mine:
                continue
            wins = sum(o.success for o in mine)
            row = {"method": method, "city": city, "episodes": len(mine), "sr": wins / len(mine),
                   "sr_ci": [round(v, 4) for v in wilson_ci(wins, len(mine))]}
            for col, values in (("spl", [o.spl for o in mine]), ("total_risk", [o.total_risk for o in mine]),
                                ("path_length_m", [o.length_m for o in mine])):
                row[col], row[f"{col}_ci"] = _mean_ci(values, settings, "fig4", method, city, col)
            rows.append(row)
    return rows


def table1_rows(outcomes: list[Outcome], methods, settings: BenchmarkParams) -> list[dict]:
    """Per method: normalised Fréchet and relaxation IoU (bootstrap), and SR, over all environments."""
    rows = []
    for method in methods:
        mine = [o for o in outcomes if o.method == method]
        if not mine:
            continue
        row = {"method": method, "environments": len(mine), "sr": float(np.mean([o.success for o in mine]))}
        for col in ("frechet", "relaxation_iou"):
            row[col], row[f"{col}_ci"] = _mean_ci([getattr(o, col) for o in mine], settings, "table1", method, col)
        rows.append(row)
    return rows


def null_rows(method: str, keys: list[dict], columns) -> list[dict]:
    """Rows of a method that was not run: every metric null (the reason goes in the notes)."""
    return [{**k, "method": method, **{c: None for c in columns}} for k in keys]


TABLE1_COLUMNS = ["method", "environments", "frechet", "frechet_ci", "relaxation_iou", "relaxation_iou_ci", "sr"]
FIG4_COLUMNS = ["method", "city", "episodes", "sr", "sr_ci", "spl", "spl_ci", "total_risk", "total_risk_ci",
                "path_length_m", "path_length_m_ci"]


def replan_note(outcomes: list[Outcome], methods) -> str:
    """Per-re-plan wall time per method: median and 95th percentile, and re-plans per episode."""
    parts = []
    for m in methods:
        t = replan_seconds(outcomes, m)
        if len(t):
            episodes = sum(o.method == m for o in outcomes)
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
