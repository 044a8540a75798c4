"""SuReNav's Table I on the context demonstrator (issues 25 and 60): every row, paired intervals and the claims.

The benchmark on which the paper's claim can be tested (a per-label cost cannot imitate its
demonstrations), so the paper's Table I claims are decided here (``claims.T1``); the per-label
demonstrator's Table I is a control (``surenav.tables``). Environments: the test demonstrations of
``surenav_context_demos`` (Table I's 100 semi-static environments, redrawn by the context demonstrator).
Every method walks Table I's executor (``benchmark.run_episode``); IoU on the superpixels of each
demonstration's stored partition.

Rows:

- ``SuReNav``: the ``surenav_context_estimator`` GPS estimator trained with the paper's loss and gradient
  (Eq. 12-14 with the false positives on the closed set, through the straight-through differentiable A*;
  the schedule, w_fp / w_fn and the seeds are ours, the paper gives none), every training seed, per environment the mean over seeds; beside it, on the first ``train.ablation_seeds``
  seeds, the other node input (an ablation) and our two training variants, the blackbox gradient and the
  false positives counted on the plan (``training.estimator_runs``), each with paired intervals against it;
- SuReNav's executor with three non-learned Psi: the *label-table* Psi ((per-label cost - 1) x
  sqrt(area), the per-label demonstrator's personas' mean costs: fixed regional costs, the control the
  paper's claim is about), the *oracle-set* Psi (0 on soft regions holding a cell the demonstration
  entered, 1000 m on other soft ones: the executor's ceiling) and the *rule* Psi (the demonstrator's
  rules at the personas' mean tolerances, from the believed map);
- the best per-label field (grid A*), chosen among the non-learned fields on the VALIDATION
  demonstrations (``measure.select_field``), never on the test environments;
- D* Lite under three readings of its cost rule (``demo_priors.dstar_readings``: 0-1 scaled reciprocal
  traversal rate lifted onto [surenav.benchmark.dstar_cost_floor, 1] — the main row, as in Table I,
  the reading closest to the paper's text —, onto the other floor, and 1 + scaled), COA* and RCR,
  their priors from the context TRAINING demonstrations only (``demo_priors.label_traversal``);
- the Expert (the context demonstrator's own planner, true persona).

Claims (``navlab.surenav.claims``, paired over environments): the paper's Table I claims, the same
registry entries ``table1_human_likeness`` decides, and our own checks: SuReNav's IoU above and Fréchet
below each D* Lite reading's and the label-table Psi's.

First measured on ``default`` (branch surenav-context-benchmark, before any ``dvc repro``; Fréchet /
IoU): SuReNav (3 seeds, context input) 0.129 / 0.533; labels-only input (1 seed) 0.154 / 0.496;
label-table Psi 0.154 / 0.459; oracle-set Psi 0.047 / 0.857; rule Psi 0.091 / 0.640; per-label field
0.163 / 0.403; D* Lite 0.166 / 0.408 (floor 0.01: 0.176 / 0.405; 1 + scaled: 0.234 / 0.263); COA*
0.238 / 0.300; RCR 0.265 / 0.183; Expert 0.072 / 0.703. Against every D* Lite reading both claims
hold; against the label-table Psi the IoU claim holds (+0.073 [0.005, 0.146]) and the Fréchet one does
not (-0.025 [-0.053, 0.001]). The context input over the labels-only one: +0.037 IoU [-0.012, 0.088].
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path
from typing import NamedTuple

import numpy as np
import torch
from tqdm.auto import tqdm

from navlab.core.labels import SOFT_IDS
from navlab.core.params import Params
from navlab.core.seeding import rng
from navlab.graphs.region_graph import RegionGraph
from navlab.metrics.intervals import bootstrap_mean_ci
from navlab.metrics.navigation import risk_table
from navlab.metrics.tables import Table
from navlab.surenav import claims, paper
from navlab.surenav.baselines import ClassOrderedPolicy, DStarLitePolicy, RCRPolicy
from navlab.surenav.baselines.cost_field import CostFieldPolicy
from navlab.surenav.baselines.rcr import risk_table as rcr_risk_table
from navlab.surenav.benchmark import (
    TABLE1_COLUMNS,
    Outcome,
    method_of,
    reference_superpixels,
    run_episode,
    seed_of,
    seed_run,
    table1_rows,
)
from navlab.surenav.context.dataset import load_context_demos, load_index, stored_environments
from navlab.surenav.context.measure import FieldChoice, select_field
from navlab.surenav.context.personas import CONTEXT_PERSONAS, mean_persona
from navlab.surenav.context.training import (
    EstimatorRun,
    context_cost,
    context_model_path,
    estimator_runs,
    main_run,
)
from navlab.surenav.context.walker import ContextWalker, RuleCost
from navlab.surenav.demo_priors import DSTAR, class_order, dstar_note, dstar_readings, label_traversal
from navlab.surenav.episodes import Environment
from navlab.surenav.policy import SuReNavPolicy
from navlab.surenav.semi_static import Policy
from navlab.surenav.train import read_log
from navlab.surenav.windows import PlanningWindow, prior_hard

SURENAV = "SuReNav"
ABLATION = "SuReNav, {} input (ablation)"
HELD_OUT = "SuReNav trained without {}"  # the leave-one-city-out runs (``held_out``)
GRADIENT_NOTES = {  # how each gradient's run trains (``training._schedule``), formatted with e = the estimator params
    "straight_through": ("the paper's: Neural A*'s straight-through selection softmax, with surenav.train's lr, epochs "
                         "and early stopping"),
    "blackbox": ("Vlastelica et al. 2020: the plan's change under a second exact A* at Psi + {e.lambda_m:g} m x dL/dy "
                 "gives the gradient; {e.epochs} epochs on a cosine schedule from lr {e.lr:g}, the best validation "
                 "epoch kept"),
}
GRADIENT_VARIANT = {"straight_through": "SuReNav, straight-through gradient (the paper's; variant)",
                    "blackbox": "SuReNav, blackbox gradient (ours, variant)"}
FALSE_POSITIVE_VARIANT = {"closed": "SuReNav, false positives on the closed set (the paper's; variant)",
                          "path": "SuReNav, false positives on the plan (ours, variant)"}
LABEL_PSI = "SuReNav with label-table Psi"
ORACLE_PSI = "SuReNav with oracle-set Psi"
RULE_PSI = "SuReNav with rule Psi"
FIELD = "best per-label field (chosen on validation demos)"
LABEL_TABLE_FIELD = "the per-label demonstrator's personas' mean costs"  # the label-table Psi's costs (by definition)
EXPERT = "Expert (context demonstrator's planner)"
ORACLE_OTHER_M = 1000.0  # oracle-set Psi on soft regions the demonstration did not enter


def paired_against(methods_) -> list[str]:
    """The rows SuReNav's claims are paired against: every D* Lite reading and the label-table Psi."""
    return [m for m in methods_ if m.startswith(DSTAR)] + [LABEL_PSI]


