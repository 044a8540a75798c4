"""navlab.hj.tables: Tables I, II and VII as the HJ notebooks write them, from constructed results."""

from __future__ import annotations

import math

import pytest

from navlab.hj.tables import PAPER_CALLS, table1, table2, table7
from navlab.metrics.hj_paper import PAPER
from navlab.reach.planning import TaskResult

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
    assert "no plan fails the dense check: DOES NOT HOLD (A* w/ Dist 1, A* w/ TTR 0)" in table.claims
    assert all(c in table.notes for c in table.claims)
    assert "at these 3 starts: above it at 1, by at most 0.250 s" in table.notes
    assert "1 without a plan, 1 failing the dense check" in table.notes


def test_table2_names_the_anytime_budget_in_expansions():
    results = {k.replace("A*", "ANA*"): v for k, v in RESULTS.items()}
    table = table2(results, EXCESS, seed=0, max_expansions=6000)
    assert table.table_id == "table2_heuristics_anastar" and table.paper_rows == PAPER["table2_heuristics_anastar"]
    assert "6,000" in table.notes or "6000" in table.notes
    assert all(c in table.notes for c in table.claims)


def test_table7_scales_the_papers_totals_to_our_call_count():
    paper = PAPER["table7_compute"]
    rows = [{"component": r["component"], "states": r["states"], "in_search_cpu_per_state_ns": 70.0,
             "paper_per_state_ns": 500.0, "cheaper_than_paper_per_state": 7.1} for r in paper]
    table = table7(rows, 2500, ((81, 81, 11, 36), (97, 55, 11, 36)))
    for ours, theirs in zip(table.paper_rows, paper, strict=True):
        assert ours["total_s"] == pytest.approx(theirs["total_s"] * 2500 / PAPER_CALLS)
        assert ours["per_state_ns"] == pytest.approx(theirs["total_s"] / PAPER_CALLS / theirs["states"] * 1e9)
    assert "TTR (81, 81, 11, 36), BRT (97, 55, 11, 36)" in table.notes
    assert all(c in table.notes for c in table.claims) and len(table.claims) >= 2
