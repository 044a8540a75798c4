"""navlab.hj.tables: the HJ tables as the notebooks write them, from constructed results: the rows, the notes
(set-up and differences, never the claims again) and the claims handed to ``hj.claims``."""

from __future__ import annotations

import math

import numpy as np
import pytest

from navlab.hj.claims import CLAIMS
from navlab.hj.paper import PAPER
from navlab.hj.planning import TaskResult
from navlab.hj.receding_horizon import Run, Trip
from navlab.hj.state_lattice_runs import (
    DIJKSTRA,
    DIST,
    METHODS,
    TTR,
    LatticeRun,
    StateLatticeRuns,
    settings_of,
)
from navlab.hj.tables import PAPER_CALLS, table1, table2, table5, table6, table7, table8, table9

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


def _keys(table_id):
    return {k for k, c in CLAIMS.items() if c.report == table_id}


def _no_claims_in_notes(table):
    assert "Claims:" not in table.notes and not any(c.ours and c.ours in table.notes for c in table.claims)


def test_table1_states_its_claims_failures_and_the_ttr_excess(smoke_params):
    table = table1(RESULTS, EXCESS, seed=0, lattice=lattice_runs(smoke_params))
    assert (table.table_id, table.paper_ref) == ("table1_heuristics_astar", "HJ-search Table I")
    assert [r["method"] for r in table.rows] == [*RESULTS, *METHODS]
    assert table.rows[1]["time_s"] == pytest.approx(0.9)  # the method's total search seconds
    assert {c.key for c in table.claims if c.source == "paper"} == _keys("table1_heuristics_astar")
    assert not [c for c in table.claims if c.source == "ours"]  # the paper's pruners: a grazing plan is a failure
    _no_claims_in_notes(table)
    assert "at these 3 starts: above it at 1, by at most 0.250 s" in table.notes
    assert "1 without a plan, 1 failing the dense check" in table.notes
    assert "OBS is the paper's conventional instantaneous check" in table.notes
    assert "cell 0.1 m, 16 grid-aligned headings" in table.notes and "1952 motion primitives" in table.notes
    (expansions,) = [c for c in table.claims if c.key == "t1_fewer_nodes"]
    assert expansions.verdict == "inconclusive"  # one task both solved: far too few
    assert "state lattice: A* w/ TTR 800 vs A* w/ Dist 2000 vs Dijkstra 9000 mean expansions" in expansions.ours


def test_table1_same_cost_holds_when_both_astar_return_dijkstras_cost_on_every_task(smoke_params):
    lattice = lattice_runs(smoke_params, dist_costs=(4.0, 5.0 + 1e-12, 6.0))
    (same,) = [c for c in table1(RESULTS, EXCESS, seed=0, lattice=lattice).claims if c.key == "t1_same_cost"]
    assert same.verdict == "holds" and not same.why
    assert "Dijkstra's costs 4.000, 5.000, 6.000 s" in same.ours and "3/3 tasks" in same.ours
    assert "continuous lattice: A* w/ TTR 5.000 vs A* w/ Dist 5.000 s mean over the tasks both solved, the same" \
        in same.ours


def test_table1_same_cost_does_not_hold_when_one_task_differs(smoke_params):
    for lattice in (lattice_runs(smoke_params, ttr_costs=(4.0, 5.0 + 1e-6, 6.0)),
                    lattice_runs(smoke_params, dist_costs=(4.0, 5.0, math.inf))):
        table = table1(RESULTS, EXCESS, seed=0, lattice=lattice)
        (same,) = [c for c in table.claims if c.key == "t1_same_cost"]
        assert same.verdict == "does not hold" and "2/3 tasks" in same.ours and "not admissible" in same.why


def test_table1_tasks_on_the_state_lattice(smoke_params, tmp_path):
    """Table I's smoke task set: every method plans, and both A* return Dijkstra's cost on every task."""
    from navlab.hj.grids import build_hj_grids
    from navlab.hj.state_lattice_runs import run_table, same_cost

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
    assert {c.key for c in table.claims if c.source == "paper"} == _keys("table2_heuristics_anastar")
    _no_claims_in_notes(table)