def label_table_cost(table: np.ndarray) -> Callable:
    """Psi = (cost per metre of the node's label - 1) x sqrt(its area) on soft nodes (0 on free ones)."""
    def cost(graph: RegionGraph, nodes: np.ndarray, position_xy=None, goal_xy=None) -> np.ndarray:
        label = graph.node_label[nodes]
        return np.where(np.isin(label, SOFT_IDS), (table[label] - 1.0) * np.sqrt(graph.area[nodes]), 0.0)
    return cost


def oracle_cost(relaxed: np.ndarray, other_m: float = ORACLE_OTHER_M) -> Callable:
    """Psi = 0 on soft nodes holding a cell of ``relaxed`` (bool raster in the graph's frame), ``other_m``
    on the other soft nodes: the demonstration's own relaxed set as Psi."""
    def cost(graph: RegionGraph, nodes: np.ndarray, position_xy=None, goal_xy=None) -> np.ndarray:
        hit = np.zeros(graph.num_nodes, dtype=bool)
        at = graph.node_raster[relaxed]
        hit[at[at >= 0]] = True
        soft = np.isin(graph.node_label[nodes], SOFT_IDS)
        return np.where(soft & ~hit[nodes], other_m, 0.0)
    return cost


def relaxed_window(env: Environment, w: PlanningWindow) -> np.ndarray:
    """The demonstration's relaxed cells as a bool raster of a planning window (``windows.walk``'s box)."""
    mask = np.zeros(env.truth.shape, dtype=bool)
    mask.ravel()[env.demonstration.relaxed_cells] = True
    return mask[w.box]


