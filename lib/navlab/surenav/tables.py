"""SuReNav's Table I on the per-label demonstrator as a report table: the control (issue 60).

The per-label demonstrator is itself a per-label cost planner, D* Lite's own model class, so its Table I
cannot test the paper's claim (that learned, context-conditioned costs beat fixed regional ones); the
paper's claims are decided on the context demonstrator (``surenav.context.benchmark``). Here the same
Table I claims are decided as our own checks (``claims.control_claims``), beside the RCR-scoring
ablation's. The notebook only runs the benchmark and hands the outcomes here.
"""

from __future__ import annotations

from navlab.core.params.surenav_benchmark import BenchmarkParams
from navlab.metrics.tables import Table
from navlab.surenav import claims, paper
from navlab.surenav.benchmark import (
    EXPERT,
    NOT_RUN,
    SURENAV,
    SURENAV_MPNN,
    SURENAV_RCR,
    TABLE1_COLUMNS,
    Outcome,
    null_rows,
    replan_note,
    table1_rows,
)
from navlab.surenav.demo_priors import dstar_note

_INTERVALS = ("95% intervals: percentile bootstrap over environments for means ({n} resamples), Wilson for "
              "success rates.")


def _missing(methods) -> str:
    return " ".join(reason for m, reason in NOT_RUN.items() if m not in methods)


def _learned(rows: list[dict], methods) -> str:
    """How the SuReNav rows were made: seeds, the ablations, the planner."""
    if SURENAV not in methods:
        return ""
    seeds = {r["method"]: r["seeds"] for r in rows if r.get("seeds") is not None}
    parts = [(f"{SURENAV}: the GPS estimator of the surenav_estimator stage, {seeds.get(SURENAV)} training seeds; "
              "each environment's value is the mean over seeds, the interval is over environments and *_seed_sd "
              "is the standard deviation of the per-seed means; grid A* in R_free ∪ R_rlx (the paper's mode).")]
    if SURENAV_RCR in methods:
        parts.append(f"{SURENAV_RCR}: the same planner with Psi = surenav.planner.rcr_scale_m x RCR's score "
                     "(label risk + goal-distance ratio) in place of the learned estimator (no training, one run).")
    if SURENAV_MPNN in methods:
        parts.append(f"{SURENAV_MPNN}: the estimator without global attention (GatedGCN layers only), "
                     f"{seeds.get(SURENAV_MPNN)} training seed(s).")
    return " ".join(parts)


def table1(outcomes: list[Outcome], methods, settings: BenchmarkParams) -> Table:
    """Table I on the per-label demonstrator (the control): normalised Fréchet distance and relaxation IoU
    against its semi-static test demonstrations."""
    rows = table1_rows(outcomes, methods, settings)
    if SURENAV not in methods:
        rows += null_rows(SURENAV, [{}], [c for c in TABLE1_COLUMNS if c != "method"])
    decided = [*claims.control_claims(outcomes, settings.seed), *claims.rcr_scoring_checks(outcomes, settings.seed)]
    groups = len({o.group for o in outcomes})
    notes = " ".join(part for part in [
        ("A control: a per-label expert is D* Lite's own model class, so it cannot test the claim; the paper's "
         "claims are decided on the context demonstrator (table1_human_likeness), these as our own checks."),
        (f"{len({o.environment for o in outcomes})} semi-static test environments on {groups} held-out real tiles "
         "with synthetic-expert demonstrations (the paper: 100 from 5 cities, human demonstrations)."),
        "Fréchet: discrete, normalised by the start-goal distance, over every episode's executed trajectory.",
        ("Relaxation IoU on superpixels of the demonstration's own region graph (one fixed partition for every "
         "method; cell sets of one-cell-wide paths barely overlap)."),
        f"{EXPERT}: the synthetic expert's planner run through the same executor (a ceiling, not a baseline).",
        dstar_note(settings.dstar_cost_floor), _learned(rows, methods), _missing(methods), _INTERVALS.format(n=settings.bootstrap_samples),
        replan_note(outcomes, methods),
    ] if part)
    return Table(claims.CONTROL, "SuReNav Table I on the per-label demonstrator (control)", TABLE1_COLUMNS, rows,
                 [dict(r) for r in paper.TABLE1], notes, decided)
