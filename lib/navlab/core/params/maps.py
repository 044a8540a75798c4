"""params.yaml `data.maps`: the SuReNav benchmark maps (real OSM tiles and procedural cities)."""

from __future__ import annotations

from dataclasses import dataclass

from navlab.core.params.fields import between


@dataclass(frozen=True)
class ProceduralParams:
    tile_size_m: float = between(50.0)  # side of a square procedural tile
    block_size_m: tuple[float, ...] = between(20.0, 400.0, length=2)  # block side range (min, max)
    river_probability: float = between(0.0, 1.0)
    living_street_probability: float = between(0.0, 1.0)


@dataclass(frozen=True)
class MapsParams:
    seed: int = between(0)
    resolution_m: float = between(0.1, 10.0)  # metres per cell of every benchmark map
    tile_size_m: float = between(50.0)  # side of a square tile cut from a real city
    min_sidewalk_fraction: float = between(0.0, 1.0)  # tiles with fewer sidewalk cells are dropped
    extra_test_tiles: int = between(0)  # real tiles held out for human-likeness beyond one per test city
    train_maps: int = between(1)
    val_maps: int = between(1)
    procedural: ProceduralParams
