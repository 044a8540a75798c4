"""The semantic label schema shared by every track (SuReNav Sec. VI-A; palette of its Figs. 5-6).

Constraint classes: free space is always traversable, soft regions are forbidden until a planner
explicitly relaxes them, hard regions are never traversable.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

Constraint = Literal["free", "soft", "hard"]


@dataclass(frozen=True)
class Label:
    id: int
    name: str
    constraint: Constraint
    rgb: tuple[int, int, int]


LABELS: tuple[Label, ...] = (
    Label(0, "sidewalk", "free", (250, 240, 215)),  # ivory
    Label(1, "crosswalk", "soft", (250, 200, 140)),  # light orange
    Label(2, "road", "soft", (90, 90, 90)),  # dark gray
    Label(3, "living_street", "soft", (140, 140, 140)),  # gray
    Label(4, "parking", "soft", (195, 195, 195)),  # light gray
    Label(5, "grass", "soft", (120, 190, 90)),  # green
    Label(6, "rough_terrain", "soft", (165, 130, 90)),  # brown
    Label(7, "building", "hard", (230, 130, 50)),  # orange
    Label(8, "water", "hard", (80, 140, 220)),  # blue
)

BY_NAME: dict[str, Label] = {lab.name: lab for lab in LABELS}
NUM_LABELS = len(LABELS)
PALETTE = np.array([lab.rgb for lab in LABELS], dtype=np.uint8)
FREE_IDS = np.array([lab.id for lab in LABELS if lab.constraint == "free"])
SOFT_IDS = np.array([lab.id for lab in LABELS if lab.constraint == "soft"])
HARD_IDS = np.array([lab.id for lab in LABELS if lab.constraint == "hard"])


def label_id(name: str) -> int:
    """The id of a label by name, with the valid names in the error."""
    try:
        return BY_NAME[name].id
    except KeyError:
        raise KeyError(f"unknown label {name!r}; labels are {', '.join(BY_NAME)}") from None


def constraint_mask(labels: np.ndarray, constraint: Constraint) -> np.ndarray:
    """Boolean mask of the cells whose label has the given constraint class."""
    ids = {"free": FREE_IDS, "soft": SOFT_IDS, "hard": HARD_IDS}[constraint]
    return np.isin(labels, ids)


def colorize(labels: np.ndarray) -> np.ndarray:
    """An RGB image of a label raster in the paper's palette."""
    return PALETTE[labels]


def cost_raster(labels: np.ndarray, soft_cost: dict[str, float]) -> np.ndarray:
    """Cost per metre of each cell: 1 on free labels, ``soft_cost[name]`` on soft ones, ``inf`` on hard.

    Every soft label needs a cost: a missing one is an error rather than a silent default.
    """
    missing = [lab.name for lab in LABELS if lab.constraint == "soft" and lab.name not in soft_cost]
    unknown = sorted(set(soft_cost) - {lab.name for lab in LABELS if lab.constraint == "soft"})
    if missing or unknown:
        raise ValueError(f"soft_cost: missing {missing}, not soft labels {unknown}; give one cost per soft label")
    table = np.array([1.0 if lab.constraint == "free" else soft_cost[lab.name] if lab.constraint == "soft"
                      else np.inf for lab in LABELS])
    return table[labels]
