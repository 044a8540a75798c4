"""The navigation stack of issue 64 (navlab.stack): its world, its route layer's terrain costs, its motion
layer's window and the hand-offs between the layers (a route that relaxes a region is followed there; the
pedestrians in the window reach the pruner), and the ablation's paired table.

Synthetic maps throughout (1 m cells, a sidewalk cut by a blockage, a grass detour on either side), so that
nothing but the HJ grids of ``artifacts/hj`` (the general TTR and the human BRT, loaded once per module) is
needed; the world's episode draw alone runs on the smoke-profile data of conftest's ``smoke_data``.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from navlab.core.grid import RasterFrame
from navlab.core.labels import FREE_IDS, HARD_IDS, SOFT_IDS, label_id
from navlab.core.params import load_params
from navlab.graphs.region_graph import build_region_graph, superpixel_graph
from navlab.maps.semantic_map import SemanticMap
from navlab.stack import ablation, motion, route, world
from navlab.stack.world import StackEpisode, Walker

pytestmark = pytest.mark.usefixtures("single_thread")

SIDEWALK, GRASS, ROAD, BUILDING = (label_id(n) for n in ("sidewalk", "grass", "road", "building"))
ORIGIN = (100.0, 50.0)  # the box's world corner: every layer must work in box metres and hand back world ones
GRASS_A, GRASS_B = 1, 2  # the two grass superpixels of the detour map (above and below the sidewalk)


# ----------------------------------------------------------------------------------------------- fixtures


@pytest.fixture(scope="module")
def params():
    return load_params("default")


@pytest.fixture(scope="module")
def follower(params):
    """HJ-search's planner on the committed grids (seconds to open); skipped where they were not built."""
    if not all((Path("artifacts") / "hj" / name).is_file() for name in ("ttr.npy", "human_brt.npy")):
        pytest.skip("artifacts/hj holds no TTR or human BRT grid: "
                    "`python -m navlab artifacts build --only hj_grids`")
    return motion.HJFollower(params, "artifacts")


def episode(prior: np.ndarray, truth: np.ndarray, superpixels: np.ndarray, start, goal,
            walkers: tuple[Walker, ...] = ()) -> StackEpisode:
    """A StackEpisode on hand-made rasters (1 m cells at ``ORIGIN``); the PACER fields are placeholders that
    neither the route layer's executor nor the motion layer reads."""
    frame = RasterFrame(prior.shape, 1.0, ORIGIN)
    return StackEpisode("synthetic", SemanticMap("synthetic", prior, frame), truth, superpixels, start, goal,
                        np.zeros(prior.shape, np.int64), np.zeros((3, 2, 2), np.float32), "realistic",
                        np.zeros(1, np.int64), np.zeros((3, 2, 2), np.float32), 0, walkers)


def detour_map():
    """(prior, truth, superpixels): a 3 m sidewalk (rows 7-9) between two equal grass fields (A rows 3-6,
    B rows 10-12, cols 4-13), buildings elsewhere; the truth blocks the sidewalk at cols 8-9 (the prior does
    not know). Superpixels: the sidewalk 0, grass A 1, grass B 2, -1 on hard ground."""
    prior = np.full((14, 18), BUILDING, np.uint8)
    prior[7:10, 1:17] = SIDEWALK
    prior[3:7, 4:14] = GRASS
    prior[10:13, 4:14] = GRASS
    truth = prior.copy()
    truth[7:10, 8:10] = BUILDING
    superpixels = np.full(prior.shape, -1, np.int32)
    superpixels[prior == SIDEWALK] = 0
    superpixels[3:7, 4:14] = GRASS_A
    superpixels[10:13, 4:14] = GRASS_B
    return prior, truth, superpixels


def zero_cost(graph, nodes, position_xy, goal_xy):
    """Psi = 0 everywhere: the terrain term alone decides what is relaxed."""
    return np.zeros(len(nodes))


def with_timeout(params, seconds: float):
    return dataclasses.replace(params, stack=dataclasses.replace(params.stack, timeout_s=seconds))


def clearance_to(cells_blocked: np.ndarray, xy: np.ndarray) -> np.ndarray:
    """(T,) exact distance (m; 1 m cells, box metres) from each point to the union of the blocked cells."""
    lo = np.argwhere(cells_blocked)[:, ::-1].astype(float)  # (x, y) of each blocked cell's corner
    dx = np.maximum(np.maximum(lo[None, :, 0] - xy[:, None, 0], xy[:, None, 0] - lo[None, :, 0] - 1.0), 0.0)
    dy = np.maximum(np.maximum(lo[None, :, 1] - xy[:, None, 1], xy[:, None, 1] - lo[None, :, 1] - 1.0), 0.0)
    return np.hypot(dx, dy).min(axis=1)