def best_field(params: Params, artifacts_dir: str | Path) -> FieldChoice:
    """The best per-label field, chosen on the context validation demonstrations (``measure.select_field``)."""
    s = params.surenav
    return select_field(load_context_demos(artifacts_dir, "train"), load_context_demos(artifacts_dir, "val"),
                        s.benchmark, s.graph)


def run_name(run: EstimatorRun, main: EstimatorRun) -> str:
    """The row of an estimator run, given the main run (``training.main_run``)."""
    if run.held_out:
        return HELD_OUT.format(run.held_out)
    if run == main:
        return SURENAV
    if run.features != main.features:
        return ABLATION.format(run.features)
    return GRADIENT_VARIANT[run.gradient] if run.gradient != main.gradient else FALSE_POSITIVE_VARIANT[run.false_positives]


Factory = Callable[[Environment, PlanningWindow], Policy]  # a fresh policy per environment and planning window


def estimator_factory(params: Params, artifacts_dir: str | Path, run: EstimatorRun, seed: int) -> Factory:
    """SuReNav's executor with one trained run's Psi (loaded once); a widened window (``windows.walk``)
    scales its own query window by its ``scale``."""
    s = params.surenav
    make = context_cost(artifacts_dir, run, seed)
    return lambda env, w: SuReNavPolicy(make(), s.planner.mode, s.model.window_margin_m * w.scale)


def surenav_runs(params: Params, artifacts_dir: str | Path, every_run: bool = True) -> dict[str, Factory]:
    """{run name: factory} of the trained estimators: the main run on every seed and, with ``every_run``, the
    ablation and variants (``training.estimator_runs``)."""
    s = params.surenav
    main = main_run(s.demos.context, s.train)
    chosen = {r: seeds for r, seeds in estimator_runs(s.demos.context, s.train).items() if every_run or r == main}
    return {seed_run(run_name(run, main), seed): estimator_factory(params, artifacts_dir, run, seed)
            for run, seeds in chosen.items() for seed in seeds}


def baselines(params: Params, artifacts_dir: str | Path, every_reading: bool = True) -> dict[str, Factory]:
    """{name: factory} of D* Lite (every reading of its cost rule, or the main one), COA*, RCR and the Expert,
    their priors from the context TRAINING demonstrations only."""
    s = params.surenav
    settings, margin = s.benchmark, s.model.window_margin_m
    train = load_context_demos(artifacts_dir, "train")
    traversal = label_traversal([md for _, md in train], [smap for smap, _ in train])
    runs: dict[str, Factory] = {}
    for name, costs in dstar_readings(traversal, settings.dstar_cost_floor).items():
        if every_reading or name == DSTAR:
            runs[name] = lambda env, w, costs=costs: DStarLitePolicy(costs)
    order = class_order(traversal)
    runs["COA*"] = lambda env, w: ClassOrderedPolicy(order)
    rcr = rcr_risk_table(settings.rcr.label_risk)
    runs["RCR"] = lambda env, w: RCRPolicy(rcr, settings.rcr.goal_weight)
    runs[EXPERT] = lambda env, w: ContextWalker(CONTEXT_PERSONAS[env.persona], margin * w.scale, prior_hard(env, w))
    return runs


