"""params.yaml `pacer`: parameters of the pacer track (PACER, Mao et al. RA-L 2025)."""

from __future__ import annotations

from dataclasses import dataclass

from navlab.core.params.fields import between


@dataclass(frozen=True)
class PacerLayoutParams:
    """Procedural label layouts of one BEV image: warped Voronoi regions plus an optional trail band."""

    regions: tuple[int, ...] = between(1, 8, length=2)  # [min, max] Voronoi regions
    path_probability: float = between(0.0, 1.0)  # chance of a trail band of one more terrain
    path_width: tuple[float, ...] = between(0.01, 1.0, length=2)  # trail width / image size
    boundary_warp: float = between(0.0, 1.0)  # region-boundary wobble / image size


@dataclass(frozen=True)
class PacerPhotometricParams:
    """Lighting and sensor effects added on top of the texture fill."""

    brightness: float = between(0.0, 1.0)  # global gain jitter, +-
    gradient: float = between(0.0, 1.0)  # linear lighting ramp across the image, +-
    shadows: int = between(0)  # at most this many soft shadows
    shadow_strength: float = between(0.0, 1.0)  # darkest shadow multiplies by 1 - this
    noise_std: float = between(0.0, 1.0)  # per-pixel Gaussian noise


@dataclass(frozen=True)
class PacerCameraParams:
    """The ground-plane homography: BEV -> forward camera -> BEV, losing detail far from the robot."""

    near_width: float = between(0.05, 1.0)  # bottom (near) edge of the FOV trapezoid / image width
    resolution: float = between(0.1, 4.0)  # camera image width / BEV width
    aspect: float = between(0.1, 4.0)  # camera image height / camera image width


@dataclass(frozen=True)
class PacerSizesParams:
    train: int = between(1)
    val: int = between(1)
    test: int = between(1)


@dataclass(frozen=True)
class PacerAerialParams:
    """Large rendered aerial maps for the navigation tables (no FOV mask)."""

    size: int = between(32)  # pixels per side
    maps: int = between(1)  # maps per evaluation set
    regions: tuple[int, ...] = between(2, 64, length=2)
    terrains: tuple[int, ...] = between(2, 16, length=2)  # distinct terrains per map
    paths: tuple[int, ...] = between(0, 8, length=2)  # trails across the map


@dataclass(frozen=True)
class PacerDataParams:
    """Terrain banks, BEV rendering, preference contexts and dataset sizes (navlab.pacer data half)."""

    seen: dict[str, tuple[str, ...]]  # terrain class -> photographs under data/raw/terrain
    unseen: dict[str, tuple[str, ...]]
    synthetic: dict[str, tuple[str, ...]]
    realistic_ordering: tuple[str, ...]  # seen + unseen classes, most preferred first
    tiers: dict[str, tuple[str, ...]]  # low / medium / high -> classes
    context_fraction: float = between(0.05, 0.5)
    image_size: int = between(16)
    patch_size: int = between(4)
    n_pairs: int = between(1)
    footprint_texels: tuple[float, ...] = between(8.0, 4096.0, length=2)
    synthetic_replace: float = between(0.0, 1.0)
    layout: PacerLayoutParams
    photometric: PacerPhotometricParams
    camera: PacerCameraParams
    sizes: PacerSizesParams
    aerial: PacerAerialParams


@dataclass(frozen=True)
class PacerParams:
    seed: int = between(0)
    data: PacerDataParams
