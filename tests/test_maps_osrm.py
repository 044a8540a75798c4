"""OSRM (the paper's router) and the networkx router agree on the same walkable network."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.labels import constraint_mask
from navlab.maps import dataset
from navlab.maps.network import edge_samples
from navlab.maps.osrm import OsrmRouter
from navlab.maps.routing import Router


@pytest.fixture(scope="module")
def tile(smoke_data):
    entry = next(e for e in dataset.load_index(smoke_data) if e["role"] == "baltimore")
    smap = next(m for m in dataset.load_maps(smoke_data, "test") if m.name == entry["name"])
    return smap, dataset.load_network(smoke_data, "test", entry["name"])


def test_osrm_and_networkx_agree_on_real_tile(tile):
    smap, network = tile
    router = Router(network)
    main = router.components()[0]
    pairs = np.random.default_rng(3).choice(main, size=(6, 2))
    with OsrmRouter(network) as osrm:
        for a, b in pairs:
            ours, theirs = router.route(network.xy[a], network.xy[b]), osrm.route(network.xy[a], network.xy[b])
            assert theirs is not None
            assert theirs.length_m == pytest.approx(ours.length_m, rel=0.01, abs=1.0)
            # OSRM walks the same nodes: every point of its geometry is a network node ...
            assert np.linalg.norm(network.xy[theirs.nodes] - theirs.xy, axis=1).max() < 0.2
            # ... and so never enters a hard cell
            steps = np.stack([np.arange(len(theirs.xy) - 1), np.arange(1, len(theirs.xy))], axis=1)
            cells = smap.frame.world_to_cell(edge_samples(theirs.xy, steps, smap.frame.resolution / 4)[0])
            cells = np.clip(cells, 0, np.array(smap.labels.shape) - 1)
            assert not constraint_mask(smap.labels[cells[:, 0], cells[:, 1]], "hard").any()