def methods(params: Params, artifacts_dir: str | Path, field: FieldChoice) -> tuple[dict[str, Factory], list[str]]:
    """Table I's (run name -> factory, methods in report order): every estimator run, the non-learned Psi,
    the best per-label field (``field``, ``best_field``) and every baseline."""
    s = params.surenav
    mode, margin = s.planner.mode, s.model.window_margin_m
    label_field = field.costs[LABEL_TABLE_FIELD]
    runs = surenav_runs(params, artifacts_dir)
    runs[LABEL_PSI] = lambda env, w: SuReNavPolicy(label_table_cost(label_field), mode, margin * w.scale)
    runs[ORACLE_PSI] = lambda env, w: SuReNavPolicy(oracle_cost(relaxed_window(env, w)), mode, margin * w.scale)
    runs[RULE_PSI] = lambda env, w: SuReNavPolicy(RuleCost(mean_persona(), prior_hard(env, w)), mode, margin * w.scale)
    runs[FIELD] = lambda env, w: CostFieldPolicy(field.table)
    runs.update(baselines(params, artifacts_dir))
    return runs, list(dict.fromkeys(method_of(r) for r in runs))


_JOB: dict = {}  # what forked workers read: runs, environments, partitions, settings


def _run(task: tuple[int, str]) -> Outcome:
    i, name = task
    env, superpixels = _JOB["envs"][i], _JOB["superpixels"][i]
    s = _JOB["params"].surenav
    return run_episode(env, name, lambda w: _JOB["runs"][name](env, w), s.benchmark, s.graph, risk_table(s.benchmark.unit_risk),
                       superpixels)


def run_all(envs: list[Environment], stored: dict[str, np.ndarray], runs: dict[str, Factory], params: Params,
            progress: bool = True) -> list[Outcome]:
    """Every run on every environment on ``surenav.benchmark.workers`` forked processes, one torch thread
    each (episodes are deterministic: the outcomes do not depend on the worker count). ``stored``: each
    test tile's superpixels, for the environments with a demonstration (IoU); an episode without one
    (the safety-efficiency set) needs none."""
    s = params.surenav
    _JOB.update(envs=envs, runs=runs, params=params,
                superpixels=[None if e.demonstration is None else reference_superpixels(e, s.graph, stored[e.group])
                             for e in envs])
    tasks = [(i, name) for i in range(len(envs)) for name in runs]
    bar = {"total": len(tasks), "desc": "context episodes x methods", "disable": not progress}
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        if s.benchmark.workers == 1:
            return [_run(t) for t in tqdm(tasks, **bar)]
        with ProcessPoolExecutor(s.benchmark.workers, mp_context=get_context("fork")) as pool:
            return list(tqdm(pool.map(_run, tasks, chunksize=4), **bar))
    finally:
        torch.set_num_threads(threads)
        _JOB.clear()


def paired(outcomes: list[Outcome], a: str, b: str, column: str, seed: int, resamples: int) -> dict:
    """Mean of a - b over environments and its 95% percentile-bootstrap interval (the notes' deltas)."""
    v = claims.paired_values(outcomes, (a, b), column)
    diff = v[a] - v[b]
    lo, hi = bootstrap_mean_ci(diff, rng(seed, "context table", a, b, column), resamples)
    return {"delta": float(diff.mean()), "ci": [round(lo, 4), round(hi, 4)]}


def _mix_note(mix: dict) -> str:
    cols = [c for c in next(iter(mix.values())) if c != "demonstrations"]
    parts = [f"{split} ({m['demonstrations']} demos): " + ", ".join(f"{c} {m[c]:.0%}" for c in cols)
             for split, m in mix.items()]
    return "Relaxation mix, share of demonstrations relaxing each label group (train vs val vs test): " + \
        "; ".join(parts) + "."


def training_note(artifacts_dir: str | Path, params: Params) -> str:
    """Per training run: epochs run, the best epoch and its validation plan IoU, the train IoU there, and
    both IoUs at every epoch (the learning curves)."""
    parts = []
    for run, seeds in estimator_runs(params.surenav.demos.context, params.surenav.train).items():
        for seed in seeds:
            rows = read_log(context_model_path(artifacts_dir, run, seed).parent / "log.tsv")
            best = max(rows, key=lambda r: r["val_iou"])
            parts.append(f"{run.folder} seed {seed}: {len(rows)} epochs, best {best['epoch']} (val IoU "
                         f"{best['val_iou']:.3f}, train IoU {best['train_iou']:.3f}; per epoch val "
                         + " ".join(f"{r['val_iou']:.2f}" for r in rows) + ", train "
                         + " ".join(f"{r['train_iou']:.2f}" for r in rows) + ")")
    return "Training (graph-level plan IoU on the validation / a fifth of the training demonstrations): " + \
        "; ".join(parts) + "."


