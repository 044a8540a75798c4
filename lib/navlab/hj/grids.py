"""The precomputed HJ value functions of the HJ-search paper (Sec. VI) as DVC artefacts in artifacts/hj/.

Four kinds, each a grid file + sidecar (reach.store) whose ``inputs`` are the params.yaml sub-sections
it depends on (plus the room geometry) and the code fingerprint of this module's imports, so a changed
parameter makes only the affected grids stale and a changed solver, dynamics or value function makes
every grid stale:

- ``ttr.npy``: general goal-centred TTR in obstacle-free space, (x, y, v, θ), goal disc at the origin;
- ``static_brt_<room>.npy``: static-map avoid BRT of each room in ``hj.grids.rooms``, (x, y, v, θ) over
  the room, failure set = signed distance to walls and obstacles minus the robot radius;
- ``human_brt.npy``: human-robot BRT in the robot's body frame, (p_x, p_y, v);
- ``map_ttr.npy``: map-based TTR to the goal ``hj.grids.map_ttr.goal_xy`` of one room (reach-avoid),
  (x, y, v, θ) over the room;
- ``forward_only/hj/{ttr,map_ttr,human_brt}.npy``: the two TTRs and the human-robot BRT of the forward-only
  car (v >= 0), for the labelled variant rows of Tables I-IX and Fig. 2 (issue 59); ``forward_only_root`` is
  an artefact root of the same layout, so ``load_ttr(forward_only(params), forward_only_root(artifacts_dir))`` reads them. Built only
  when the car reverses (v_min < 0).

``build_hj_grids`` is the ``hj_grids`` artefact step; it skips files whose sidecar already records the
same inputs, so ``dvc repro`` after an unrelated change recomputes nothing. ``load_*`` open the files for
lookups and stop with the stage to re-run when params.yaml asks for something else.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import torch

from navlab.core.fingerprint import code_fingerprint
from navlab.core.params import Params, ParamsError
from navlab.maps.rooms import Room, load_room
from navlab.reach.grid import Grid
from navlab.reach.lookup import HumanBRTLookup, MapTTRLookup, StaticBRTLookup, TTRLookup
from navlab.reach.solver import Backend
from navlab.reach.store import StoredGrid, grid_to_dict, is_current, load_grid, save_grid

SUBDIR = "hj"


def solver_code() -> str:
    """Fingerprint of the navlab source this module runs (solver, dynamics, value functions, rooms)."""
    return code_fingerprint(__name__)


@dataclasses.dataclass(frozen=True)
class GridSpec:
    """One value function to build: its file name, grid and the inputs recorded in its sidecar."""

    name: str
    grid: Grid
    inputs: dict[str, Any]
    solve: Callable[[Backend], tuple[Any, dict]]  # backend -> (values, info)


def _asdict(section) -> dict[str, Any]:
    return json_ready(dataclasses.asdict(section))


def json_ready(tree: Any) -> Any:
    if isinstance(tree, dict):
        return {k: json_ready(v) for k, v in tree.items()}
    if isinstance(tree, list | tuple):
        return [json_ready(v) for v in tree]
    return tree


def _settings(params: Params):
    from navlab.reach.settings import SolverSettings

    s = params.hj.grids.solver
    return SolverSettings(scheme=s.scheme, rk_order=s.rk_order, cfl=s.cfl)


def _car(params: Params):
    from navlab.reach.dynamics import DubinsCar4D

    r = params.hj.grids.robot
    return DubinsCar4D(v_max=r.v_max, a_min=r.accel_min, a_max=r.accel_max, omega_max=r.omega_max, v_min=r.v_min)


def _relative(params: Params):
    from navlab.reach.dynamics import HumanRobotRelative

    r = params.hj.grids.robot
    return HumanRobotRelative(v_max=r.v_max, a_min=r.accel_min, a_max=r.accel_max, omega_max=r.omega_max,
                              human_speed=params.hj.grids.human.speed, v_min=r.v_min)


def ttr_spec(params: Params) -> GridSpec:
    g = params.hj.grids
    half = g.ttr.half_extent_m
    grid = Grid((-half, -half, g.robot.v_min, -math.pi), (half, half, g.robot.v_max, math.pi), g.ttr.shape,
                (False, False, False, True))
    inputs = {"code": solver_code(), "kind": "ttr", "grid": grid_to_dict(grid), "robot": _asdict(g.robot),
              "solver": _asdict(g.solver), "ttr": _asdict(g.ttr)}

    def solve(backend):
        from navlab.hj.reachability import general_ttr

        values = general_ttr(_car(params), grid, g.ttr.goal_radius_m, g.ttr.horizon_s, _settings(params),
                             stall_time=g.ttr.stall_s, backend=backend)
        return values, {"unreached_fraction": float((values >= g.ttr.horizon_s).float().mean())}

    return GridSpec("ttr", grid, inputs, solve)


def room_grid(room: Room, shape: tuple[int, ...], speeds: tuple[float, float]) -> Grid:
    """(x, y, v, θ) over the room, v over ``speeds`` (v_min, v_max): a reversing car's v_min < 0."""
    (x0, x1), (y0, y1) = room.bounds
    (v0, v1) = speeds
    return Grid((x0, y0, v0, -math.pi), (x1, y1, v1, math.pi), shape, (False, False, False, True))


