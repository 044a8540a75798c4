"""A semantic bird's-eye map: a label raster (core.labels ids) in a metric raster frame."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from navlab.core.grid import RasterFrame
from navlab.core.io import load_npz, save_npz
from navlab.core.labels import NUM_LABELS


@dataclass(frozen=True)
class SemanticMap:
    name: str
    labels: np.ndarray  # (rows, cols) uint8 label ids
    frame: RasterFrame

    def __post_init__(self):
        if self.labels.shape != self.frame.shape:
            raise ValueError(f"{self.name}: labels {self.labels.shape} do not match frame {self.frame.shape}")
        if self.labels.size and int(self.labels.max()) >= NUM_LABELS:
            raise ValueError(f"{self.name}: label id {int(self.labels.max())} is not in core.labels")

    def crop(self, rows: slice, cols: slice, labels: np.ndarray | None = None) -> SemanticMap:
        """The map inside the box ``[rows, cols]`` (cell slices with explicit bounds) in the same world
        coordinates; ``labels`` (same shape as this map) replaces the label raster, e.g. a perturbed one."""
        r0, r1, c0, c1 = rows.start, rows.stop, cols.start, cols.stop
        if not (0 <= r0 < r1 <= self.frame.shape[0] and 0 <= c0 < c1 <= self.frame.shape[1]):
            raise ValueError(f"{self.name}: crop rows {r0}:{r1}, cols {c0}:{c1} is empty or leaves the "
                             f"{self.frame.shape} map")
        source = self.labels if labels is None else labels
        res = self.frame.resolution
        frame = RasterFrame((r1 - r0, c1 - c0), res, (self.frame.origin[0] + c0 * res, self.frame.origin[1] + r0 * res))
        return SemanticMap(self.name, np.ascontiguousarray(source[r0:r1, c0:c1]), frame)

    def save(self, path: str | Path) -> None:
        save_npz(path, {
            "labels": self.labels.astype(np.uint8),
            "resolution": np.float64(self.frame.resolution),
            "origin": np.asarray(self.frame.origin, dtype=np.float64),
            "name": np.array(self.name),
        })

    @classmethod
    def load(cls, path: str | Path) -> SemanticMap:
        arrays = load_npz(path, fix="build the dataset with `python -m navlab data build`")
        labels = arrays["labels"]
        frame = RasterFrame(labels.shape, float(arrays["resolution"]), tuple(float(v) for v in arrays["origin"]))
        return cls(str(arrays["name"]), labels, frame)