# -------------------------------------------------------------------------------------- motion: RasterRoom


def square_room(rng: np.random.Generator, res: float = 0.1):
    """A 40 x 50 window with one blocked square of random size and place, and the square's box (metres)."""
    blocked = np.zeros((40, 50), bool)
    side = int(rng.integers(4, 15))
    r0, c0 = int(rng.integers(3, 40 - side - 3)), int(rng.integers(3, 50 - side - 3))
    blocked[r0:r0 + side, c0:c0 + side] = True
    return motion.RasterRoom(blocked, res), (c0 * res, (c0 + side) * res, r0 * res, (r0 + side) * res)


def box_signed_distance(x, y, box):
    x0, x1, y0, y1 = box
    outside = np.hypot(np.maximum.reduce([x0 - x, 0 * x, x - x1]), np.maximum.reduce([y0 - y, 0 * y, y - y1]))
    inside = np.minimum.reduce([x - x0, x1 - x, y - y0, y1 - y])
    return np.where(outside > 0, outside, -np.maximum(inside, 0.0))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_raster_room_distance_is_the_distance_to_the_square_or_the_border(seed):
    rng = np.random.default_rng(seed)
    room, box = square_room(rng)
    assert room.bounds == ((0.0, 5.0), (0.0, 4.0))
    x, y = rng.uniform(0, room.width, 20_000), rng.uniform(0, room.height, 20_000)
    expected = np.minimum.reduce([box_signed_distance(x, y, box), x, y, room.width - x, room.height - y])
    free = box_signed_distance(x, y, box) >= 0  # the free side: what the pruners' clearance reads
    got = room.obstacle_distance(x, y)
    assert got.shape == x.shape
    assert np.abs(got - expected)[free].max() <= room.res / 2 + 1e-6
    assert np.allclose(room.signed_distance(x, y, 0.285), got - 0.285)
    # an empty window: the border alone, exactly
    empty = motion.RasterRoom(np.zeros((40, 50), bool), 0.1)
    assert np.allclose(empty.obstacle_distance(x, y), np.minimum.reduce([x, y, 5.0 - x, 4.0 - y]))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_raster_room_signed_distance_inside_the_square_is_exact_to_half_a_cell(seed):
    rng = np.random.default_rng(seed)
    room, box = square_room(rng)
    x, y = rng.uniform(0, room.width, 20_000), rng.uniform(0, room.height, 20_000)
    inside = box_signed_distance(x, y, box) < -room.res  # a cell or more inside the square
    expected = np.minimum.reduce([box_signed_distance(x, y, box), x, y, room.width - x, room.height - y])
    assert inside.sum() > 100
    assert np.abs(room.obstacle_distance(x, y) - expected)[inside].max() <= room.res / 2 + 1e-6


# ---------------------------------------------------------------------------------- motion: window_blocked


def test_window_blocked_reads_the_map_cells_under_the_window():
    allowed = np.ones((10, 12), bool)
    # fully inside an all-allowed map: nothing blocked
    inside = motion.window_blocked(allowed, 1.0, (2.0, 3.0), 4.0, 0.1)
    assert inside.shape == (40, 40) and not inside.any()
    # hanging off the left (x < 0) and the bottom (y >= 10 m) of the map: those window cells are blocked
    off = motion.window_blocked(allowed, 1.0, (-1.0, 8.0), 4.0, 0.1)
    i, j = np.mgrid[0:40, 0:40]
    assert np.array_equal(off, (j < 10) | (i >= 20))
    # one disallowed map cell (row 5, col 7), i.e. x in [7, 8), y in [5, 6): window cells whose centre
    # 5.3 + (j + 0.5) 0.1 is in [7, 8) and 2.7 + (i + 0.5) 0.1 in [5, 6): rows 23-32, cols 17-26
    allowed[5, 7] = False
    one = motion.window_blocked(allowed, 1.0, (5.3, 2.7), 4.0, 0.1)
    expected = np.zeros((40, 40), bool)
    expected[23:33, 17:27] = True
    assert np.array_equal(one, expected)
    # the same cell at 2 m map cells is x in [14, 16), y in [10, 12): from (12, 9) cols 20-39, rows 10-29
    coarse = motion.window_blocked(allowed, 2.0, (12.0, 9.0), 4.0, 0.1)
    expected = np.zeros((40, 40), bool)
    expected[10:30, 20:40] = True
    assert np.array_equal(coarse, expected)


