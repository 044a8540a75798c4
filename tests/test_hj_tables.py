"""navlab.hj.tables: Tables I, II and VII as the HJ notebooks write them, from constructed results."""

from __future__ import annotations

import math

import pytest

from navlab.hj.paper import PAPER
from navlab.hj.planning import TaskResult
from navlab.hj.tables import PAPER_CALLS, table1, table2, table5, table6, table7
from navlab.metrics.tables import Claim

EXCESS = {"starts": 3, "over": 1, "max_excess_s": 0.25}


def task(clearance, cost, found=True, seconds=0.1):
    return TaskResult("Dist", "OBS", "A*", (0.0, 0.0, 0.0, 0.0), (1.0, 1.0), "found" if found else "time limit",
                      found, clearance, 10, 10, cost, cost, seconds, 1.0)


RESULTS = {"A* w/ Dist": [task(0.1, 5.0), task(-0.2, 6.0), task(-math.inf, math.inf, found=False)],
           "A* w/ TTR": [task(0.1, 5.0, seconds=0.2), task(0.2, 5.5, seconds=0.3), task(0.05, 4.0, seconds=0.4)]}


def test_table1_states_its_claims_failures_and_the_ttr_excess():
    table = table1(RESULTS, EXCESS, seed=0)
    assert (table.table_id, table.paper_ref) == ("table1_heuristics_astar", "HJ-search Table I")
    assert [r["method"] for r in table.rows] == list(RESULTS)
    assert table.rows[1]["time_s"] == pytest.approx(0.9)  # the method's total search seconds
    assert Claim("no plan fails the dense check", "does not hold", "A* w/ Dist 1, A* w/ TTR 0") in table.claims
    assert all(str(c) in table.notes for c in table.claims)
    assert "at these 3 starts: above it at 1, by at most 0.250 s" in table.notes
    assert "1 without a plan, 1 failing the dense check" in table.notes


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
