"""params.yaml `data`: how `python -m navlab data build` makes the dataset snapshot."""

from __future__ import annotations

from dataclasses import dataclass

from navlab.core.params.demos import DemosParams
from navlab.core.params.maps import MapsParams


@dataclass(frozen=True)
class DataParams:
    maps: MapsParams
    demos: DemosParams