def room_obstacle_distance(room: Room, grid: Grid) -> np.ndarray:
    """Signed distance to the room's walls and obstacles on the grid's (x, y) nodes, indexed [i_x, i_y]."""
    x, y = np.meshgrid(grid.axis(0), grid.axis(1), indexing="ij")
    return room.obstacle_distance(x, y)


def static_brt_spec(params: Params, room_name: str) -> GridSpec:
    g = params.hj.grids
    room = load_room(room_name)
    grid = room_grid(room, g.static_brt.shape, (g.robot.v_min, g.robot.v_max))
    inputs = {"code": solver_code(), "kind": "static_brt", "grid": grid_to_dict(grid), "robot": _asdict(g.robot),
              "solver": _asdict(g.solver), "static_brt": _asdict(g.static_brt),
              "room": json_ready(dataclasses.asdict(room))}

    def solve(backend):
        from navlab.hj.reachability import static_brt

        b = g.static_brt
        sol = static_brt(room_obstacle_distance(room, grid), _car(params), grid, robot_radius=g.robot.radius_m,
                         max_horizon=b.horizon_s, band=b.band_m, tolerance=b.tolerance_m, window=b.window_s,
                         settings=_settings(params), backend=backend)
        return sol.values, {"converged": bool(sol.converged), "time_s": float(sol.time), "steps": int(sol.steps)}

    return GridSpec(f"static_brt_{room_name}", grid, inputs, solve)


def human_brt_spec(params: Params) -> GridSpec:
    g = params.hj.grids
    h = g.human_brt
    if len(h.shape) != 3:
        raise ValueError(f"hj.grids.human_brt.shape = {list(h.shape)}: the relative state (p_x, p_y, v) has "
                         f"3 axes")
    reach = g.robot.radius_m + g.human.radius_m + (g.human.speed + g.robot.v_max) * h.horizon_s
    if h.half_extent_m < reach:
        raise ValueError(f"hj.grids.human_brt.half_extent_m = {h.half_extent_m}: must be >= {reach:.3f} m "
                         f"(radii + closing speed × horizon), so every encounter within the horizon is on the grid")
    grid = Grid((-h.half_extent_m, -h.half_extent_m, g.robot.v_min), (h.half_extent_m, h.half_extent_m, g.robot.v_max),
                h.shape, (False, False, False))
    inputs = {"code": solver_code(), "kind": "human_brt", "grid": grid_to_dict(grid), "robot": _asdict(g.robot),
              "human": _asdict(g.human), "solver": _asdict(g.solver), "human_brt": _asdict(h)}

    def solve(backend):
        from navlab.hj.reachability import human_brt

        values = human_brt(_relative(params), grid, collision_radius=g.robot.radius_m + g.human.radius_m,
                           horizon=h.horizon_s, settings=_settings(params), backend=backend)
        return values, {}

    return GridSpec("human_brt", grid, inputs, solve)


