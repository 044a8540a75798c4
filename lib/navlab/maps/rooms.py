"""Indoor rooms of the HJ-search paper as exact geometry: rectangles and discs in metres.

The paper (Sec. VII, VIII-B) uses a 9.6 m × 5.4 m room; its figures (Figs. 5, 9) are not in the text, so
the layouts below are our designs that keep each test's purpose. Frame: x along the 9.6 m side, y along
the 5.4 m side, origin at a corner, so the room is ``[0, 9.6] × [0, 5.4]`` and its walls are obstacles.

- ``simulation`` (Fig. 5, Sec. VII): a room with several static obstacles — a desk block, two pillars, a
  cabinet on a wall and a corner shelf — leaving passages of 1.0 m or more, so start-goal pairs are
  often separated by an obstacle.
- ``long_hallway`` (Fig. 9 left, Sec. VIII-B): two solid blocks leave a 1.4 m wide, 6 m long hallway
  between a west and an east bay; goals A (west bay) and B, C (east bay, 1.6 m apart) make the cyclic
  task A → B → C → A run the length of a narrow passage twice.
- ``open`` (Sec. VII-D, Tables VI and IX): the same room with no obstacles but its walls, so that the
  closed-loop tests among humans differ only in how the humans are handled.
- ``dense_room`` (Fig. 9 right): two staggered walls (from the top and from the bottom) and clutter; the
  goals A and B are 5.6 m apart with no line of sight, so a path must wind around both walls (S-shape).

Everything is computed from the geometry: an occupancy raster on a RasterFrame and the exact signed
distance to the obstacles minus the robot radius (the failure set of the static BRT is ``sdf < 0``).
The distance is exact in free space — where the BRT needs it — and inside obstacles it is the depth
into the nearest single shape (a lower bound on the depth into the union; the sign is always right).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from navlab.core.grid import RasterFrame

ROOM_SIZE = (9.6, 5.4)


@dataclass(frozen=True)
class Rect:
    x0: float
    y0: float
    x1: float
    y1: float

    def signed_distance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Exact signed distance to the rectangle (negative inside)."""
        cx, cy = (self.x0 + self.x1) / 2, (self.y0 + self.y1) / 2
        dx = np.abs(x - cx) - (self.x1 - self.x0) / 2
        dy = np.abs(y - cy) - (self.y1 - self.y0) / 2
        outside = np.hypot(np.maximum(dx, 0.0), np.maximum(dy, 0.0))
        return outside + np.minimum(np.maximum(dx, dy), 0.0)


@dataclass(frozen=True)
class Disc:
    cx: float
    cy: float
    r: float

    def signed_distance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.hypot(x - self.cx, y - self.cy) - self.r


@dataclass(frozen=True)
class Room:
    """A rectangular room ``[0, width] × [0, height]`` whose walls and ``obstacles`` are the failure set."""

    name: str
    width: float
    height: float
    obstacles: tuple[Rect | Disc, ...]
    goals: dict[str, tuple[float, float]] = field(default_factory=dict)  # named task positions (m)

    @property
    def bounds(self) -> tuple[tuple[float, float], tuple[float, float]]:
        return (0.0, self.width), (0.0, self.height)

    def obstacle_distance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Signed distance to walls ∪ obstacles (negative inside an obstacle or outside the room)."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        walls = -Rect(0.0, 0.0, self.width, self.height).signed_distance(x, y)
        return np.minimum.reduce([walls, *(o.signed_distance(x, y) for o in self.obstacles)])

    def signed_distance(self, x: np.ndarray, y: np.ndarray, robot_radius: float) -> np.ndarray:
        """The static BRT's implicit failure function: clearance of a disc robot of ``robot_radius``."""
        return self.obstacle_distance(x, y) - robot_radius

    def frame(self, resolution: float) -> RasterFrame:
        rows, cols = round(self.height / resolution), round(self.width / resolution)
        if not np.isclose(rows * resolution, self.height) or not np.isclose(cols * resolution, self.width):
            raise ValueError(f"room {self.name}: resolution {resolution} m does not divide "
                             f"{self.width} m × {self.height} m")
        return RasterFrame((rows, cols), resolution)

    def occupancy(self, resolution: float, robot_radius: float = 0.0) -> tuple[np.ndarray, RasterFrame]:
        """Boolean raster (True = blocked at the cell centre) and its frame; inflate by ``robot_radius``."""
        frame = self.frame(resolution)
        rows, cols = np.indices(frame.shape)
        centres = frame.cell_to_world(np.stack([rows, cols], axis=-1))
        return self.signed_distance(centres[..., 0], centres[..., 1], robot_radius) < 0.0, frame


def simulation_room() -> Room:
    return Room("simulation", *ROOM_SIZE, obstacles=(
        Rect(2.0, 1.6, 3.2, 3.8),    # desk block in the west half
        Disc(5.0, 1.2, 0.35),        # pillar
        Disc(5.0, 4.2, 0.35),        # pillar
        Rect(6.6, 2.2, 7.4, 5.4),    # cabinet against the y = 5.4 wall
        Rect(8.4, 0.0, 9.6, 0.9),    # corner shelf
    ), goals={"west": (0.8, 2.7), "east": (8.8, 2.0), "north_east": (8.6, 4.6), "south": (4.0, 0.6)})


def long_hallway_room() -> Room:
    return Room("long_hallway", *ROOM_SIZE, obstacles=(
        Rect(1.8, 0.0, 7.8, 2.0),    # south block
        Rect(1.8, 3.4, 7.8, 5.4),    # north block: the hallway is y ∈ [2.0, 3.4], x ∈ [1.8, 7.8]
    ), goals={"A": (0.8, 2.7), "B": (8.8, 1.9), "C": (8.8, 3.5)})


def dense_room() -> Room:
    return Room("dense_room", *ROOM_SIZE, obstacles=(
        Rect(3.0, 0.0, 3.3, 3.6),    # wall from the y = 0 side; pass it at y > 3.6
        Rect(4.8, 1.8, 5.1, 5.4),    # wall from the y = 5.4 side; pass it at y < 1.8
        Disc(1.7, 3.1, 0.3),         # clutter before the first wall
        Disc(1.0, 4.6, 0.25),
        Rect(6.5, 3.8, 7.5, 4.6),    # box
        Rect(7.8, 0.5, 8.6, 1.3),    # box
        Disc(8.4, 3.0, 0.3),         # pillar
    ), goals={"A": (1.2, 1.2), "B": (6.6, 2.8)})


def open_room() -> Room:
    return Room("open", *ROOM_SIZE, obstacles=())


ROOMS = {"open": open_room, "simulation": simulation_room, "long_hallway": long_hallway_room, "dense_room": dense_room}


def load_room(name: str) -> Room:
    if name not in ROOMS:
        raise ValueError(f"room {name!r}: no such room; rooms are {', '.join(ROOMS)}")
    return ROOMS[name]()
