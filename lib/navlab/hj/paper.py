"""HJ-search paper (Hu, Siu & Chen): its printed numbers for Tables I-V, VII and Fig. 2, and the summaries
our tables use (success with a Wilson interval, means with a bootstrap interval over tasks, on the subset
every method solved and on all of a method's successes). Its claims and their verdicts: ``hj.claims``.

Numbers the paper's text leaves blank (Table I and III node counts) are ``None`` here, never guessed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from navlab.metrics.intervals import bootstrap_mean_ci, wilson_ci

PAPER = {
    "table1_heuristics_astar": [
        {"method": "A* w/ Dist", "success": 4, "tasks": 4, "nodes": None, "time_s": 414.16, "cost": 5.25},
        {"method": "A* w/ TTR", "success": 4, "tasks": 4, "nodes": None, "time_s": 20.97, "cost": 5.25},
    ],
    "table2_heuristics_anastar": [
        {"method": "ANA* w/ Dist", "success": 7, "tasks": 12, "nodes_common": 257.0, "cost_common": 8.06,
         "nodes_all": None, "cost_all": None},
        {"method": "ANA* w/ TTR", "success": 12, "tasks": 12, "nodes_common": 258.6, "cost_common": 8.20,
         "nodes_all": 273.4, "cost_all": 8.61},
    ],
    "table3_pruning_astar": [
        {"method": "A* w/ OBS", "success": 4, "tasks": 4, "nodes": None, "time_s": 303.32, "cost": 89.5},
        {"method": "A* w/ BRT", "success": 4, "tasks": 4, "nodes": None, "time_s": 335.84, "cost": 89.5},
    ],
    "table4_pruning_anastar": [
        {"method": "ANA* w/ OBS", "success": 8, "tasks": 12, "nodes_common": 401.4, "cost_common": 404.57,
         "nodes_all": None, "cost_all": None},
        {"method": "ANA* w/ BRT", "success": 12, "tasks": 12, "nodes_common": 373.1, "cost_common": 408.79,
         "nodes_all": 326.8, "cost_all": 371.43},
    ],
    "table5_static_general": [
        {"method": "Dist + OBS", "success": 81, "tasks": 100, "nodes_common": 311.1, "cost_common": 191.44},
        {"method": "Dist + BRT", "success": 85, "tasks": 100, "nodes_common": 299.9, "cost_common": 188.98},
        {"method": "TTR + OBS", "success": 83, "tasks": 100, "nodes_common": 235.4, "cost_common": 146.58},
        {"method": "TTR + BRT", "success": 97, "tasks": 100, "nodes_common": 229.3, "cost_common": 146.37,
         "nodes_all": 287.2, "cost_all": 180.47},
    ],
    # Table VII: 10,000 calls, total seconds, at (states, dims) = (35, 4) TTR, (35, 2) Dist, (140, 4) BRT, (140, 2) OBS
    "table7_compute": [
        {"component": "TTR heuristic", "states": 35, "total_s": 0.187},
        {"component": "Dist heuristic", "states": 35, "total_s": 0.053},
        {"component": "BRT pruner", "states": 140, "total_s": 0.247},
        {"component": "OBS pruner", "states": 140, "total_s": 0.076},
    ],
    # Sec. VI-A: Fig. 2's four heuristics (s) at its robot, heading upward, then reversed (its two rows)
    "fig2_heuristic_values": [
        {"map_ttr_s": 7.57, "general_ttr_s": 5.81, "map_dist_s": 5.09, "general_dist_s": 4.20},
        {"map_ttr_s": 9.06, "general_ttr_s": 7.89, "map_dist_s": 5.09, "general_dist_s": 4.20},
    ],
}
# Table I's reduction is stated only as a ratio of times; Table III's node reduction as 15.1 %.
TABLE3_NODE_REDUCTION = 0.151


def wilson(successes: int, n: int) -> tuple[float, float]:
    """95 % Wilson interval of a success rate (``metrics.intervals``); undefined (NaN) without tasks."""
    return wilson_ci(successes, n) if n > 0 else (math.nan, math.nan)


def bootstrap_mean(values: Sequence[float], seed: int) -> tuple[float, tuple[float, float]]:
    """Mean and 95 % percentile-bootstrap interval over tasks (``metrics.intervals``); NaN when empty."""
    x = np.asarray(values, dtype=np.float64)
    if x.size == 0:
        return math.nan, (math.nan, math.nan)
    return float(x.mean()), bootstrap_mean_ci(x, np.random.default_rng(seed))


def _ci(ci) -> list | None:
    """An interval for the report (None when undefined: no sample)."""
    return None if any(not math.isfinite(c) for c in ci) else [round(float(c), 6) for c in ci]


def is_ours(method: str) -> bool:
    """A variant row of ours beside the paper's ("TTR + swept OBS (ours)", "FI-BRT (1.5 s prediction, ours)")."""
    return method.endswith("ours)")


