"""params.yaml `surenav.graph`: the superpixel region graph (SuReNav Sec. IV-B)."""

from __future__ import annotations

from typing import Annotated

from navlab.core.params.fields import between, section


@section
class GraphParams:
    target_nodes: Annotated[int, between(1)]  # SLIC's target number of superpixels for one map tile
    compactness: Annotated[float, between(0.0)]  # SLIC: spatial vs label term; small values follow label edges closely
    tau_m: Annotated[float, between(0.0)]  # τ of Eq. (5): shortest shared boundary (metres) that still makes an edge
