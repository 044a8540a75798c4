"""navlab.surenav.blackbox: Eq. 12-14 through the exact A* with blackbox-differentiation gradients.

Two routes from the start to the goal, each through one soft region: the plan takes the cheaper one (a),
the demonstration the other (b). The gradient must raise a's Psi and lower b's, be zero when the plan
already is the demonstration or lambda is too small to change it, and one descent step on it must move
the plan onto the demonstration.
"""

from __future__ import annotations

import numpy as np
import pytest
import torch

from navlab.core.params import load_params
from navlab.search.diff_astar import batch_graphs, diff_astar
from navlab.search.graph_astar import csr_graph
from navlab.surenav.blackbox import blackbox_loss

TRAIN = load_params("default").surenav.train
START, A, B, GOAL = range(4)
# via a: 2 x 11.18 m + Psi_a; via b: 2 x 12.81 m + Psi_b
GRAPH = csr_graph(np.array([[0.0, 0.0], [10.0, 5.0], [10.0, -8.0], [20.0, 0.0]]),
                  np.array([[START, A], [A, GOAL], [START, B], [B, GOAL]]))
SOFT = torch.tensor([[0.0, 1.0, 1.0, 0.0]])


def gradient(psi: list[float], target: list[int], lambda_m: float) -> tuple[torch.Tensor, float]:
    psi = torch.tensor([psi], requires_grad=True)
    graphs = batch_graphs([GRAPH], starts=[START], goals=[GOAL])
    wanted = torch.zeros(1, 4, dtype=torch.bool)
    wanted[0, target] = True
    surrogate, value = blackbox_loss(psi, graphs, SOFT, wanted, TRAIN, lambda_m)
    (grad,) = torch.autograd.grad(surrogate, psi)
    return grad[0], value


def relaxed(psi: torch.Tensor) -> list[int]:
    path = diff_astar(batch_graphs([GRAPH], starts=[START], goals=[GOAL]), psi[None], temperature=1.0).path[0]
    return [i for i in (A, B) if path[i] > 0]


def test_the_gradient_raises_the_wrong_region_and_lowers_the_demonstrated_one():
    assert relaxed(torch.tensor([0.0, 5.0, 10.0, 0.0])) == [A]
    grad, value = gradient([0.0, 5.0, 10.0, 0.0], [B], 30.0)
    assert value > 0
    assert grad[A] < 0 < grad[B]  # descent raises Psi_a and lowers Psi_b
    assert grad[START] == grad[GOAL] == 0
    # Eq. 14's weight (0.5 x 1 FP + 0.5 x 1 FN over 1 + 1 demonstrated)^0.5 scales the plan's change / lambda
    assert grad[B].item() == pytest.approx(0.5 ** TRAIN.gamma / 30.0)


def test_no_gradient_where_the_plan_is_the_demonstration_or_lambda_cannot_change_it():
    grad, value = gradient([0.0, 5.0, 10.0, 0.0], [A], 30.0)
    assert value == 0 and not grad.any()
    grad, _ = gradient([0.0, 5.0, 10.0, 0.0], [B], 1.0)  # Psi moves 0.15 / 0.35 m: route a stays cheaper
    assert not grad.any()


def test_one_descent_step_moves_the_plan_onto_the_demonstration():
    psi = torch.tensor([0.0, 5.0, 10.0, 0.0])
    grad, _ = gradient(psi.tolist(), [B], 30.0)
    stepped = (psi - 500.0 * grad).clamp_min(0.0)
    assert relaxed(stepped) == [B]
    assert gradient(stepped.tolist(), [B], 30.0)[1] == 0


def test_lambda_must_be_positive():
    with pytest.raises(ValueError, match="lambda_m"):
        gradient([0.0, 5.0, 10.0, 0.0], [B], 0.0)
