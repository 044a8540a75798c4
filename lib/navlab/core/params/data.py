"""params.yaml `data`: how `python -m navlab data build` makes the dataset snapshot."""

from __future__ import annotations

from navlab.core.params.demos import DemosParams
from navlab.core.params.fields import section
from navlab.core.params.maps import MapsParams


@section
class DataParams:
    maps: MapsParams
    demos: DemosParams
