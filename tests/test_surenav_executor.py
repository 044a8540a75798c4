"""Algorithm 1's walker (navlab.surenav.semi_static) with every benchmark policy, on hand-built maps."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.labels import HARD_IDS, NUM_LABELS, SOFT_IDS
from navlab.core.params.surenav_benchmark import ExecutorParams
from navlab.core.params.surenav_graph import GraphParams
from navlab.search.grid_astar import plan
from navlab.surenav.baselines import (
    ClassOrderedPolicy,
    CostFieldPolicy,
    DStarLitePolicy,
    ExpertPolicy,
    RCRPolicy,
)
from navlab.surenav.baselines.rcr import risk_table
from navlab.surenav.experts.personas import PERSONAS
from navlab.surenav.semi_static import execute
from synthetic_city import L, city

GRAPH = GraphParams(target_nodes=120, compactness=1.0, tau_m=1.0)
WALK = ExecutorParams(sensor_radius_m=8.0, step_m=3.0, max_steps=300, window_margin_m=20.0)
COSTS = np.array([0.1, 0.15, 0.6, 0.4, 0.3, 0.5, 1.0, np.inf, np.inf])  # per label id, as demo_priors gives
ORDER = np.array([6, 2, 3, 5, 4, 1])  # soft labels, most critical first
RISK = {"crosswalk": 0.1, "road": 0.9, "living_street": 0.4, "parking": 0.3, "grass": 0.5, "rough_terrain": 0.8}
START, GOAL = (5, 6), (114, 110)  # sidewalks in opposite corners of the town


def policies():
    return {
        "cost field": lambda: CostFieldPolicy(COSTS),
        "D* Lite": lambda: DStarLitePolicy(COSTS),
        "COA*": lambda: ClassOrderedPolicy(ORDER),
        "RCR": lambda: RCRPolicy(risk_table(RISK), 1.0),
        "Expert": lambda: ExpertPolicy(PERSONAS[1], 40),
    }


def blocked_city():
    """The town and a true version with new buildings across two sidewalks and an obfuscated crossing."""
    prior = city()
    truth = prior.labels.copy()
    truth[44:56, 36:52] = L["building"]
    truth[74:86, 76:84] = L["building"]
    truth[76:84, 86:100] = L["grass"]
    return prior, truth


def test_endpoints_are_on_the_sidewalk():
    prior, truth = blocked_city()
    assert prior.labels[START] == prior.labels[GOAL] == L["sidewalk"]
    assert truth[START] == truth[GOAL] == L["sidewalk"]


@pytest.mark.parametrize("name", list(policies()))
def test_reaches_the_goal_without_perturbation(name):
    prior = city()
    ex = execute(prior, prior.labels, START, GOAL, policies()[name](), WALK, GRAPH)
    assert ex.status == "reached"
    assert tuple(ex.trajectory[0]) == START and tuple(ex.trajectory[-1]) == GOAL
    assert len(ex.replans) == 1  # nothing new was seen: one plan was enough
    assert np.abs(np.diff(ex.trajectory, axis=0)).max() == 1  # 8-connected steps only


@pytest.mark.parametrize("name", list(policies()))
def test_no_successful_path_enters_a_hard_region(name):
    prior, truth = blocked_city()
    ex = execute(prior, truth, START, GOAL, policies()[name](), WALK, GRAPH)
    assert ex.status == "reached"
    assert not np.isin(truth[ex.trajectory[:, 0], ex.trajectory[:, 1]], HARD_IDS).any()
    assert len(ex.replans) > 1  # the changes were seen and planned around
    flat = np.unique(ex.trajectory[:, 0] * truth.shape[1] + ex.trajectory[:, 1])
    assert ex.relaxed_cells.tolist() == flat[np.isin(truth.ravel()[flat], SOFT_IDS)].tolist()


def _true_cost(cells, cost):
    steps = np.linalg.norm(np.diff(cells, axis=0), axis=1)
    c = cost[cells[:, 0], cells[:, 1]]
    return float((steps * (c[1:] + c[:-1]) / 2).sum())


def test_dstar_lite_walks_as_replanning_from_scratch():
    """D* Lite repairs its search; from-scratch A* on the same beliefs must give plans of the same cost
    at every re-plan, and so the same walk up to ties between equal-cost paths."""
    prior, truth = blocked_city()

    class Recording:
        def __init__(self, inner):
            self.inner, self.uses_graph, self.costs = inner, False, []

        def plan(self, believed, graph, position, goal):
            cells = self.inner.plan(believed, graph, position, goal)
            scratch = plan(COSTS[believed.labels], position, goal)
            self.costs.append((_true_cost(cells, COSTS[believed.labels]), scratch.cost))
            return cells

    dstar = Recording(DStarLitePolicy(COSTS))
    ex = execute(prior, truth, START, GOAL, dstar, WALK, GRAPH)
    assert ex.reached and len(dstar.costs) > 1
    for ours, scratch in dstar.costs:
        assert ours == pytest.approx(scratch, rel=1e-9)
    ref = execute(prior, truth, START, GOAL, CostFieldPolicy(COSTS), WALK, GRAPH)
    assert _true_cost(ex.trajectory, COSTS[truth]) == pytest.approx(_true_cost(ref.trajectory, COSTS[truth]), rel=1e-6)


def test_rcr_relaxes_only_when_blocked_and_prefers_low_risk():
    prior = city()
    policy = RCRPolicy(risk_table(RISK), 1.0)
    ex = execute(prior, prior.labels, START, GOAL, policy, WALK, GRAPH)
    labels_used = set(np.unique(prior.labels[ex.trajectory[:, 0], ex.trajectory[:, 1]]).tolist())
    assert ex.reached
    assert labels_used - {L["sidewalk"]}, "the town's blocks are cut by roads: something had to be relaxed"
    assert L["rough_terrain"] not in labels_used  # the riskiest soft label is never the best choice here


def test_bad_settings_and_endpoints_are_one_clear_error():
    prior = city()
    with pytest.raises(ValueError, match="step_m"):
        execute(prior, prior.labels, START, GOAL, CostFieldPolicy(COSTS),
                ExecutorParams(sensor_radius_m=2.0, step_m=3.0, max_steps=10, window_margin_m=0.0), GRAPH)
    hard = tuple(np.argwhere(prior.labels == L["building"])[0])
    with pytest.raises(ValueError, match="hard cell"):
        execute(prior, prior.labels, hard, GOAL, CostFieldPolicy(COSTS), WALK, GRAPH)
    assert len(COSTS) == NUM_LABELS