def test_table7_scales_the_papers_totals_to_our_call_count():
    paper = PAPER["table7_compute"]
    rows = [{"component": r["component"], "states": r["states"], "total_s": r["total_s"] / 4,
             "in_search_cpu_per_state_ns": 70.0, "paper_per_state_ns": 500.0, "cheaper_than_paper_per_state": 7.1}
            for r in paper]
    table = table7(rows, 2500, ((81, 81, 11, 36), (97, 55, 11, 36)))
    for ours, theirs in zip(table.paper_rows, paper, strict=True):
        assert ours["total_s"] == pytest.approx(theirs["total_s"] * 2500 / PAPER_CALLS)
        assert ours["per_state_ns"] == pytest.approx(theirs["total_s"] / PAPER_CALLS / theirs["states"] * 1e9)
    assert "TTR (81, 81, 11, 36), BRT (97, 55, 11, 36)" in table.notes
    assert {c.key for c in table.claims if c.source == "paper"} == _keys("table7_compute")
    assert len([c for c in table.claims if c.source == "ours"]) == 2
    _no_claims_in_notes(table)


def test_table5_reads_its_pairs_and_budget_from_the_planner_params(smoke_params):
    results = {m: RESULTS["A* w/ TTR"] for m in ("Dist + OBS", "Dist + BRT", "TTR + OBS", "TTR + BRT")}
    table = table5(results, 0.0123, seed=0, planner=smoke_params.hj.planner)
    t5 = smoke_params.hj.planner.table5
    assert table.table_id == "table5_static_general" and [r["method"] for r in table.rows] == list(results)
    assert table.notes.startswith(f"{t5.pairs} pairs drawn with seed hj.seed") and "BRT margin 0.0123" in table.notes
    assert {c.key for c in table.claims if c.source == "paper"} == _keys("table5_static_general")
    _no_claims_in_notes(table)


SPEED = {"simulated_s": 300.0, "wall_s": 100.0, "cpu_s": 90.0, "plan_median_ms": 17.9}


def patrol(ok: list[bool], dynamic=None) -> Run:
    """A run of one trip per outcome, 10 s each; with ``dynamic``, driven straight along Table VI's head-on line."""
    run = Run(trips=[Trip((0.0, 0.0), (1.0, 0.0), "success" if o else "deadlock", 10.0) for o in ok])
    if dynamic is not None:
        f = dynamic.table6.face_to_face
        for k, x in enumerate(np.linspace(f.robot_start[:2], f.robot_goal, 5)):
            run.trajectory.append(np.array([float(k), *x, 0.5, 0.0]))
            run.humans.append(np.array([f.robot_goal]))
    return run


@pytest.mark.parametrize("table_id", ["table6_dynamic", "table8_rooms", "table9_humans"])
def test_closed_loop_tables_decide_their_claims_on_the_runs_and_keep_the_committed_columns(table_id, smoke_params):
    """Each closed-loop table lays out the rows it is given (the committed report's, here), keeps the notes to the
    set-up, and decides its registry's claims on the runs (constructed here) keyed as ``run_cells`` keys them."""
    import json
    from pathlib import Path

    d = smoke_params.hj.dynamic
    report = json.loads(Path("reports/hj", f"{table_id}.json").read_text())
    if table_id == "table6_dynamic":
        runs = {(m, s): [patrol([True], d) for _ in range(5)] for m in ("FI-BRT", "FS-BRT", "OBS")
                for s in ("Face-to-Face", "Zig-Zag")}
        table = table6(report["rows"], runs, d, "RULES.", SPEED)
        assert "RULES." in table.notes and "300 s simulated in 100 s wall" in table.notes
        assert "(3.0x real time" in table.notes
    elif table_id == "table8_rooms":
        runs = {(f"{h} + {p}", room): [patrol([True] * 6)] for h in ("Dist", "TTR") for p in ("OBS", "BRT")
                for room in ("long_hallway", "dense_room")}
        table = table8(report["rows"], runs, d, "RULES.", SPEED, 12.3)
        assert "Dense Room re-plan median 12.3 ms" in table.notes
    else:
        runs = {(m, n): [patrol([True] * 9) for _ in range(2)] for m in ("FI-BRT", "FS-BRT", "OBS") for n in (1, 2)}
        table = table9(report["rows"], runs, d, "RULES.", SPEED)
    assert table.columns == report["columns"] and table.rows == report["rows"]
    assert {c.key for c in table.claims} == _keys(table_id) and all(c.source == "paper" for c in table.claims)
    _no_claims_in_notes(table)
