"""navlab.hj.tables: Tables I, II and VII as the HJ notebooks write them, from constructed results."""

from __future__ import annotations

import math

import pytest

from navlab.hj.paper import PAPER
from navlab.hj.planning import TaskResult
from navlab.hj.state_lattice_runs import (
    DIJKSTRA,
    DIST,
    METHODS,
    TTR,
    LatticeRun,
    StateLatticeRuns,
    settings_of,
)
from navlab.hj.tables import PAPER_CALLS, table1, table2, table5, table6, table7
from navlab.metrics.tables import Claim

EXCESS = {"starts": 3, "over": 1, "max_excess_s": 0.25}


def task(clearance, cost, found=True, seconds=0.1):
    return TaskResult("Dist", "OBS", "A*", (0.0, 0.0, 0.0, 0.0), (1.0, 1.0), "found" if found else "time limit",
                      found, clearance, 10, 10, cost, cost, seconds, 1.0)


RESULTS = {"A* w/ Dist": [task(0.1, 5.0), task(-0.2, 6.0), task(-math.inf, math.inf, found=False)],
           "A* w/ TTR": [task(0.1, 5.0, seconds=0.2), task(0.2, 5.5, seconds=0.3), task(0.05, 4.0, seconds=0.4)]}


def lattice_run(cost, expansions, found=True):
    return LatticeRun((1.0, 1.0, 0.0, 0.0), 0.0, (4.0, 1.0), found, cost if found else math.inf, expansions, 0.01,
                      0.0, 0.0)


def lattice_runs(smoke_params, dist_costs=(4.0, 5.0, 6.0), ttr_costs=(4.0, 5.0, 6.0)) -> StateLatticeRuns:
    """Synthetic state-lattice runs of three tasks: Dijkstra's costs 4, 5, 6 s; A*'s as given (inf: no plan)."""
    results = {DIJKSTRA: [lattice_run(c, 9000) for c in (4.0, 5.0, 6.0)],
               DIST: [lattice_run(c, 2000, math.isfinite(c)) for c in dist_costs],
               TTR: [lattice_run(c, 800, math.isfinite(c)) for c in ttr_costs]}
    return StateLatticeRuns(settings_of(smoke_params), 1952, results)


def test_table1_states_its_claims_failures_and_the_ttr_excess(smoke_params):
    table = table1(RESULTS, EXCESS, seed=0, lattice=lattice_runs(smoke_params))
    assert (table.table_id, table.paper_ref) == ("table1_heuristics_astar", "HJ-search Table I")
    assert [r["method"] for r in table.rows] == [*RESULTS, *METHODS]
    assert table.rows[1]["time_s"] == pytest.approx(0.9)  # the method's total search seconds
    assert Claim("no plan fails the dense check", "does not hold", "A* w/ Dist 1, A* w/ TTR 0") in table.claims
    assert all(str(c) in table.notes for c in table.claims)
    assert "at these 3 starts: above it at 1, by at most 0.250 s" in table.notes
    assert "1 without a plan, 1 failing the dense check" in table.notes
    assert "cell 0.1 m, 16 grid-aligned headings" in table.notes and "1952 motion primitives" in table.notes
    expansions = table.claims[0]
    assert expansions.claim == "TTR cuts A* expansions" and expansions.verdict == "does not hold"  # continuous rows
    assert "state lattice: A* w/ TTR 800 vs A* w/ Dist 2000 vs Dijkstra 9000 mean expansions" in expansions.ours


def test_table1_same_cost_holds_when_both_astar_return_dijkstras_cost_on_every_task(smoke_params):
    # the continuous rows differ (5.00 vs 4.83 mean): the claim is decided on the state lattice alone
    lattice = lattice_runs(smoke_params, dist_costs=(4.0, 5.0 + 1e-12, 6.0))
    (same,) = [c for c in table1(RESULTS, EXCESS, seed=0, lattice=lattice).claims if c.claim == "same optimal cost"]
    assert same.verdict == "holds" and not same.why
    assert "on 3/3 and 3/3 tasks; Dijkstra's costs 4.000, 5.000, 6.000 s, mean 5.000 s" in same.ours
    assert "continuous lattice: A* w/ TTR 4.833 vs A* w/ Dist 5.000 s mean; they differ" in same.ours
    assert "duplicate detection" in same.ours


def test_table1_same_cost_does_not_hold_when_one_task_differs(smoke_params):
    for lattice in (lattice_runs(smoke_params, ttr_costs=(4.0, 5.0 + 1e-6, 6.0)),
                    lattice_runs(smoke_params, dist_costs=(4.0, 5.0, math.inf))):
        table = table1(RESULTS, EXCESS, seed=0, lattice=lattice)
        (same,) = [c for c in table.claims if c.claim == "same optimal cost"]
        assert same.verdict == "does not hold" and "differs from Dijkstra on 1 of 3 task(s)" in same.why
        assert str(same) in table.notes


