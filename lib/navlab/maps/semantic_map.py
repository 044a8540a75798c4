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