# ------------------------------------------------------------- hand-off: route layer -> motion layer


@pytest.mark.parametrize("cheap", [GRASS_A, GRASS_B])
def test_a_route_that_relaxes_a_region_is_followed_there(params, follower, cheap):
    """The route layer (SuReNav's executor, terrain-costed, Psi = 0) meets the blockage and relaxes the
    cheaper grass field; the motion layer's allowed ground is the sidewalk plus that field alone, and the HJ
    follower drives the route through it to the goal without ever leaving the allowed ground."""
    prior, truth, superpixels = detour_map()
    terrain = np.where(np.isin(superpixels, [GRASS_A, GRASS_B]) & (superpixels != cheap), 1.0, 0.0)
    ep = episode(prior, truth, superpixels, (8, 3), (8, 14))
    policy = route.TerrainSuReNavPolicy(zero_cost, terrain, params.stack.terrain_weight,
                                        params.surenav.model.window_margin_m)
    walked = route.walk_route(ep, policy, params)
    assert walked.status == "reached"
    cells = walked.trajectory
    assert (superpixels[cells[:, 0], cells[:, 1]] == cheap).any()  # the route enters the cheap field

    allowed = motion.allowed_ground(ep, cells)
    assert np.array_equal(allowed, (truth == SIDEWALK) | (superpixels == cheap))
    assert not allowed[np.isin(truth, HARD_IDS)].any()
    assert not allowed[np.isin(superpixels, [GRASS_A, GRASS_B]) & (superpixels != cheap)].any()

    frame = ep.prior.frame
    drive = ablation.drive(ep, frame.cell_to_world(cells), allowed, follower, params)
    assert drive.outcome == "success" and drive.contacts == 0
    xy = drive.trajectory[:, 1:3]
    here = frame.world_to_cell(xy)
    assert frame.contains(here).all()
    assert allowed[here[:, 0], here[:, 1]].all()  # the robot's centre never on disallowed ground
    assert (superpixels[here[:, 0], here[:, 1]] == cheap).any()  # it drove through the relaxed field
    robot = params.hj.grids.robot
    # the disc itself: clear of the disallowed ground by the radius, less the window rasters' exactness
    assert clearance_to(~allowed, xy - ORIGIN).min() >= robot.radius_m - params.stack.window_resolution_m / 2
    assert np.linalg.norm(xy[-1] - frame.cell_to_world(np.array(ep.goal))) <= ablation.GOAL_REACHED_M
    # the car's dynamics: speeds within the lattice's, each period's change within the acceleration limit
    # (plus dv / 2 dt, what the first step from an off-level speed may add: dubins_lattice.first_step)
    period, spec = 1.0 / params.stack.replan_hz, follower.spec
    dv = (spec.v_max - spec.v_min) / (spec.speed_levels - 1)
    v = drive.trajectory[:, 3]
    assert v.min() >= spec.v_min - 1e-9 and v.max() <= spec.v_max + 1e-9
    assert np.abs(np.diff(v)).max() <= (robot.accel_max + dv / (2 * spec.dt)) * period + 1e-9
    assert np.linalg.norm(np.diff(xy, axis=0), axis=1).max() <= spec.v_max * period + 1e-9


# ------------------------------------------------------------- hand-off: pedestrians -> the HJ pruner


def corridor(width: int = 5):
    """A ``width`` m wide straight sidewalk (rows 1..width, cols 1-14), buildings round it; the route along its
    middle row (row 3 for the default 5 m)."""
    labels = np.full((width + 2, 16), BUILDING, np.uint8)
    labels[1:width + 1, 1:15] = SIDEWALK
    superpixels = np.where(labels == SIDEWALK, 0, -1).astype(np.int32)
    middle = (width + 2) // 2
    cells = np.array([(middle, c) for c in range(2, 14)])
    return labels, superpixels, cells


def standing(xy) -> Walker:
    return Walker(np.array([xy, xy], dtype=float), 0.0, 0.0)


