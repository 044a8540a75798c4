"""The context demonstrator's rules on small hand-built maps where each rule's decision is known."""

from __future__ import annotations

import numpy as np
import pytest

from navlab.core.grid import RasterFrame
from navlab.core.labels import HARD_IDS, label_id
from navlab.graphs.region_graph import build_region_graph
from navlab.maps.semantic_map import SemanticMap
from navlab.surenav.context.personas import CONTEXT_PERSONAS, mean_persona
from navlab.surenav.context.regions import region_context
from navlab.surenav.context.rules import ROUGH_FACTOR, relaxation_costs
from navlab.surenav.context.walker import ContextWalker, RuleCost

L = {name: label_id(name) for name in ("sidewalk", "crosswalk", "road", "grass", "rough_terrain", "building")}
PRAGMATIC = CONTEXT_PERSONAS[1]


def blocks(labels: np.ndarray, size: int, across: set[int] = frozenset()) -> np.ndarray:
    """Region ids: ``size``-cell blocks of one label (labels in ``across``: column strips spanning the
    map's height, as one superpixel spans a narrow road), 0..N-1, -1 on hard cells."""
    rows, cols = np.indices(labels.shape)
    band = np.where(np.isin(labels, list(across)), 0, rows // size)
    key = (labels.astype(np.int64) * 1000 + band) * 1000 + cols // size
    _, ids = np.unique(key, return_inverse=True)
    ids = ids.reshape(labels.shape)
    hard = np.isin(labels, HARD_IDS)
    _, ids[~hard] = np.unique(ids[~hard], return_inverse=True)
    ids[hard] = -1
    return ids


def psi_at(labels, regions, cell, persona=PRAGMATIC, new_hard=None) -> float:
    ctx = region_context(labels, regions, int(regions.max()) + 1, 1.0, new_hard)
    return float(relaxation_costs(ctx, persona)[regions[cell]])


def street(width: int = 120, bottom_sidewalk_to: int | None = None) -> np.ndarray:
    """Sidewalk rows 0-2, a 10 m road rows 3-12, sidewalk rows 13-15 (up to ``bottom_sidewalk_to``,
    then buildings)."""
    lab = np.full((16, width), L["road"], dtype=np.uint8)
    lab[:3] = lab[13:] = L["sidewalk"]
    if bottom_sidewalk_to is not None:
        lab[13:, bottom_sidewalk_to:] = L["building"]
    return lab


def test_road_where_the_sidewalk_ends_is_a_crossing_point_and_mid_block_costs_the_budget():
    lab = street(bottom_sidewalk_to=60)
    regions = blocks(lab, 10, {L["road"]})
    surface = 0.2 * 10.0  # (1.2 - 1) x sqrt(100 m²)
    assert psi_at(lab, regions, (8, 55)) == pytest.approx(PRAGMATIC.crossing_point_m + surface)
    assert psi_at(lab, regions, (8, 25)) == pytest.approx(PRAGMATIC.crossing_budget_m + surface)


def test_road_without_a_sidewalk_alongside_costs_its_surface_only():
    lab = np.full((40, 60), L["rough_terrain"], dtype=np.uint8)
    lab[15:25] = L["road"]
    regions = blocks(lab, 10, {L["road"]})
    assert psi_at(lab, regions, (20, 30)) == pytest.approx(0.2 * 10.0)


def test_small_patch_is_cut_a_large_one_only_at_its_corner():
    lab = np.full((60, 60), L["sidewalk"], dtype=np.uint8)
    lab[2:10, 2:10] = L["grass"]  # 64 m²: small for every persona
    lab[15:55, 15:55] = L["grass"]  # 1600 m²: large
    regions = blocks(lab, 10)
    surface = 0.2 * 10.0
    assert psi_at(lab, regions, (5, 5)) == pytest.approx(PRAGMATIC.small_patch_m + 0.2 * 8.0)
    assert psi_at(lab, regions, (16, 16)) == pytest.approx(PRAGMATIC.corner_cut_m + 0.2 * np.sqrt(25.0))
    assert psi_at(lab, regions, (35, 35)) == pytest.approx(PRAGMATIC.interior_m + surface)
    lab[15:55, 15:55] = L["rough_terrain"]
    assert psi_at(lab, regions, (35, 35)) == pytest.approx(ROUGH_FACTOR * PRAGMATIC.interior_m + 0.6 * 10.0)


def test_what_borders_a_new_obstacle_is_cheap_whatever_its_label():
    lab = street()
    regions = blocks(lab, 10, {L["road"]})
    new = np.zeros(lab.shape, dtype=bool)
    new[0:3, 50:60] = True  # the sidewalk above road strip 50-59 is blocked
    lab[new] = L["building"]
    regions[new] = -1
    assert psi_at(lab, regions, (8, 55), new_hard=new) == pytest.approx(PRAGMATIC.bypass_m + 2.0)
    assert psi_at(lab, regions, (8, 25), new_hard=new) == pytest.approx(PRAGMATIC.crossing_budget_m + 2.0)


def test_crosswalk_costs_nothing():
    lab = street()
    lab[3:13, 40:44] = L["crosswalk"]
    regions = blocks(lab, 10, {L["road"], L["crosswalk"]})
    assert psi_at(lab, regions, (8, 42)) == 0.0
    assert psi_at(lab, regions, (8, 35)) == pytest.approx(PRAGMATIC.crossing_point_m + 2.0)  # beside it
    new = np.zeros(lab.shape, dtype=bool)
    new[0:3, 40:44] = True  # an obstacle where the crosswalk meets the sidewalk: the crosswalk stays free
    assert psi_at(lab, regions, (8, 42), new_hard=new) == 0.0


def test_mean_persona_averages_every_tolerance():
    mean = mean_persona()
    assert mean.crossing_budget_m == pytest.approx(np.mean([p.crossing_budget_m for p in CONTEXT_PERSONAS]))
    assert mean.interior_m == pytest.approx(np.mean([p.interior_m for p in CONTEXT_PERSONAS]))


def _crossing_column(persona, crosswalk_offset_m: int) -> float:
    """Where the walker crosses a long street from (1, 100) to (14, 100), a crosswalk ``crosswalk_offset_m``
    to the left: the mean column of the road and crosswalk cells it walks."""
    lab = street(width=200)
    c = 100 - crosswalk_offset_m
    lab[3:13, c - 2:c + 2] = L["crosswalk"]
    regions = blocks(lab, 10, {L["road"], L["crosswalk"]})
    frame = RasterFrame(lab.shape, 1.0)
    graph = build_region_graph(regions.astype(np.int32), lab, frame, 1.0)
    cells = ContextWalker(persona, 100.0).plan(SemanticMap("street", lab, frame), graph, (1, 100), (14, 100))
    crossing = np.isin(lab[cells[:, 0], cells[:, 1]], [L["road"], L["crosswalk"]])
    return float(cells[crossing, 1].mean())


def test_walker_takes_the_farther_crosswalk_within_its_budget_and_jaywalks_beyond_it():
    # the detour is about twice the offset: 80 m, inside the pragmatic budget (120 m), beyond the hurried (60 m)
    assert abs(_crossing_column(PRAGMATIC, 40) - 60) <= 10
    assert abs(_crossing_column(CONTEXT_PERSONAS[2], 40) - 100) <= 3


def test_rule_cost_reads_new_obstacles_against_the_first_graph_it_saw():
    lab = street()
    frame = RasterFrame(lab.shape, 1.0)
    regions = blocks(lab, 10, {L["road"]})
    cost = RuleCost(PRAGMATIC)
    before = build_region_graph(regions.astype(np.int32), lab, frame, 1.0)
    nodes = np.arange(before.num_nodes)
    node = before.node_raster[8, 55]
    assert cost(before, nodes)[node] == pytest.approx(PRAGMATIC.crossing_budget_m + 2.0)
    lab[0:3, 50:60] = L["building"]
    regions[0:3, 50:60] = -1
    after = build_region_graph(regions.astype(np.int32), lab, frame, 1.0)
    assert cost(after, np.arange(after.num_nodes))[after.node_raster[8, 55]] == pytest.approx(PRAGMATIC.bypass_m + 2.0)