def summarise(results: dict[str, list], seed: int) -> list[dict]:
    """Rows per method from per-task results (``hj.planning.TaskResult``), all methods over the same
    task list: success count and rate (Wilson), the two ways to fail (no plan within the limits; a plan
    that fails the densified check, with the median depth it reaches into an obstacle), and mean nodes /
    cost (bootstrap) over the tasks every one of the paper's methods solved (``*_common``; our variant rows,
    labelled "ours", do not narrow it) and over the method's own successes (``*_all``)."""
    names = list(results)
    n = len(results[names[0]])
    if any(len(r) != n for r in results.values()):
        raise ValueError("summarise: every method needs the same task list")
    papers = [m for m in names if not is_ours(m)] or names
    common = [i for i in range(n) if all(results[m][i].success for m in papers)]
    rows = []
    for m in names:
        res = results[m]
        ok = [i for i in range(n) if res[i].success]
        infeasible = [-res[i].clearance for i in range(n) if res[i].found and not res[i].feasible]
        row = {"method": m, "success": len(ok), "tasks": n, "success_rate": len(ok) / n,
               "success_rate_ci": _ci(wilson(len(ok), n)), "common_tasks": len(common),
               "no_plan": sum(not r.found for r in res), "infeasible": len(infeasible),
               "infeasible_depth_m": float(np.median(infeasible)) if infeasible else None}
        for label, idx in (("common", common), ("all", ok)):
            for col, attr in (("nodes", "expansions"), ("cost", "cost")):
                mean, ci = bootstrap_mean([getattr(res[i], attr) for i in idx], seed)
                row[f"{col}_{label}"], row[f"{col}_{label}_ci"] = mean, _ci(ci)
        rows.append(row)
    return rows


FAILURE_COLUMNS = ["no_plan", "infeasible", "infeasible_depth_m"]
ASTAR_COLUMNS = ["method", "success", "tasks", "success_rate", "success_rate_ci", *FAILURE_COLUMNS, "nodes",
                 "nodes_ci", "time_s", "cost", "cost_ci"]
ANA_COLUMNS = ["method", "success", "tasks", "success_rate", "success_rate_ci", *FAILURE_COLUMNS, "common_tasks",
               "nodes_common", "nodes_common_ci", "cost_common", "cost_common_ci", "nodes_all", "nodes_all_ci",
               "cost_all", "cost_all_ci", "time_s"]


def astar_rows(rows: list[dict]) -> list[dict]:
    """``summarise`` rows as A* table rows (Tables I, III): every task's own nodes and cost."""
    rename = {"nodes": "nodes_all", "nodes_ci": "nodes_all_ci", "cost": "cost_all", "cost_ci": "cost_all_ci"}
    return [{c: r.get(rename.get(c, c)) for c in ASTAR_COLUMNS} for r in rows]


def ana_rows(rows: list[dict]) -> list[dict]:
    """``summarise`` rows as ANA* table rows (Tables II, IV, V): common subset and all successes."""
    return [{c: r.get(c) for c in ANA_COLUMNS} for r in rows]


def anytime_budget(results: dict[str, list], max_expansions: int) -> str:
    """One sentence: ANA*'s budget in expansions (what the tables run on, the same on every machine) and in
    milliseconds on this machine, from the expansions per wall second its searches in ``results`` ran at
    (issue 26 item 5; the paper states only a time budget)."""
    runs = [r for rs in results.values() for r in rs]
    seconds = sum(r.seconds for r in runs)
    rate = sum(r.total_expansions for r in runs) / seconds if seconds > 0 else math.nan
    return (f"ANA* budget: at most {max_expansions:,} expansions per search, no time limit (machine-independent); "
            f"its searches here ran {rate:,.0f} expansions per wall second, so the cap is about "
            f"{1000 * max_expansions / rate:,.0f} ms on this machine.")


def failure_modes(rows: list[dict]) -> str:
    """One sentence per table: how each method's failures split (no plan / plan failing the dense check)."""
    parts = []
    for r in rows:
        depth = f", median {1000 * r['infeasible_depth_m']:.1f} mm deep" if r["infeasible"] else ""
        parts.append(f"{r['method']} {r['no_plan']} without a plan, {r['infeasible']} failing the dense check{depth}")
    return "Failures: " + "; ".join(parts) + "."


def compare_table7(rows: list[dict]) -> list[dict]:
    """Our Table VII rows (``hj.timing.table7_timings``) with the paper's ns per state beside them and
    how many times cheaper ours is per evaluated state, in CPU time inside the compiled loop."""
    paper = {r["component"]: r for r in PAPER["table7_compute"]}
    out = []
    for r in rows:
        p = paper[r["component"]]
        per_state = p["total_s"] / 10000 / p["states"] * 1e9
        out.append({**r, "paper_per_state_ns": per_state,
                    "cheaper_than_paper_per_state": per_state / r["in_search_cpu_per_state_ns"]})
    return out