def test_a_pedestrian_in_the_window_reaches_the_pruner_and_one_far_away_does_not(params, follower):
    labels, _, _ = corridor()
    allowed = labels == SIDEWALK
    state, goal, dt = np.array([2.5, 3.5, 0.0, 0.0]), (5.5, 3.5), 1.0 / params.stack.replan_hz
    alone = follower.step(state, allowed, 1.0, goal, False, np.zeros((0, 2)), dt)
    far = follower.step(state, allowed, 1.0, goal, False, np.array([[22.5, 3.5]]), dt)  # 20 m ahead
    near = follower.step(state, allowed, 1.0, goal, False, np.array([[4.5, 3.5]]), dt)  # 2 m ahead
    assert alone.planned and far.planned
    assert np.array_equal(far.state, alone.state)
    assert not np.array_equal(near.state, alone.state)


@pytest.mark.parametrize("width", [5, 1])
def test_a_pedestrian_standing_on_the_route_is_passed_where_there_is_room_and_waited_for_where_not(
        params, follower, width):
    """A walker standing on the route's middle: never within the contact distance. On the 5 m walkway the
    local goal steps aside, out of the walker's BRT (``motion.clear_point``), and the robot passes it and
    arrives; on a 1 m walkway there is no way past, and the robot stops short and waits (cut at 15 s), while the same drive without the walker passes through its place (so the pruner, not the route,
    kept the robot off)."""
    labels, superpixels, cells = corridor(width)
    frame = RasterFrame(labels.shape, 1.0, ORIGIN)
    spot = frame.cell_to_world(np.array(cells[5]))
    reach = params.hj.grids.robot.radius_m + params.hj.grids.human.radius_m
    short = with_timeout(params, 15.0)
    route_xy = frame.cell_to_world(cells)
    ep = episode(labels, labels, superpixels, tuple(cells[0]), tuple(cells[-1]), (standing(spot),))
    allowed = motion.allowed_ground(ep, cells)
    met = ablation.drive(ep, route_xy, allowed, follower, short)
    assert met.outcome != "collision" and met.contacts == 0
    gaps = np.linalg.norm(met.trajectory[:, 1:3] - spot, axis=1)
    assert gaps.min() >= reach - 1e-6
    if width == 5:
        assert met.outcome == "success"
        assert gaps.min() >= follower.keep_off_m - 0.5  # it kept off by about the walker's BRT at rest
    else:
        assert met.outcome == "timeout"
        assert met.trajectory[-1, 1] < spot[0] - reach  # short of the walker, on its side
    free = ablation.drive(dataclasses.replace(ep, walkers=()), route_xy, allowed, follower, short)
    assert free.contacts == 0 and free.outcome != "collision"
    assert np.linalg.norm(free.trajectory[:, 1:3] - spot, axis=1).min() < reach


def test_the_resting_keep_off_distance_bounds_the_human_brt(follower):
    """``rest_keep_off``: every stored state of the human BRT at v = 0 farther from the walker than it is safe,
    and it exceeds the collision radius (a pedestrian's BRT is more than its disc)."""
    lookup, keep = follower.human_brt, follower.keep_off_m
    grid = lookup.grid
    axes = [np.linspace(lo, hi, n) for lo, hi, n in zip(grid.lo, grid.hi, grid.shape)]
    rest = lookup.stored.values[:, :, int(np.argmin(np.abs(axes[2])))]
    radius = np.hypot(*np.meshgrid(axes[0], axes[1], indexing="ij"))
    assert keep > lookup.collision_radius
    assert (rest[radius >= keep] > follower.fi.margin).all()


def test_the_follower_passes_a_pedestrian_beside_the_route(params, follower):
    labels, superpixels, cells = corridor()
    frame = RasterFrame(labels.shape, 1.0, ORIGIN)
    spot = frame.cell_to_world(np.array([3, 7])) + [0.0, 1.0]  # 1 m off the route line
    reach = params.hj.grids.robot.radius_m + params.hj.grids.human.radius_m
    # a short path walked to its end before t = 0: it stands there
    walker = Walker(np.array([spot + [-1.0, 0.0], spot]), 5.0, 0.8)
    ep = episode(labels, labels, superpixels, tuple(cells[0]), tuple(cells[-1]), (walker,))
    drive = ablation.drive(ep, frame.cell_to_world(cells), motion.allowed_ground(ep, cells), follower, params)
    assert drive.outcome == "success" and drive.contacts == 0
    assert np.linalg.norm(drive.trajectory[:, 1:3] - spot, axis=1).min() >= reach - 1e-6


