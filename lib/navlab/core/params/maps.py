"""params.yaml `data.maps`: the SuReNav benchmark maps (real OSM tiles and procedural cities)."""

from __future__ import annotations

from typing import Annotated

from navlab.core.params.fields import between, section


@section
class ProceduralParams:
    tile_size_m: Annotated[float, between(50.0)]  # side of a square procedural tile
    block_size_m: Annotated[tuple[float, ...], between(20.0, 400.0, length=2, ordered=True)]  # block side range [min, max]
    river_probability: Annotated[float, between(0.0, 1.0)]
    living_street_probability: Annotated[float, between(0.0, 1.0)]


@section
class MapsParams:
    seed: Annotated[int, between(0)]
    resolution_m: Annotated[float, between(0.1, 10.0)]  # metres per cell of every benchmark map
    tile_size_m: Annotated[float, between(50.0)]  # side of a square tile cut from a real city
    min_sidewalk_fraction: Annotated[float, between(0.0, 1.0)]  # tiles with fewer sidewalk cells are dropped
    extra_test_tiles: Annotated[int, between(0)]  # real tiles held out for human-likeness beyond one per test city
    train_maps: Annotated[int, between(1)]
    val_maps: Annotated[int, between(1)]
    procedural: ProceduralParams
