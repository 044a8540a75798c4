"""The benchmark's planning window widens when a method finds no plan inside it (navlab.surenav.windows)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.core.grid import RasterFrame
from navlab.core.params.surenav_benchmark import ExecutorParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.maps.semantic_map import SemanticMap
from navlab.metrics.navigation import risk_table
from navlab.surenav.baselines import ClassOrderedPolicy, DStarLitePolicy, ExpertPolicy, RCRPolicy
from navlab.surenav.baselines.rcr import risk_table as rcr_risk_table
from navlab.surenav.benchmark import run_episode
from navlab.surenav.episodes import Environment
from navlab.surenav.experts.personas import PERSONAS
from navlab.surenav.policy import SuReNavPolicy
from navlab.surenav.windows import windows
from synthetic_city import L

GRAPH = GraphParams(target_nodes=200, compactness=1.0, tau_m=1.0)
MARGIN_M = 10.0
RISK = {"crosswalk": 0.1, "road": 0.9, "living_street": 0.4, "parking": 0.3, "grass": 0.5, "rough_terrain": 0.8}
UNIT = {"sidewalk": 0.0, **RISK}
COSTS = np.array([0.1, 0.15, 0.6, 0.4, 0.3, 0.5, 1.0, np.inf, np.inf])
START, GOAL = (57, 15), (57, 105)


def _no_psi(graph, nodes, position_xy, goal_xy):
    return np.zeros(len(nodes))


METHODS = {  # a fresh policy per planning window, its own query window scaled as the benchmark scales it
    "SuReNav": lambda w: SuReNavPolicy(_no_psi, "free_union", MARGIN_M * w.scale),
    "D* Lite": lambda w: DStarLitePolicy(COSTS),
    "COA*": lambda w: ClassOrderedPolicy(np.array([6, 2, 3, 5, 4, 1])),
    "RCR": lambda w: RCRPolicy(rcr_risk_table(RISK), 1.0),
    "Expert": lambda w: ExpertPolicy(PERSONAS[1], int(MARGIN_M * w.scale)),
}


def _ring(blocked_corridor: bool, blocked_detour: bool) -> Environment:
    """A 120 m block of buildings with a sidewalk from START to GOAL along row 57 and a detour round the
    top (rows 2-6, 50 m outside the 10 m window); the truth closes the straight sidewalk (and the detour)."""
    lab = np.full((120, 120), L["building"], dtype=np.uint8)
    lab[55:60, 10:111] = L["sidewalk"]
    lab[2:60, 10:15] = L["sidewalk"]
    lab[2:60, 106:111] = L["sidewalk"]
    lab[2:7, 10:111] = L["sidewalk"]
    truth = lab.copy()
    if blocked_corridor:
        truth[55:60, 55:60] = L["building"]
    if blocked_detour:
        truth[2:7, 55:60] = L["building"]
    prior = SemanticMap("ring", lab, RasterFrame(lab.shape, 1.0))
    return Environment("ring/0", "ring", prior, truth, np.array(START), np.array(GOAL), 1)


def _run(env: Environment, method: str):
    executor = ExecutorParams(sensor_radius_m=8.0, step_m=3.0, max_steps=300, window_margin_m=MARGIN_M)
    settings = type("S", (), {"executor": executor})  # run_episode reads settings.executor only
    return run_episode(env, method, METHODS[method], settings, GRAPH, risk_table(UNIT))


@pytest.mark.parametrize("method", list(METHODS))
def test_a_route_that_leaves_the_window_is_found_by_widening(method):
    out = _run(_ring(blocked_corridor=True, blocked_detour=False), method)
    assert out.success, out.status
    assert out.window_scale > 1  # the first window held no route
    assert out.trajectory[:, 1].min() < START[0] - MARGIN_M  # world y = row + 0.5: the walk left the first window
    assert out.length_m >= out.shortest_m > 0


@pytest.mark.parametrize("method", ["SuReNav", "D* Lite"])
def test_an_open_route_keeps_the_first_window(method):
    out = _run(_ring(blocked_corridor=False, blocked_detour=False), method)
    assert out.success and out.window_scale == 1
    assert out.shortest_m == pytest.approx(90.0)


@pytest.mark.parametrize("method", ["SuReNav", "Expert"])
def test_a_goal_cut_off_on_the_whole_map_still_fails(method):
    out = _run(_ring(blocked_corridor=True, blocked_detour=True), method)
    assert not out.success and out.status == "no_plan"
    assert out.window_scale >= 8  # it widened to the whole map first
    assert np.isinf(out.shortest_m)


@settings(max_examples=60, deadline=None)
@given(rows=st.integers(5, 60), cols=st.integers(5, 60), a=st.tuples(st.integers(0, 59), st.integers(0, 59)),
       b=st.tuples(st.integers(0, 59), st.integers(0, 59)), margin=st.integers(1, 20))
def test_windows_are_nested_and_end_on_the_whole_map(rows, cols, a, b, margin):
    start, goal = np.minimum(a, (rows - 1, cols - 1)), np.minimum(b, (rows - 1, cols - 1))
    seen = list(windows((rows, cols), start, goal, margin))
    for w in seen:
        assert w.box[0].start <= min(start[0], goal[0]) and w.box[0].stop > max(start[0], goal[0])
        assert w.box[1].start <= min(start[1], goal[1]) and w.box[1].stop > max(start[1], goal[1])
    for small, big in itertools.pairwise(seen):
        assert big.scale == 2 * small.scale
        assert big.box[0].start <= small.box[0].start and big.box[0].stop >= small.box[0].stop
        assert big.box[1].start <= small.box[1].start and big.box[1].stop >= small.box[1].stop
    last = seen[-1].box
    assert (last[0].start, last[0].stop, last[1].start, last[1].stop) == (0, rows, 0, cols)


def test_a_margin_under_one_cell_is_refused():
    with pytest.raises(ValueError, match="at least one cell"):
        next(windows((10, 10), (1, 1), (5, 5), 0))