# ---------------------------------------------------------------------------- route: the terrain costs


def block_labels(rng: np.random.Generator, shape=(24, 32), block=4) -> np.ndarray:
    names = np.array([SIDEWALK, GRASS, ROAD, BUILDING], np.uint8)
    coarse = rng.choice(names, size=(shape[0] // block, shape[1] // block), p=[0.35, 0.25, 0.25, 0.15])
    return np.repeat(np.repeat(coarse, block, 0), block, 1)


@pytest.mark.parametrize("seed", [0, 1])
def test_region_means_and_the_terrain_term_of_psi(params, seed):
    rng = np.random.default_rng(seed)
    labels = block_labels(rng)
    frame = RasterFrame(labels.shape, 0.5, ORIGIN)
    graph = superpixel_graph(labels, frame, dataclasses.replace(params.surenav.graph, target_nodes=24))
    values = rng.random(labels.shape)
    means = route.region_means(graph, values)
    brute = np.array([values[graph.node_raster == i].mean() for i in range(graph.num_nodes)])
    assert np.allclose(means, brute, rtol=0, atol=1e-12)

    def base(g, n, p, q):  # any Psi: the terrain term is added to it
        return 1.0 + 0.1 * n

    weight = 2.5
    nodes = np.arange(0, graph.num_nodes, 2)  # a window: every other node
    xy = np.array([0.0, 0.0])
    psi = route.with_terrain(base, values, weight)(graph, nodes, xy, xy)
    soft = np.isin(graph.node_label[nodes], SOFT_IDS)
    free = np.isin(graph.node_label[nodes], FREE_IDS)
    assert soft.any() and free.any() and graph.area[nodes[soft]].max() > graph.area.min()
    added = psi - base(graph, nodes, xy, xy)
    expected = weight * brute[nodes[soft]] * np.sqrt(graph.area[nodes[soft]])
    assert np.allclose(added[soft], expected, rtol=1e-12)
    assert np.array_equal(added[free], np.zeros(free.sum()))


@pytest.mark.parametrize("cheap", [GRASS_A, GRASS_B])
def test_the_graph_plan_relaxes_the_cheaper_of_two_equal_detours(params, cheap):
    _, truth, superpixels = detour_map()
    believed = SemanticMap("synthetic", truth, RasterFrame(truth.shape, 1.0, ORIGIN))  # the blockage seen
    sp = superpixels.copy()
    sp[truth == BUILDING] = -1
    sp[(truth == SIDEWALK) & (np.arange(truth.shape[1]) >= 10)] = 3  # the sidewalk beyond the blockage
    graph = build_region_graph(sp, truth, believed.frame, params.surenav.graph.tau_m)
    dear = GRASS_A + GRASS_B - cheap
    terrain = np.where(sp == dear, 0.9, np.where(sp == cheap, 0.1, 0.0))
    policy = route.TerrainSuReNavPolicy(zero_cost, terrain, params.stack.terrain_weight,
                                        params.surenav.model.window_margin_m)
    cells = policy.plan(believed, graph, (8, 3), (8, 14))
    assert cells is not None and tuple(cells[0]) == (8, 3) and tuple(cells[-1]) == (8, 14)
    assert list(policy.last_relaxed) == [cheap]
    on = sp[cells[:, 0], cells[:, 1]]
    assert (on == cheap).any() and not (on == dear).any()
    assert not np.isin(truth[cells[:, 0], cells[:, 1]], HARD_IDS).any()


# ------------------------------------------------------------------------------------------ world: Walker


def test_walker_walks_its_polyline_at_its_speed_and_stops_at_the_end():
    walker = Walker(np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]]), offset_m=1.0, speed=0.5)
    for t in np.linspace(0.0, 20.0, 81):
        s = min(1.0 + 0.5 * t, 7.0)
        expected = (s, 0.0) if s <= 3.0 else (3.0, s - 3.0)
        assert np.allclose(walker.position(t), expected, atol=1e-12), t
    assert np.allclose(walker.velocity(1.0), [0.5, 0.0])  # mid first leg
    assert np.allclose(walker.velocity(8.0), [0.0, 0.5])  # mid second leg
    for t in (1.0, 2.5, 7.0, 10.0):
        assert math.isclose(np.linalg.norm(walker.velocity(t)), 0.5, rel_tol=1e-9)
    assert np.allclose(walker.velocity(12.0), 0.0) and np.allclose(walker.position(1e6), [3.0, 4.0])
    still = standing((2.0, -1.0))
    assert np.allclose(still.position(0.0), [2.0, -1.0]) and np.allclose(still.position(50.0), [2.0, -1.0])
    assert np.allclose(still.velocity(3.0), 0.0)


