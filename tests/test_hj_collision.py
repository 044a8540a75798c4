"""The lattice's collision check is conservative by construction (issue 26): a segment the swept OBS check
accepts never comes within the robot radius of an obstacle on its dense replay, and a plan the search
returns with it never fails the dense check. The paper's own OBS (the point check) does let plans graze,
and the closed-loop policy never drives such a plan."""

import math

import numpy as np
import pytest

from navlab.hj.guidance import dist_heuristic
from navlab.hj.planning import plan_clearance
from navlab.hj.pruners import field_error, obs_point_pruner, obs_pruner
from navlab.maps.rooms import Disc, Rect, Room
from navlab.search.dubins_lattice import LatticeSpec, first_step, place, primitive_table
from navlab.search.lattice_fields import chord_clearance
from navlab.search.lattice_search import Budget, Goal, Pruners, search

SPEC = LatticeSpec(0.5, (-0.5, -0.25, 0.0, 0.25, 0.5), (-1.0, -0.5, 0.0, 0.5, 1.0), 1.0, 9, 4, 0.2, 24)  # forward only
# the reversing car (params.yaml's): its segments may pass through rest and back (a cusp)
REVERSING = LatticeSpec(0.5, (-0.5, -0.25, 0.0, 0.25, 0.5), (-1.0, -0.5, 0.0, 0.5, 1.0), 1.0, 13, 4, 0.2, 24,
                        v_min=-0.5)
RADIUS = 0.285


def random_room(rng: np.random.Generator) -> Room:
    """A 3 m × 2 m room with 1-4 random boxes and discs."""
    shapes = []
    for _ in range(rng.integers(1, 5)):
        x, y = rng.uniform(0.3, 2.7), rng.uniform(0.3, 1.7)
        if rng.random() < 0.5:
            w, h = rng.uniform(0.05, 0.6, 2)
            shapes.append(Rect(x - w / 2, y - h / 2, x + w / 2, y + h / 2))
        else:
            shapes.append(Disc(x, y, rng.uniform(0.03, 0.35)))
    return Room("random", 3.0, 2.0, tuple(shapes))


def test_field_error_bounds_the_interpolated_distance():
    """The bilinear raster of the exact distance never exceeds it by more than ``field_error``."""
    rng = np.random.default_rng(0)
    for _ in range(20):
        room = random_room(rng)
        obs = obs_pruner(room, 0.0, resolution=rng.choice([0.02, 0.05, 0.1]))
        xy = rng.uniform((0.0, 0.0), (3.0, 2.0), size=(4000, 2))
        states = np.column_stack([xy, np.zeros((4000, 2))])
        interpolated = obs.values(states) + obs.par[0]  # values() takes the threshold off
        assert (interpolated - room.obstacle_distance(xy[:, 0], xy[:, 1]) <= field_error(obs.field)).all()


def drive(spec: LatticeSpec, parent: np.ndarray, controls: np.ndarray, n: int) -> np.ndarray:
    """(P, n + 1, 2) positions of holding each (a, ω) from ``parent`` for dt in ``n`` midpoint sub-steps
    (``dubins_lattice.integrate``'s rule, vectorised over the primitives)."""
    h = spec.dt / n
    x, y, v, th = (np.full(len(controls), c) for c in parent)
    out = [np.column_stack([x, y])]
    for _ in range(n):
        v1 = np.clip(v + controls[:, 0] * h, spec.v_min, spec.v_max)
        tm = th + 0.5 * controls[:, 1] * h
        x, y = x + h * 0.5 * (v + v1) * np.cos(tm), y + h * 0.5 * (v + v1) * np.sin(tm)
        v, th = v1, th + controls[:, 1] * h
        out.append(np.column_stack([x, y]))
    return np.stack(out, axis=1)


