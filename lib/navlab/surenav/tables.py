"""Table I and Fig. 4 of SuReNav as report tables: our rows, the paper's, the notes and the claims.

The notebooks only run the benchmark and hand the outcomes here; what is printed beside what and which
methods are null and why are decided in this module. The claims (the paper's, from the registry, and our
own checks) are decided on the same per-episode outcomes by ``navlab.surenav.claims``; the notes carry
the set-up and the differences from the paper only.
"""

from __future__ import annotations

from navlab.core.params.surenav_benchmark import BenchmarkParams
from navlab.metrics.tables import Table
from navlab.surenav import claims, paper
from navlab.surenav.benchmark import (
    EXPERT,
    FIG4_COLUMNS,
    NOT_RUN,
    SURENAV,
    SURENAV_MPNN,
    SURENAV_RCR,
    TABLE1_COLUMNS,
    Outcome,
    fig4_rows,
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
    """Table I: normalised Fréchet distance and relaxation IoU against the semi-static test demonstrations."""
    rows = table1_rows(outcomes, methods, settings)
    if SURENAV not in methods:
        rows += null_rows(SURENAV, [{}], [c for c in TABLE1_COLUMNS if c != "method"])
    decided = [*claims.table1_claims(outcomes, claims.T1, settings.seed),
               *claims.rcr_scoring_checks(outcomes, settings.seed)]
    groups = len({o.group for o in outcomes})
    notes = " ".join(part for part in [
        (f"{len({o.environment for o in outcomes})} semi-static test environments on {groups} held-out real tiles "
         "with synthetic-expert demonstrations (the paper: 100 from 5 cities, human demonstrations)."),
        "Fréchet: discrete, normalised by the start-goal distance, over every episode's executed trajectory.",
        ("Relaxation IoU on superpixels of the demonstration's own region graph (one fixed partition for every "
         "method; cell sets of one-cell-wide paths barely overlap)."),
        f"{EXPERT}: the synthetic expert's planner run through the same executor (a ceiling, not a baseline).",
        dstar_note(settings.dstar_cost_floor), _learned(rows, methods), _missing(methods), _INTERVALS.format(n=settings.bootstrap_samples),
        replan_note(outcomes, methods),
    ] if part)
    return Table(claims.T1, "SuReNav Table I", TABLE1_COLUMNS, rows, [dict(r) for r in paper.TABLE1], notes, decided)


def fig4(outcomes: list[Outcome], methods, settings: BenchmarkParams) -> Table:
    """Fig. 4: SR, SPL and total risk per method and city on the safety-efficiency episodes."""
    rows = fig4_rows(outcomes, methods, settings)
    cities = list(dict.fromkeys(o.group for o in outcomes))
    if SURENAV not in methods:
        rows += null_rows(SURENAV, [{"city": c} for c in cities], [c for c in FIG4_COLUMNS if c not in ("method", "city")])
    notes = " ".join(part for part in [
        (f"{len({o.environment for o in outcomes})} episodes on {len(cities)} held-out real tiles standing in for "
         "Milan, Baltimore and Capitol Hill (see data/surenav/maps/index.json roles); perturbations along OSRM "
         "routes aggregated per map; each method plans on the original map and walks the modified one "
         f"(sensor {settings.executor.sensor_radius_m:g} m, step {settings.executor.step_m:g} m)."),
        ("The paper prints Fig. 4 as a scatter: its SPL and risk values are not numbers we can copy, only the "
         "SR stated in the text. Total risk integrates our fixed per-label unit risks (params.yaml "
         "surenav.benchmark.unit_risk) along the path; the paper's are mean 0-1 scores of three language models."),
        f"{EXPERT}: the synthetic expert's planner through the same executor (a reference, not a baseline).",
        dstar_note(settings.dstar_cost_floor), _learned(rows, methods),
        "SR intervals: Wilson for a single run, bootstrap over episodes of the seed-averaged success for a "
        "method run on several training seeds." if SURENAV in methods else "",
        _missing(methods), _INTERVALS.format(n=settings.bootstrap_samples), replan_note(outcomes, methods),
    ] if part)
    return Table(claims.FIG4, "SuReNav Fig. 4", FIG4_COLUMNS, rows, [dict(r) for r in paper.FIG4_SR], notes,
                 claims.fig4_claims(outcomes, settings.seed))