# ----------------------------------------------------------------------------------- world: the episodes


def test_stack_episodes_are_a_deterministic_draw(smoke_params, smoke_data):
    from navlab.pacer.terrain import load_terrain_bank

    bank = load_terrain_bank(smoke_data, smoke_params.pacer.data)
    first = world.stack_episodes(smoke_params, smoke_data, bank, count=2)
    again = world.stack_episodes(smoke_params, smoke_data, bank, count=2)
    assert len(first) == len(again) == 2
    for a, b in zip(first, again, strict=True):
        assert a.name == b.name and a.start == b.start and a.goal == b.goal
        for field in ("truth", "superpixels", "terrain", "aerial", "ordering", "context"):
            assert np.array_equal(getattr(a, field), getattr(b, field)), field
        assert len(a.walkers) == len(b.walkers) == smoke_params.stack.pedestrians
        for u, w in zip(a.walkers, b.walkers, strict=True):
            assert np.array_equal(u.path, w.path) and u.offset_m == w.offset_m
        # what the draw promises: ends on the mapped sidewalk, a blockage the prior does not know
        assert a.prior.labels[a.start] == SIDEWALK and a.prior.labels[a.goal] == SIDEWALK
        changed = a.truth != a.prior.labels
        assert changed.any() and np.isin(a.truth[changed], HARD_IDS).all()
    other = world.stack_episodes(dataclasses.replace(smoke_params, stack=dataclasses.replace(
        smoke_params.stack, seed=smoke_params.stack.seed + 1)), smoke_data, bank, count=1)[0]
    assert (other.start, other.goal) != (first[0].start, first[0].goal)  # the seed draws, not a constant


def test_the_episode_box_holds_a_route_whose_ends_it_holds():
    route_cells = np.array([(80, c) for c in range(10, 20)] + [(r, 20) for r in range(80, 100)]
                           + [(99, c) for c in range(21, 30)] + [(r, 30) for r in range(98, 79, -1)])
    rows, cols = world._box(route_cells, (100, 100), 12, 8)
    ends = route_cells[[0, -1]]
    assert ((ends[:, 0] < rows.stop) & (ends[:, 1] < cols.stop)).all()  # stack_episode's own check passes
    assert rows.start <= route_cells[:, 0].min() and route_cells[:, 0].max() < rows.stop
    assert cols.start <= route_cells[:, 1].min() and route_cells[:, 1].max() < cols.stop


# ------------------------------------------------------------------------------- ablation: paired table


def test_paired_rows_pair_each_row_with_the_stack_by_episode():
    rng = np.random.default_rng(3)
    names = [f"tile/{i}" for i in range(7)]
    values = {(row, e): {m: float(rng.normal(i, 1.0)) for m in ablation.METRICS}
              for i, row in enumerate(ablation.ROWS) for e in names}
    outcomes = [ablation.Outcome(row, e, "success", values[row, e], np.zeros(0), np.zeros((1, 5)),
                                 np.zeros((1, 2), np.int64))
                for row in ablation.ROWS for e in rng.permutation(names)]  # each row in its own order
    rng.shuffle(outcomes)
    table = ablation.paired_rows(outcomes, seed=0)
    assert [entry["row"] for entry in table] == list(ablation.ROWS)
    for entry in table:
        row = entry["row"]
        assert entry["episodes"] == len(names)
        for metric in ablation.METRICS:
            mine = np.array([values[row, e][metric] for e in names])
            mean, lo, hi = entry[metric]
            assert math.isclose(mean, mine.mean(), abs_tol=1e-12) and lo <= mean <= hi
            if row == ablation.STACK:
                assert f"{metric}_vs_stack" not in entry
                continue
            diff = mine - np.array([values[ablation.STACK, e][metric] for e in names])
            mean, lo, hi = entry[f"{metric}_vs_stack"]
            assert math.isclose(mean, diff.mean(), abs_tol=1e-12) and lo <= mean <= hi
    assert not any(key.endswith("_vs_stack") for key in table[0])
    again = ablation.paired_rows(list(reversed(outcomes)), seed=0)
    assert again == table  # the input's order changes nothing