def same_seeds(outcomes: list[Outcome], method: str) -> list[Outcome]:
    """``method``'s runs and the main row's runs of the same training seeds: what a paired comparison of a
    variant trained on fewer seeds must use (so seed-to-seed spread does not enter the difference)."""
    seeds = {seed_of(o.method) for o in outcomes if method_of(o.method) == method}
    main = {seed_run(SURENAV, k) for k in seeds}
    return [o for o in outcomes if method_of(o.method) == method or o.method in main]


def versus_main(outcomes: list[Outcome], methods_: list[str], settings) -> str:
    """Each ablation and training variant against the main row of the same seeds, paired over environments:
    ΔIoU and ΔFréchet with their intervals, and which is better (where the interval excludes 0) by how much."""
    parts = []
    for other in methods_:
        if other == SURENAV or not other.startswith(f"{SURENAV}, "):
            continue
        mine = same_seeds(outcomes, other)
        seeds = sorted({seed_of(o.method) for o in mine if method_of(o.method) == other})
        deltas = []
        for column, better in (("relaxation_iou", 1.0), ("frechet", -1.0)):
            d = paired(mine, other, SURENAV, column, settings.seed, settings.bootstrap_samples)
            lo, hi = d["ci"]
            verdict = ("the variant is better" if better * lo > 0 and better * hi > 0 else
                       "the main row is better" if better * lo < 0 and better * hi < 0 else "indistinguishable")
            deltas.append(f"Δ{'IoU' if column == 'relaxation_iou' else 'Fréchet'} {d['delta']:+.3f} {d['ci']} ({verdict})")
        parts.append(f"{other} - {SURENAV} (seed {', '.join(map(str, seeds))}): " + ", ".join(deltas))
    return ("Ablation and variants against the main row (the paper's training), paired over environments and "
            "seed for seed: " + "; ".join(parts) + ".") if parts else ""


def run_note(run: EstimatorRun, main: EstimatorRun, estimator) -> str:
    """What one ablation or variant run changes against the main run, in words."""
    if run.features != main.features:
        return "the other node input (an ablation)"
    if run.gradient != main.gradient:
        extra = "; its loss counts both terms on the plan" if run.gradient == "blackbox" else ""
        return f"the {run.gradient} gradient ({GRADIENT_NOTES[run.gradient].format(e=estimator)}{extra})"
    where = {"path": "the plan's relaxed regions (the false negatives stay on the closed set; surenav.train)",
             "closed": "the search's closed set (the paper's)"}[run.false_positives]
    return f"Eq. 12's false positives counted on {where}"