def test_chord_clearance_is_the_chords_distance_to_outside_both_discs():
    """Against brute force: the least distance from the segment a -> b to a point outside both B(a, da) and
    B(b, db) (where an obstacle may be), over random discs: never above it (conservative), and within 1 mm
    of it (tight); the 1-Lipschitz bound (<= 0) where the discs leave a gap on the segment."""
    rng = np.random.default_rng(3)
    angles = np.linspace(0.0, 2.0 * math.pi, 4000, endpoint=False)
    ring = np.column_stack([np.cos(angles), np.sin(angles)])
    for _ in range(300):
        da, db, c = rng.uniform(0.01, 0.5), rng.uniform(0.01, 0.5), rng.uniform(0.0, 0.6)
        a, b = np.zeros(2), np.array([c, 0.0])
        rim = np.vstack([da * ring, b + db * ring])  # each circle's points outside the other disc
        rim = rim[(np.linalg.norm(rim - a, axis=1) >= da - 1e-12) & (np.linalg.norm(rim - b, axis=1) >= db - 1e-12)]
        chord = np.column_stack([np.linspace(0.0, c, 400), np.zeros(400)])
        bound = chord_clearance(da, db, c)
        if c >= da + db:  # the discs leave the chord open: an obstacle may touch it, the Lipschitz bound is <= 0
            assert bound == pytest.approx((da + db - c) / 2) and bound <= 0.0
            continue
        exact = np.linalg.norm(chord[:, None] - rim[None], axis=2).min()
        assert bound <= exact + 1e-9, (da, db, c, bound, exact)
        assert bound >= exact - 1e-3, (da, db, c, bound, exact)
        assert bound >= (da + db - c) / 2 - 1e-12  # never below the 1-Lipschitz bound
    # where the discs leave the chord open the bound is the Lipschitz one, negative when it may cross an obstacle
    assert chord_clearance(-0.1, -0.1, 1.4) == pytest.approx(-0.8)


def test_an_obs_threshold_below_the_field_error_is_refused():
    """A threshold below the raster's error bound is a negative radius: the swept check would keep a segment
    straight through a disc (found in review: 1.4 m through a 0.3 m disc, kept at threshold 0)."""
    obs = obs_pruner(Room("disc", 2.0, 2.0, (Disc(1.0, 1.0, 0.3),)), RADIUS)
    with pytest.raises(ValueError, match="below the field's error bound"):
        obs.with_threshold(0.0)
    assert obs.with_threshold(field_error(obs.field)).par[0] == field_error(obs.field)


@pytest.mark.parametrize("spec", [SPEC, REVERSING], ids=["forward", "reversing"])
def test_no_accepted_primitive_touches_an_obstacle(spec):
    """1,000 random rooms, the 25 primitives from 2 parents just clear of the obstacles in each (at a
    lattice speed, or an off-level one with ``first_step``'s primitives): every segment the swept check
    accepts keeps the radius on its dense replay (the sub-steps the table is integrated on) and on a 4
    times finer one; and the check is tight: it accepts 99% of the segments whose replay is 2 cm clear (the
    1-Lipschitz bound alone accepted 95%: it asks the samples for up to half the step's length of clearance).
    Reversing, a segment may stop and drive back (a cusp), where only the Lipschitz bound decides."""
    rng = np.random.default_rng(26)
    table = primitive_table(spec)
    n = spec.samples_per_step * spec.micro_steps
    accepted = clear = 0  # of the segments whose finer replay is 2 cm clear
    worst = math.inf
    for _ in range(1000):
        room = random_room(rng)
        obs = obs_pruner(room, RADIUS)
        for _ in range(2):
            while True:  # a parent just clear of the obstacles, where the check decides
                xy = rng.uniform((0.0, 0.0), (3.0, 2.0))
                if 0.0 < room.signed_distance(*xy, RADIUS) - field_error(obs.field) < 0.25:
                    break
            level = rng.integers(spec.speed_levels)
            speed = spec.speeds[level] if rng.random() < 0.7 else rng.uniform(spec.v_min, spec.v_max)
            rows, controls = (table[level], spec.controls) if speed == spec.speeds[level] else first_step(spec, speed)
            parent = np.array([*xy, speed, rng.uniform(-math.pi, math.pi)])
            samples = place(rows, parent)
            keep = ~obs.swept(np.broadcast_to(parent, (len(samples), 4)), samples, np.full(len(samples), spec.dt))
            for points, ok in ((drive(spec, parent, controls, n), keep), (drive(spec, parent, controls, 4 * n), keep)):
                gap = room.signed_distance(points[..., 0], points[..., 1], RADIUS).min(axis=1)
                worst = min(worst, gap[ok].min(initial=math.inf))
            accepted += (keep & (gap > 0.02)).sum()
            clear += (gap > 0.02).sum()
    assert worst > 0.0, worst
    assert accepted > 0.99 * clear > 10000, (accepted, clear)


