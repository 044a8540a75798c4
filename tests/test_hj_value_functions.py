"""HJ-search Figs. 2 and 3 as tables: the heuristic values at the figure's robots and the orderings the paper
reads off them, on constructed value functions whose answers are known."""

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.hj.value_functions import fig2_table, fig3_table, heuristic_values
from navlab.pipeline.results import claims_of


def _report(table):
    return {"notes": table.notes}


def test_heuristic_values_read_each_lookup_at_each_robot():
    frame = RasterFrame(origin=(0.0, 0.0), resolution=0.5, shape=(4, 4))
    geo = np.arange(16.0).reshape(4, 4)
    robots = [(0.2, 1.2, 0.5, 0.0), (1.7, 0.2, 0.5, np.pi)]
    values = heuristic_values(robots, (1.0, 1.0), lambda x, g: x[:, 3] + 1.0, lambda x: x[:, 0] * 10, (geo, frame),
                              v_max=2.0)
    assert values[(0, "general TTR")] == 1.0 and values[(1, "general TTR")] == np.pi + 1.0
    assert values[(0, "map TTR")] == 2.0 and values[(1, "map TTR")] == 17.0
    assert values[(0, "map Dist")] == geo[2, 0] and values[(1, "map Dist")] == geo[0, 3]
    assert np.isclose(values[(1, "general Dist")], np.hypot(0.7, 0.8) / 2.0)


def _values(rows):
    names = ("map TTR", "general TTR", "map Dist", "general Dist")
    return {(r, n): v for r, row in enumerate(rows) for n, v in zip(names, row)}


def test_fig2_orderings_hold_and_fail_where_the_numbers_say():
    good = _values([(5.0, 4.0, 3.5, 3.0), (6.0, 5.5, 3.5, 3.0)])
    claims = claims_of(_report(fig2_table(good, ["up", "down"], slack_s=0.2)))
    assert [c.verdict for c in claims] == ["holds"] * 4
    # general TTR below Dist by more than the goal disc; map Dist below Dist; map TTR far below TTR; same TTR
    bad = _values([(1.0, 2.0, 2.5, 3.0), (1.0, 2.0, 2.5, 3.0)])
    table = fig2_table(bad, ["up", "down"], slack_s=0.2)
    assert [c.verdict for c in claims_of(_report(table))] == ["does not hold"] * 4
    assert [r["heading"] for r in table.rows] == ["up", "down"] and table.rows[0]["map_dist_s"] == 2.5
    within = _values([(3.95, 4.0, 3.5, 3.0), (5.0, 4.5, 3.5, 3.0)])  # map TTR 0.05 s under: the grid's allowance
    assert claims_of(_report(fig2_table(within, ["up", "down"], slack_s=0.2)))[2].verdict == "holds"


def test_fig3_growth_claim():
    grows = claims_of(_report(fig3_table([0.0, 0.5, 1.0], [0.1, 0.2, 0.2])))
    shrinks = claims_of(_report(fig3_table([0.0, 0.5, 1.0], [0.1, 0.3, 0.2])))
    assert [c.verdict for c in grows] == ["holds"] and [c.verdict for c in shrinks] == ["does not hold"]
    assert "0.50 m/s: 0.300" in shrinks[0].ours