def table(outcomes: list[Outcome], methods_: list[str], params: Params, index: dict, trained: str = "",
          field: FieldChoice | None = None) -> Table:
    """The report table: rows (``benchmark.table1_rows``), notes with the mix, the field chosen, paired
    deltas and claims (the paper's Table I claims, decided here, and our own checks)."""
    s = params.surenav
    settings = s.benchmark
    rows = table1_rows(outcomes, methods_, settings)
    found = (claims.table1_claims(outcomes, claims.T1, settings.seed)
             + claims.context_checks(outcomes, paired_against(methods_), settings.seed))
    ctx = s.demos.context
    main = main_run(ctx, s.train)
    extras = [(RULE_PSI, FIELD), (EXPERT, FIELD), (SURENAV, ORACLE_PSI)]
    deltas = []
    for a, b in extras:
        if a in methods_ and b in methods_:
            p = paired(outcomes, a, b, "relaxation_iou", settings.seed, settings.bootstrap_samples)
            deltas.append(f"{a} - {b}: ΔIoU {p['delta']:+.3f} {p['ci']}")
    train_tiles, val_tiles = len(index["maps"]["train"]), len(index["maps"]["val"])
    notes = " ".join(part for part in [
        (f"{len({o.environment for o in outcomes})} semi-static environments on {len({o.group for o in outcomes})} "
         "held-out real test tiles, demonstrated by the context demonstrator (navlab.surenav.context: relaxations "
         "decided per region from context, three hidden personas). The paper's claims are decided here; the "
         "per-label demonstrator's Table I is a control (table1_per_label_control: a per-label expert is D* Lite's "
         "own model class, so it cannot test the claim)."),
        (f"Training data: {train_tiles} real 500 m OSM tiles, validation {val_tiles} (cut from the shipped extracts "
         "as the maps step cuts them, disjoint from the test tiles; no procedural maps), "
         f"{s.demos.context.train_pairs_per_map} demonstrations per tile (surenav_context_demos)."),
        _mix_note(index["mix"]),
        (f"{SURENAV}: the GPS estimator of surenav_context_estimator (surenav_estimator's architecture) with node "
         f"input '{ctx.node_features}' (context: Eq. 7 + RWSE + log area, log patch area, by a sidewalk, crossing "
         "point, on the walkway, beside a new obstacle), trained with the paper's loss and gradient: Eq. 12-14 with "
         f"the false positives counted on the search's {main.false_positives} set, through the {main.gradient} "
         f"gradient ({GRADIENT_NOTES[main.gradient].format(e=ctx.estimator)}); the paper gives no schedule, "
         "w_fp / w_fn values (only w_fn > w_fp) or seed count: AdamW, lr, epochs, early stopping on the validation "
         "plan IoU, w_fp = 0.3 / w_fn = 0.7 and the seeds are ours (surenav.train). Each environment's value is the "
         "mean over seeds; *_seed_sd is the spread of the per-seed means. It stays the main row whatever the "
         "variants score. Beside it: " + "; ".join(
             f"{run_name(run, main)}: {run_note(run, main, ctx.estimator)}"
             for run in estimator_runs(ctx, s.train) if run != main) + "."),
        versus_main(outcomes, methods_, settings),
        trained,
        (f"{LABEL_PSI}: Psi = (cost per metre - 1) x sqrt(area) with the per-label demonstrator's personas' mean costs "
         f"(fixed regional costs). {ORACLE_PSI}: 0 on soft regions holding a demonstrated cell, "
         f"{ORACLE_OTHER_M:g} m on other soft ones. {RULE_PSI}: the demonstrator's rules at the personas' mean "
         f"tolerances from the believed map. {FIELD}: grid A* on that per-label cost field."),
        field.note() if field is not None else "",
        dstar_note(settings.dstar_cost_floor) + " The traversal rates here are the context training "
        "demonstrations'; COA*'s class order comes from the same rates.",
        "Paired 95% intervals (percentile bootstrap over environments): " + "; ".join(deltas) + "." if deltas else "",
        f"95% intervals: percentile bootstrap over environments ({settings.bootstrap_samples} resamples).",
    ] if part)
    return Table(claims.T1, "SuReNav Table I (context demonstrator)", TABLE1_COLUMNS, rows,
                 [dict(r) for r in paper.TABLE1], notes, found)


class ContextRun(NamedTuple):
    """Table I on the context environments: the table, the stage's index (tiles per split, relaxation
    mix), and what the leave-one-city-out table pairs with (the outcomes, environments and stored superpixels)."""
    table: Table
    index: dict
    outcomes: list[Outcome]
    environments: list[Environment]
    stored: dict[str, np.ndarray]


def context_table1(params: Params, artifacts_dir: str | Path, progress: bool = True) -> ContextRun:
    """Run every method on the context test environments (``ContextRun``)."""
    envs, stored = stored_environments(artifacts_dir)
    field = best_field(params, artifacts_dir)
    runs, methods_ = methods(params, artifacts_dir, field)
    outcomes = run_all(envs, stored, runs, params, progress)
    index = load_index(artifacts_dir)
    found = table(outcomes, methods_, params, index, training_note(artifacts_dir, params), field)
    return ContextRun(found, index, outcomes, envs, stored)
