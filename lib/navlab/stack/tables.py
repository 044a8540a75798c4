"""The stack's two reports: the ablation table (every row's mean per metric with its 95% interval over the
episodes) and which layer matters for which metric (each ablation row minus the full stack, paired over the
same episodes; "matters" only where the interval excludes zero)."""

from __future__ import annotations

import numpy as np

from navlab.core.params import Params
from navlab.metrics.tables import Table
from navlab.stack.ablation import METRICS, NO_HJ, NO_PACER, NO_SURENAV, ROWS, STACK, Outcome, paired_rows

HIGHER_IS_BETTER = {"success": True, "time_s": False, "contacts": False, "low_tier": True, "frechet": False,
                    "relaxation_iou": True, "spl": True}
LAYER = {NO_PACER: "PACER's terrain costs", NO_SURENAV: "SuReNav's relaxation", NO_HJ: "HJ-search's planner"}

SETUP = (
    "The stack (issue 64; no paper joins these layers, so there is no paper row): the operator's preference "
    "context -> PACER's costmap of the episode's aerial image -> SuReNav's relax-plan-execute on the region graph, "
    "PACER's costs entering the relaxation cost and the grid plan (w = stack.terrain_weight) -> HJ-search's lattice "
    "planner (A*, general TTR toward the route point stack.lookahead_m ahead, the paper's OBS point check of the "
    "window's ground, FI-BRT against the pedestrians, prediction-free) re-planning at stack.replan_hz in a "
    "stack.window_m window around the robot, braking when it has no feasible plan; where the route point lies "
    "in a pedestrian's BRT (within its extent at rest, read from the stored grid), the local goal steps aside "
    "to the nearest point out of it (the grid A* row's out of its discs), so the robot passes a pedestrian "
    "where the ground has room and waits where it has none. Each ablation row replaces one "
    "layer: label costs (each label's terrain at its realistic rank, blind to the operator) for PACER's; D* Lite "
    "on the fitted label costs x the same terrain factor for SuReNav's relaxation; grid A* on the window with the "
    "pedestrians as discs where they stand (an instantaneous point check), driven at full speed without "
    "dynamics, for HJ-search's planner. Episodes: SuReNav's five test tiles (real OSM), one semi-static blockage "
    "on the walkway route, pedestrians walking it head-on at HJ-search's 0.8 m/s, the operator's order "
    "alternating realistic / inverted. Metrics per episode, on the robot's own path: success (goal reached, no "
    "static collision, no pedestrian contact, within stack.timeout_s), time (a failed trip counts its time "
    "at the failure, a timeout the timeout), pedestrian contacts, the share of the path on the operator's "
    "low-cost tier (PACER's metric), Fréchet distance (normalised by the start-goal distance) and relaxation "
    "IoU against SuReNav's context demonstrator walked through the same executor, SPL. 95% bootstrap "
    "intervals over episodes; the layer table pairs each ablation with the full stack episode by episode. "
    "Differences from the issue: the route layer's walk is finished before the robot drives it (the layers hand "
    "over a route, not a shared clock; a dead-end spur the walk took to find the blockage is skipped where "
    "the walk comes back), and the pedestrians do not react to the robot (HJ-search's human model)."
)


def _ci(values) -> list[float]:
    return [round(float(v), 4) for v in values]


def ablation_table(outcomes: list[Outcome], params: Params) -> Table:
    """Table: one row per stack row, each metric's mean over episodes and its interval, and the re-plan
    time's 95th percentile (wall clock, this machine)."""
    rows = []
    for entry in paired_rows(outcomes, seed=params.stack.seed):
        row = {"row": entry["row"], "episodes": entry["episodes"]}
        for metric in METRICS:
            row[metric], row[f"{metric}_ci"] = entry[metric][0], _ci(entry[metric][1:])
        seconds = np.concatenate([o.plan_seconds for o in outcomes if o.row == entry["row"]])
        row["replan_p95_ms"] = float(np.percentile(seconds, 95) * 1e3) if len(seconds) else float("nan")
        rows.append(row)
    columns = ["row", "episodes", *[c for m in METRICS for c in (m, f"{m}_ci")], "replan_p95_ms"]
    return Table("stack_ablation", "navlab stack (issue 64): the stack and its one-layer ablation", columns, rows,
                 [], SETUP)


def layer_effects_table(outcomes: list[Outcome], params: Params) -> Table:
    """Table: per replaced layer and metric, the ablation minus the stack (paired over episodes) and what it
    says: the layer matters (the ablation is worse, the interval clear of zero), the ablation is better, or
    no difference shown."""
    rows = []
    for entry in paired_rows(outcomes, seed=params.stack.seed):
        if entry["row"] == STACK:
            continue
        for metric in METRICS:
            mean, lo, hi = entry[f"{metric}_vs_stack"]
            worse = (hi < 0) if HIGHER_IS_BETTER[metric] else (lo > 0)
            better = (lo > 0) if HIGHER_IS_BETTER[metric] else (hi < 0)
            verdict = ("the layer matters (without it: worse)" if worse else
                       "without it: better" if better else "no difference shown")
            rows.append({"layer": LAYER[entry["row"]], "metric": metric, "ablation_minus_stack": mean,
                         "ablation_minus_stack_ci": _ci([lo, hi]), "verdict": verdict})
    notes = ("Each row: the ablation row minus the full stack on the same episodes (paired), with its 95% "
             "bootstrap interval; a layer matters for a metric when the interval excludes zero on the side where "
             "the ablation is worse. An interval that holds zero is no difference shown, not no difference.")
    return Table("stack_layer_effects", "navlab stack (issue 64): which layer matters for which metric",
                 ["layer", "metric", "ablation_minus_stack", "ablation_minus_stack_ci", "verdict"], rows, [], notes)


def stack_tables(outcomes: list[Outcome], params: Params) -> list[Table]:
    missing = [row for row in ROWS if not any(o.row == row for o in outcomes)]
    if missing:
        raise ValueError(f"no outcome for {', '.join(missing)}: run every row of stack.ablation.ROWS")
    return [ablation_table(outcomes, params), layer_effects_table(outcomes, params)]
