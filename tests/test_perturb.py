"""maps.perturb: the altered superpixels really cut the route."""

import numpy as np
import pytest

from navlab.core.labels import FREE_IDS, HARD_IDS, SOFT_IDS
from navlab.core.seeding import rng
from navlab.graphs.superpixels import label_consistent_slic
from navlab.maps.perturb import obstruct_route
from navlab.search.grid_astar import plan
from synthetic_city import city


@pytest.mark.parametrize("kind_probability", [1.0, 0.0])  # new obstacle / obfuscated prior
def test_perturbation_blocks_the_route(kind_probability):
    m = city()
    sp = label_consistent_slic(m.labels, 150, 1.0)
    free_cost = np.where(np.isin(m.labels, FREE_IDS), 1.0, np.inf)
    route = plan(free_cost, (5, 5), (34, 34)).cells  # along the top sidewalk
    for trial in range(5):
        out = obstruct_route(m.labels, sp, route, 2, rng(0, "perturb", trial), obstacle_probability=kind_probability,
                             clearance_cells=6)
        assert 1 <= len(out.seeds) <= 2
        kinds = {"obstacle": HARD_IDS, "obfuscated": SOFT_IDS}
        assert set(out.kinds) == {"obstacle" if kind_probability == 1.0 else "obfuscated"}
        assert np.isin(out.labels[out.changed], kinds[out.kinds[0]]).all()
        assert np.array_equal(out.labels[~out.changed], m.labels[~out.changed])
        hit = out.changed[route[:, 0], route[:, 1]]
        assert hit.any() and not hit[:6].any() and not hit[-6:].any()  # start and goal stay clear
        # grid A* on free space can no longer follow the route through the perturbed cells
        new_free = np.where(np.isin(out.labels, FREE_IDS), 1.0, np.inf)
        assert not np.isfinite(new_free[route[hit, 0], route[hit, 1]]).any()
        detour = plan(new_free, (5, 5), (34, 34))
        if detour.cells is not None:
            assert not out.changed[detour.cells[:, 0], detour.cells[:, 1]].any()
            assert detour.cost >= plan(free_cost, (5, 5), (34, 34)).cost
        # the delta reproduces the new map
        cells, labels = out.delta()
        again = m.labels.copy()
        again.ravel()[cells] = labels
        assert np.array_equal(again, out.labels)


def test_bad_route_is_a_clear_error():
    m = city()
    with pytest.raises(ValueError, match="route_cells"):
        obstruct_route(m.labels, label_consistent_slic(m.labels, 50, 1.0), np.zeros((1, 2), int), 1, rng(0),
                       obstacle_probability=0.5)