@pytest.mark.parametrize("spec", [SPEC, REVERSING], ids=["forward", "reversing"])
@pytest.mark.parametrize("seed", range(3))
def test_plans_never_fail_the_dense_check(seed, spec):
    """Searches in random rooms (A* and ANA*) return plans whose dense replay keeps the radius."""
    rng = np.random.default_rng(seed)
    found = 0
    for _ in range(15):
        room = random_room(rng)
        obs = obs_pruner(room, RADIUS)
        xy = rng.uniform((0.3, 0.3), (2.7, 1.7), size=(40, 2))
        points = xy[room.signed_distance(xy[:, 0], xy[:, 1], RADIUS) > 0.1]
        if len(points) < 2:
            continue
        start, goal_xy = points[0], points[-1]
        goal = Goal(tuple(goal_xy), 0.2, 0.25)
        for anytime in (False, True):
            result = search(spec, room.bounds, [*start, 0.0, rng.uniform(-math.pi, math.pi)], goal,
                            dist_heuristic(goal.xy, spec.v_max, goal.tolerance), pruners=Pruners(static=obs),
                            budget=Budget(anytime=anytime, max_expansions=20000))
            found += result.found
            assert not result.found or plan_clearance(room, RADIUS, spec, result) > 0.0
    assert found > 10


def test_the_papers_point_check_lets_plans_graze_and_the_closed_loop_never_drives_one():
    """The paper's OBS baseline checks the clearance at the sampled states only (``obs_point_pruner``): in
    random rooms some plans it passes cut into an obstacle between samples, the failure the paper's dense check
    catches (Table IV). Our closed-loop rule: the policy never returns such a plan (it counts it rejected)."""
    from navlab.hj.lattice_policy import LatticePolicy
    from navlab.hj.receding_horizon import Observation

    rng = np.random.default_rng(0)
    grazing = []
    for _ in range(60):
        room = random_room(rng)
        xy = rng.uniform((0.3, 0.3), (2.7, 1.7), size=(40, 2))
        points = xy[room.signed_distance(xy[:, 0], xy[:, 1], RADIUS) > 0.1]
        if len(points) < 2:
            continue
        start, goal = np.array([*points[0], 0.0, rng.uniform(-math.pi, math.pi)]), Goal(tuple(points[1]), 0.2, 0.25)
        result = search(SPEC, room.bounds, start, goal, dist_heuristic(goal.xy, SPEC.v_max, goal.tolerance),
                        pruners=Pruners(static=obs_point_pruner(room, RADIUS)), budget=Budget(max_expansions=50000))
        if result.found and plan_clearance(room, RADIUS, SPEC, result) <= 0.0:
            grazing.append((room, start, goal))
    assert grazing, "no plan of the point check grazed an obstacle: the paper's failure mode is not exercised"
    for room, start, goal in grazing:
        policy = LatticePolicy(SPEC, room, lambda g: dist_heuristic(g, SPEC.v_max, 0.2), obs_point_pruner(room, RADIUS),
                               goal_tolerance=goal.tolerance, goal_max_speed=goal.max_speed, max_expansions=50000,
                               robot_radius=RADIUS)
        commands = policy(Observation(0.0, start, goal.xy, np.zeros((0, 2)), np.zeros((0, 2))))
        assert policy.dense_rejections == 1
        assert isinstance(commands, np.ndarray) and len(commands) == 0  # braked at rest: no plan driven
