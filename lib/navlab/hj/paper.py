"""HJ-search paper (Hu, Siu & Chen): its printed numbers for Tables I-V and VII, the summaries our tables
use (success with a Wilson interval, means with a bootstrap interval over tasks, on the subset every
method solved and on all of a method's successes) and the checks of its claims.

Numbers the paper's text leaves blank (Table I and III node counts) are ``None`` here, never guessed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from navlab.metrics.intervals import bootstrap_mean_ci, wilson_ci
from navlab.metrics.tables import Claim

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


def summarise(results: dict[str, list], seed: int) -> list[dict]:
    """Rows per method from per-task results (``hj.planning.TaskResult``), all methods over the same
    task list: success count and rate (Wilson), the two ways to fail (no plan within the limits; a plan
    that fails the densified check, with the median depth it reaches into an obstacle), and mean nodes /
    cost (bootstrap) over the tasks every method solved (``*_common``) and over the method's own
    successes (``*_all``)."""
    names = list(results)
    n = len(results[names[0]])
    if any(len(r) != n for r in results.values()):
        raise ValueError("summarise: every method needs the same task list")
    common = [i for i in range(n) if all(results[m][i].success for m in names)]
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


TABLE7_TARGET = 5.0  # issue 11: our look-ups at least 5x cheaper per evaluated state than the paper's


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


def check_claims(table_id: str, rows: list[dict]) -> list[Claim]:
    """The paper's qualitative claims for one table, each holding or not, with our numbers."""
    by = {r.get("method", r.get("component")): r for r in rows}
    out = []

    def claim(text, ok, detail):
        out.append(Claim.of(text, ok, detail))

    if table_id == "table1_heuristics_astar":
        d, t = by["A* w/ Dist"], by["A* w/ TTR"]
        claim("TTR cuts A* expansions", t["nodes"] < d["nodes"], f"{t['nodes']:.0f} vs {d['nodes']:.0f}")
        same = abs(t["cost"] - d["cost"]) < 1e-6
        claim("same optimal cost", same, f"{t['cost']:.2f} vs {d['cost']:.2f}" + ("" if same else
              "; the lattice keeps one node per (x, y, v, θ) cell, the first best one to reach it (Smac-style "
              "duplicate detection), so A* is optimal only over those representatives, and another heuristic "
              "expands in another order and keeps others"))
    elif table_id == "table2_heuristics_anastar":
        d, t = by["ANA* w/ Dist"], by["ANA* w/ TTR"]
        claim("TTR solves at least as many orientation tasks as Dist", t["success"] >= d["success"],
              f"{t['success']}/{t['tasks']} vs {d['success']}/{d['tasks']}; paper 12/12 vs 7/12")
        claim("TTR solves every task", t["success"] == t["tasks"], f"{t['success']}/{t['tasks']}")
    elif table_id == "table3_pruning_astar":
        o, b = by["A* w/ OBS"], by["A* w/ BRT"]
        claim("BRT cuts A* expansions", b["nodes"] < o["nodes"], f"{b['nodes']:.0f} vs {o['nodes']:.0f}")
        claim("BRT keeps success", b["success"] >= o["success"], f"{b['success']} vs {o['success']}")
    elif table_id == "table4_pruning_anastar":
        o, b = by["ANA* w/ OBS"], by["ANA* w/ BRT"]
        claim("BRT raises ANA* success", b["success"] > o["success"],
              f"{b['success']}/{b['tasks']} vs {o['success']}/{o['tasks']}; paper 12/12 vs 8/12"
              + ("; why: OBS already solves every task here, so BRT has nothing left to raise (the paper's OBS "
                 "failures were plans grazing obstacles, Fig. 7; see the failure counts)"
                 if o["success"] == o["tasks"] else ""))
    elif table_id == "table5_static_general":
        best = max(rows, key=lambda r: r["success"])
        claim("TTR + BRT has the highest success", by["TTR + BRT"]["success"] >= best["success"],
              ", ".join(f"{r['method']} {r['success']}/{r['tasks']}" for r in rows))
        claim("BRT raises success under both heuristics",
              by["Dist + BRT"]["success"] >= by["Dist + OBS"]["success"]
              and by["TTR + BRT"]["success"] >= by["TTR + OBS"]["success"], "Dist and TTR rows")
        claim("TTR cuts expansions on the common subset",
              by["TTR + BRT"]["nodes_common"] < by["Dist + BRT"]["nodes_common"],
              f"{by['TTR + BRT']['nodes_common']:.1f} vs {by['Dist + BRT']['nodes_common']:.1f}")
    elif table_id == "table7_compute":
        for name in ("TTR heuristic", "BRT pruner"):
            r = by[name]
            claim(f"our {name} >= {TABLE7_TARGET:g}x cheaper per evaluated state than the paper's",
                  r["cheaper_than_paper_per_state"] >= TABLE7_TARGET,
                  f"{r['in_search_cpu_per_state_ns']:.1f} vs {r['paper_per_state_ns']:.0f} ns: "
                  f"{r['cheaper_than_paper_per_state']:.1f}x")
    else:
        raise ValueError(f"check_claims: no claims for {table_id!r}")
    if table_id != "table7_compute":  # the swept collision check makes a failing plan a bug (planning.Planner.run)
        failing = sum(r["infeasible"] for r in rows)
        claim("no plan fails the dense check", failing == 0,
              ", ".join(f"{r['method']} {r['infeasible']}" for r in rows))
    return out
