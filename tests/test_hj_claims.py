"""Every claim branch of HJ-search's Tables I-V and VII (``navlab.hj.paper.check_claims``) on constructed rows:
each claim holds where our numbers say the paper's finding, does not hold where they say the opposite, and
carries the numbers it was decided on. The closed-loop tables' branches: tests/test_sim_closed_loop.py."""

import pytest

from navlab.hj.closed_loop import PAPER as LOOP_PAPER
from navlab.hj.closed_loop import check_claims as loop_claims
from navlab.hj.paper import TABLE7_TARGET, check_claims


def _verdicts(table_id, rows):
    return {c.claim: c.verdict for c in check_claims(table_id, rows)}


def _search_rows(methods, **columns):
    """One row per method; each column maps to one value per method, in order."""
    return [{"method": m, "infeasible": 0, **{k: v[i] for k, v in columns.items()}} for i, m in enumerate(methods)]


ASTAR_H, ANA_H = ("A* w/ Dist", "A* w/ TTR"), ("ANA* w/ Dist", "ANA* w/ TTR")
ASTAR_P, ANA_P = ("A* w/ OBS", "A* w/ BRT"), ("ANA* w/ OBS", "ANA* w/ BRT")
COMBOS = ("Dist + OBS", "Dist + BRT", "TTR + OBS", "TTR + BRT")

CASES = {  # table: (rows where every claim holds, rows where every claim fails)
    "table1_heuristics_astar": (_search_rows(ASTAR_H, nodes=(900, 300), cost=(5.0, 5.0)),
                                _search_rows(ASTAR_H, nodes=(300, 900), cost=(5.0, 5.12), infeasible=(1, 0))),
    "table2_heuristics_anastar": (_search_rows(ANA_H, success=(7, 12), tasks=(12, 12)),
                                  _search_rows(ANA_H, success=(12, 10), tasks=(12, 12), infeasible=(0, 2))),
    "table3_pruning_astar": (_search_rows(ASTAR_P, nodes=(900, 700), success=(3, 3)),
                             _search_rows(ASTAR_P, nodes=(700, 900), success=(3, 2), infeasible=(1, 1))),
    "table4_pruning_anastar": (_search_rows(ANA_P, success=(8, 12), tasks=(12, 12)),
                               _search_rows(ANA_P, success=(12, 11), tasks=(12, 12), infeasible=(0, 1))),
    "table5_static_general": (_search_rows(COMBOS, success=(90, 95, 92, 98), tasks=(100,) * 4,
                                           nodes_common=(900.0, 800.0, 400.0, 300.0)),
                              _search_rows(COMBOS, success=(99, 95, 92, 90), tasks=(100,) * 4,
                                           nodes_common=(300.0, 400.0, 800.0, 900.0), infeasible=(0, 0, 0, 1))),
}


@pytest.mark.parametrize("table_id", CASES)
def test_each_claim_holds_and_fails_where_the_numbers_say(table_id):
    good, bad = CASES[table_id]
    holding, failing = _verdicts(table_id, good), _verdicts(table_id, bad)
    assert set(holding) == set(failing) and "no plan fails the dense check" in holding
    assert set(holding.values()) == {"holds"}, holding
    assert set(failing.values()) == {"does not hold"}, failing


def test_claims_carry_the_numbers_and_the_reason():
    same, differs = (check_claims("table1_heuristics_astar", rows)[1] for rows in CASES["table1_heuristics_astar"])
    assert same.ours == "5.00 vs 5.00" and "duplicate detection" in differs.ours
    (raise_,) = [c for c in check_claims("table4_pruning_anastar", CASES["table4_pruning_anastar"][1])
                 if c.claim == "BRT raises ANA* success"]
    assert raise_.ours.startswith("11/12 vs 12/12; paper 12/12 vs 8/12") and "nothing left to raise" in raise_.ours
    dense = check_claims("table2_heuristics_anastar", CASES["table2_heuristics_anastar"][1])[-1]
    assert dense.ours == "ANA* w/ Dist 0, ANA* w/ TTR 2"


def test_table7_claims_against_the_target_ratio():
    def rows(ratio):
        return [{"component": name, "cheaper_than_paper_per_state": ratio, "in_search_cpu_per_state_ns": 10.0,
                 "paper_per_state_ns": 10.0 * ratio} for name in ("TTR heuristic", "BRT pruner")]

    above, below = (check_claims("table7_compute", rows(r)) for r in (TABLE7_TARGET + 0.1, TABLE7_TARGET - 0.1))
    assert [c.verdict for c in above] == ["holds", "holds"] and [c.verdict for c in below] == ["does not hold"] * 2
    assert all("dense check" not in c.claim for c in above)  # Table VII runs no plans


def test_table6_face_to_face_reason_when_fs_brt_clears_it_too():
    rows = [dict(r, collisions=0, detour_m=1.5) for r in LOOP_PAPER["table6_dynamic"]]
    rows = [dict(r, success=r["runs"]) if (r["method"], r["scenario"]) == ("FS-BRT", "Face-to-Face") else r
            for r in rows]
    head_on = loop_claims("table6_dynamic", rows)[0]
    assert head_on.verdict == "does not hold" and head_on.why.startswith("FS-BRT detoured 1.50 m")
    assert "; why: FS-BRT detoured" in head_on.line()


def test_unknown_table():
    with pytest.raises(ValueError, match="no claims for 'table6_dynamic'"):
        check_claims("table6_dynamic", [])