def map_ttr_spec(params: Params) -> GridSpec:
    g = params.hj.grids
    room = load_room(g.map_ttr.room)
    (x0, x1), (y0, y1) = room.bounds
    gx, gy = g.map_ttr.goal_xy
    if not (x0 < gx < x1 and y0 < gy < y1) or float(room.obstacle_distance(np.array(gx), np.array(gy))) <= 0:
        raise ParamsError(f"hj.grids.map_ttr.goal_xy = {list(g.map_ttr.goal_xy)}: not in the free space of room "
                          f"{g.map_ttr.room!r} (x in ({x0}, {x1}), y in ({y0}, {y1}), outside walls and obstacles); "
                          "choose a goal inside the room in params.yaml")
    grid = room_grid(room, g.static_brt.shape, (g.robot.v_min, g.robot.v_max))
    inputs = {"code": solver_code(), "kind": "map_ttr", "grid": grid_to_dict(grid), "robot": _asdict(g.robot),
              "solver": _asdict(g.solver), "ttr": _asdict(g.ttr), "map_ttr": _asdict(g.map_ttr),
              "room": json_ready(dataclasses.asdict(room))}

    def solve(backend):
        from navlab.hj.reachability import map_ttr

        values = map_ttr(_car(params), grid, room_obstacle_distance(room, grid), g.map_ttr.goal_xy,
                         g.ttr.goal_radius_m, g.robot.radius_m, g.ttr.horizon_s, _settings(params),
                         stall_time=g.ttr.stall_s, backend=backend)
        return values, {"unreached_fraction": float((values >= g.ttr.horizon_s).float().mean())}

    return GridSpec("map_ttr", grid, inputs, solve)


def specs(params: Params) -> list[GridSpec]:
    return [ttr_spec(params), *(static_brt_spec(params, r) for r in params.hj.grids.rooms), human_brt_spec(params),
            map_ttr_spec(params)]


FORWARD_ONLY = "forward_only"


def _forward_points(n: int, v_min: float, v_max: float, key: str) -> int:
    """Points of a speed axis cut from [v_min, v_max] (``n`` points) to [0, v_max] at the same spacing; 0 m/s
    must be a node of the axis (``key``: its params.yaml key, named when it is not)."""
    spacing = (v_max - v_min) / (n - 1)
    below = -v_min / spacing
    if abs(below - round(below)) > 1e-6:
        raise ParamsError(f"{key} = {n} speed points over [{v_min:g}, {v_max:g}] m/s ({spacing:.4g} m/s apart): 0 m/s "
                          f"is not a node, so the forward-only car's grids cannot keep the spacing; choose n with "
                          f"(n - 1) * {-v_min:g} / {v_max - v_min:g} a whole number")
    return round(v_max / spacing) + 1


def forward_only(params: Params) -> Params:
    """The forward-only car (v in [0, v_max]): the old default, kept as a labelled variant (issue 59). The
    speed axes of the grids and the lattice's speed levels keep their spacing, so the variant differs from the
    paper's reversing car in the speeds it may take, not in resolution."""
    g, lat = params.hj.grids, params.hj.planner.lattice
    v0, v1 = g.robot.v_min, g.robot.v_max

    def cut(shape, key):
        return (*shape[:2], _forward_points(shape[2], v0, v1, key), *shape[3:])

    grids = dataclasses.replace(
        g, robot=dataclasses.replace(g.robot, v_min=0.0),
        ttr=dataclasses.replace(g.ttr, shape=cut(g.ttr.shape, "hj.grids.ttr.shape[2]")),
        static_brt=dataclasses.replace(g.static_brt, shape=cut(g.static_brt.shape, "hj.grids.static_brt.shape[2]")),
        human_brt=dataclasses.replace(g.human_brt, shape=cut(g.human_brt.shape, "hj.grids.human_brt.shape[2]")))
    lattice = dataclasses.replace(
        lat, speed_levels=_forward_points(lat.speed_levels, v0, v1, "hj.planner.lattice.speed_levels"))
    planner = dataclasses.replace(params.hj.planner, lattice=lattice)
    return dataclasses.replace(params, hj=dataclasses.replace(params.hj, grids=grids, planner=planner))


def forward_only_root(artifacts_dir: str | Path) -> Path:
    """The forward-only car's artefact root (inside the ``hj_grids`` output, laid out as ``artifacts_dir``)."""
    return Path(artifacts_dir) / SUBDIR / FORWARD_ONLY


