"""One-sided derivatives: exactness on linear data, order of accuracy on smooth periodic data, upwinding."""

import math

import numpy as np
import pytest
import torch
from hypothesis import given, settings
from hypothesis import strategies as st

from navlab.reach.boundary_conditions import pad
from navlab.reach.finite_differences import SCHEMES, scheme
from navlab.reach.grid import Grid


@pytest.mark.parametrize("name", sorted(SCHEMES))
@settings(max_examples=15, deadline=None)
@given(
    slope=st.floats(-5, 5),
    offset=st.floats(-5, 5),
    dim=st.integers(0, 2),
    shape=st.tuples(st.integers(3, 9), st.integers(3, 9), st.integers(3, 9)),
)
def test_linear_functions_are_differentiated_exactly_up_to_the_boundary(name, slope, offset, dim, shape):
    grid = Grid((-1.0, 0.0, 2.0), (1.0, 3.0, 4.0), shape, (False, False, False))
    values = (slope * grid.mesh(dim, dtype=torch.float64) + offset).expand(shape).contiguous()
    for d in range(3):
        left, right = scheme(name).left_right(values, d, grid.spacing[d], False)
        expected = slope if d == dim else 0.0
        assert torch.allclose(left, torch.full_like(left, expected), atol=1e-9)
        assert torch.allclose(right, torch.full_like(right, expected), atol=1e-9)


@pytest.mark.parametrize("name, order", [("upwind1", 0.9), ("eno2", 1.8), ("weno5", 3.5)])
def test_order_of_accuracy_on_a_smooth_periodic_function(name, order):
    errors = []
    for n in (40, 80):
        grid = Grid((0.0,), (2 * math.pi,), (n,), (True,))
        x = grid.mesh(0, dtype=torch.float64)
        left, right = scheme(name).left_right(torch.sin(x) + 0.5 * torch.cos(2 * x), 0, grid.spacing[0], True)
        exact = torch.cos(x) - torch.sin(2 * x)
        errors.append(max(float((left - exact).abs().max()), float((right - exact).abs().max())))
    assert math.log2(errors[0] / errors[1]) > order


@pytest.mark.parametrize("name", sorted(SCHEMES))
def test_one_sided_derivatives_see_their_own_side_of_a_kink(name):
    grid = Grid((-1.0,), (1.0,), (41,), (False,))
    x = grid.mesh(0, dtype=torch.float64)
    left, right = scheme(name).left_right(x.abs(), 0, grid.spacing[0], False)
    assert float(left[20]) == pytest.approx(-1.0, abs=1e-9)
    assert float(right[20]) == pytest.approx(1.0, abs=1e-9)
    assert torch.allclose(left[:18], torch.full((18,), -1.0, dtype=torch.float64))
    assert torch.allclose(right[23:], torch.full((18,), 1.0, dtype=torch.float64))


def test_ghost_cells_wrap_periodic_axes_and_extrapolate_the_others():
    values = torch.tensor([[1.0, 2.0, 4.0], [3.0, 5.0, 9.0]])
    assert pad(values, 1, 2, True).tolist() == [
        [2.0, 4.0, 1.0, 2.0, 4.0, 1.0, 2.0],
        [5.0, 9.0, 3.0, 5.0, 9.0, 3.0, 5.0],
    ]
    assert pad(values, 1, 2, False).tolist() == [
        [-1.0, 0.0, 1.0, 2.0, 4.0, 6.0, 8.0],
        [-1.0, 1.0, 3.0, 5.0, 9.0, 13.0, 17.0],
    ]


def test_unknown_scheme_names_the_choices():
    with pytest.raises(ValueError, match="weno5"):
        scheme("weno7")


def test_quadratic_is_exact_for_eno2_in_the_interior():
    grid = Grid((-1.0,), (1.0,), (21,), (False,))
    x = grid.mesh(0, dtype=torch.float64)
    left, right = scheme("eno2").left_right(3 * x**2 - x, 0, grid.spacing[0], False)
    exact = (6 * x - 1).numpy()
    np.testing.assert_allclose(left[2:-2].numpy(), exact[2:-2], atol=1e-9)
    np.testing.assert_allclose(right[2:-2].numpy(), exact[2:-2], atol=1e-9)