def test_table1_tasks_on_the_state_lattice(smoke_params, tmp_path):
    """Table I's smoke task set: every method plans, and both A* return Dijkstra's cost on every task."""
    from navlab.hj.state_lattice_runs import run_table, same_cost
    from navlab.reach.precompute import build_hj_grids

    build_hj_grids(smoke_params, "unused", tmp_path, progress=False, log=lambda m: None)
    runs = run_table(smoke_params, tmp_path, smoke_params.hj.planner.table1)
    tasks = len(smoke_params.hj.planner.table1.headings_deg)
    assert list(runs.results) == list(METHODS) and all(len(r) == tasks for r in runs.results.values())
    assert all(r.found for rs in runs.results.values() for r in rs)
    for method in (DIST, TTR):
        assert all(same_cost(d, r) for d, r in zip(runs.results[DIJKSTRA], runs.results[method], strict=True))
        assert sum(r.expansions for r in runs.results[method]) < sum(r.expansions for r in runs.results[DIJKSTRA])


def test_table2_names_the_anytime_budget_in_expansions():
    results = {k.replace("A*", "ANA*"): v for k, v in RESULTS.items()}
    table = table2(results, EXCESS, seed=0, max_expansions=6000)
    assert table.table_id == "table2_heuristics_anastar" and table.paper_rows == PAPER["table2_heuristics_anastar"]
    assert "6,000" in table.notes or "6000" in table.notes
    assert all(str(c) in table.notes for c in table.claims)


def test_table7_scales_the_papers_totals_to_our_call_count():
    paper = PAPER["table7_compute"]
    rows = [{"component": r["component"], "states": r["states"], "in_search_cpu_per_state_ns": 70.0,
             "paper_per_state_ns": 500.0, "cheaper_than_paper_per_state": 7.1} for r in paper]
    table = table7(rows, 2500, ((81, 81, 11, 36), (97, 55, 11, 36)))
    for ours, theirs in zip(table.paper_rows, paper, strict=True):
        assert ours["total_s"] == pytest.approx(theirs["total_s"] * 2500 / PAPER_CALLS)
        assert ours["per_state_ns"] == pytest.approx(theirs["total_s"] / PAPER_CALLS / theirs["states"] * 1e9)
    assert "TTR (81, 81, 11, 36), BRT (97, 55, 11, 36)" in table.notes
    assert all(str(c) in table.notes for c in table.claims) and len(table.claims) >= 2


def test_table5_reads_its_pairs_and_budget_from_the_planner_params(smoke_params):
    results = {m: RESULTS["A* w/ TTR"] for m in ("Dist + OBS", "Dist + BRT", "TTR + OBS", "TTR + BRT")}
    table = table5(results, 0.0123, seed=0, planner=smoke_params.hj.planner)
    t5 = smoke_params.hj.planner.table5
    assert table.table_id == "table5_static_general" and [r["method"] for r in table.rows] == list(results)
    assert table.notes.startswith(f"{t5.pairs} pairs drawn with seed hj.seed") and "BRT margin 0.0123" in table.notes
    assert all(str(c) in table.notes for c in table.claims)


def closed_loop_row(method, scenario, success, collisions, time_s, time_all_s):
    return {"method": method, "scenario": scenario, "success": success, "runs": 5, "collisions": collisions,
            "contacts_on_plan": collisions, "time_s": time_s, "time_all_s": time_all_s, "detour_m": 2.0}


def test_table6_decides_the_head_on_claim_and_quotes_the_speed(smoke_params):
    rows = [closed_loop_row("FI-BRT", "Face-to-Face", 5, 0, 30.0, 30.0),
            closed_loop_row("FS-BRT", "Face-to-Face", 2, 3, 28.0, 28.0),
            closed_loop_row("OBS", "Face-to-Face", 0, 5, None, 25.0),
            closed_loop_row("FI-BRT", "Zig-Zag", 5, 0, 40.0, 40.0),
            closed_loop_row("FS-BRT", "Zig-Zag", 5, 0, 31.0, 31.0),
            closed_loop_row("OBS", "Zig-Zag", 3, 2, 29.0, 29.0)]
    speed = {"simulated_s": 300.0, "wall_s": 100.0, "cpu_s": 90.0, "plan_median_ms": 17.9}
    table = table6(rows, smoke_params.hj.dynamic, "RULES.", speed)
    assert table.claims[0].claim == "FI-BRT avoids the head-on collisions that FS-BRT and OBS do not (Face-to-Face)"
    assert all(c.verdict == "holds" for c in table.claims), table.claims
    assert "RULES." in table.notes and "300 s simulated in 100 s wall" in table.notes and "(3.0x real time" in table.notes
    assert all(str(c) in table.notes for c in table.claims)


@pytest.mark.parametrize("table_id", ["table6_dynamic", "table8_rooms", "table9_humans"])
def test_the_committed_closed_loop_reports_state_the_claims_their_rows_decide(table_id, smoke_params):
    """The verdicts in each committed closed-loop report are the ones ``hj.tables`` decides from its rows."""
    import json
    from pathlib import Path

    from navlab.hj import tables

    report = json.loads(Path("reports/hj", f"{table_id}.json").read_text())
    speed = {"simulated_s": 1.0, "wall_s": 1.0, "cpu_s": 1.0, "plan_median_ms": 1.0}
    build = {"table6_dynamic": lambda rows: tables.table6(rows, smoke_params.hj.dynamic, "", speed),
             "table8_rooms": lambda rows: tables.table8(rows, smoke_params.hj.dynamic, "", speed, 1.0),
             "table9_humans": lambda rows: tables.table9(rows, smoke_params.hj.dynamic, "", speed)}[table_id]
    table = build(report["rows"])
    assert table.claims and all(str(c) in report["notes"] for c in table.claims)
    assert table.columns == report["columns"]