def _builds(params: Params, artifacts_dir: str | Path) -> list[tuple[GridSpec, Path]]:
    """(spec, file) of every grid ``hj_grids`` stores: the paper's car's, then the forward-only car's TTRs and
    human-robot BRT (its variant rows of Tables I-II, Fig. 2 and the OBS-checked rows of Tables III-IX; its
    static BRTs are not built: each would need its own margin solve, ``hj_margins``' largest cost)."""
    out = [(spec, grid_path(artifacts_dir, spec.name)) for spec in specs(params)]
    if params.hj.grids.robot.v_min < 0:
        forward = forward_only(params)
        out += [(spec, grid_path(forward_only_root(artifacts_dir), spec.name))
                for spec in (ttr_spec(forward), map_ttr_spec(forward), human_brt_spec(forward))]
    return out


def grid_path(artifacts_dir: str | Path, name: str) -> Path:
    return Path(artifacts_dir) / SUBDIR / f"{name}.npy"


def build_hj_grids(params: Params, data_dir: str | Path, artifacts_dir: str | Path, *,
                   device: str | torch.device | None = None, progress: bool = True, log=print) -> list[Path]:
    """Artefact step ``hj_grids``: solve and store every value function whose file is not current.

    ``device``: default ``hj.grids.device``; ``hj.grids.compile`` fuses the numerical Hamiltonian
    (torch.compile: the inductor C++ backend on CPU, Triton on CUDA).
    """
    del data_dir  # rooms are analytic geometry; nothing is read from data/
    device = torch.device(device or params.hj.grids.device)
    if device.type == "cuda" and not torch.cuda.is_available():
        raise ValueError(f"hj.grids.device = 'cuda' ({params.profile} profile) but torch sees no GPU; "
                         f"set it to cpu in params.yaml or run on a machine with one")
    backend = Backend(device=device, progress=progress, compile=params.hj.grids.compile)
    out = []
    for spec, path in _builds(params, artifacts_dir):
        if is_current(path, spec.inputs):
            log(f"[hj_grids] {spec.name}: up to date ({path})")
        else:
            start = time.perf_counter()
            values, info = spec.solve(backend)
            values = _to_numpy(values).astype(np.float32)
            # no wall clock in the artefact: the same code and inputs must give the same bytes (DVC hashes them)
            info.update(device=str(device), min_value=float(values.min()), max_value=float(values.max()))
            save_grid(path, values, spec.grid, spec.inputs, info=info)
            log(f"[hj_grids] {spec.name}: {spec.grid.shape} solved in {time.perf_counter() - start:.1f} s -> {path}")
        out.append(path)
    return out


def _to_numpy(values) -> np.ndarray:
    if isinstance(values, torch.Tensor):
        return values.detach().cpu().numpy()
    return np.asarray(values)


def load_value_function(params: Params, artifacts_dir: str | Path, name: str, verify: bool = True) -> StoredGrid:
    """Open one stored value function ("ttr", "static_brt_<room>", "human_brt") checked against params."""
    by_name = {s.name: s for s in specs(params)}
    if name not in by_name:
        raise ValueError(f"value function {name!r}: not built by hj_grids; names are {', '.join(by_name)}")
    return load_grid(grid_path(artifacts_dir, name), by_name[name].inputs, verify=verify)


def load_ttr(params: Params, artifacts_dir: str | Path, verify: bool = True) -> TTRLookup:
    return TTRLookup(load_value_function(params, artifacts_dir, "ttr", verify))


def load_static_brt(params: Params, artifacts_dir: str | Path, room: str, verify: bool = True) -> StaticBRTLookup:
    return StaticBRTLookup(load_value_function(params, artifacts_dir, f"static_brt_{room}", verify))


def load_map_ttr(params: Params, artifacts_dir: str | Path, verify: bool = True) -> MapTTRLookup:
    return MapTTRLookup(load_value_function(params, artifacts_dir, "map_ttr", verify))


def load_human_brt(params: Params, artifacts_dir: str | Path, verify: bool = True) -> HumanBRTLookup:
    return HumanBRTLookup(load_value_function(params, artifacts_dir, "human_brt", verify))
