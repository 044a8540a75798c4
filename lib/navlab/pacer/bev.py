"""Bird's-eye-view rendering: a terrain-id raster becomes a photograph-textured ground image.

PACER's inputs are BEV images made from a forward camera by a static ground-plane homography (Sec. II);
we render them the other way round, from a terrain raster, so every pixel's terrain is known exactly:

1. texture fill: each terrain's area gets a crop of one of its photographs (image parts only, see
   ``terrain``), rotated and scaled at random per region, at one ground scale per image;
2. lighting: a global gain with a slight colour cast, a linear lighting ramp, soft elliptical shadows;
3. camera: the ground image is warped into a forward camera's view (the FOV trapezoid onto the camera
   rectangle, ``cv2.warpPerspective``), sensor noise is added there, and it is warped back, so far
   ground (the top) loses detail the way real homography BEVs do;
4. the trapezoid field-of-view mask: narrow at the robot (bottom), full width at the far edge (top);
   everything outside is zero.

Aerial maps (:func:`render_aerial`) take steps 1-2 and add noise, with no camera and no mask.
Images are float32 (H, W, 3) RGB in [0, 1].
"""

from __future__ import annotations

import cv2
import numpy as np

from navlab.core.params.pacer import PacerCameraParams, PacerDataParams, PacerPhotometricParams
from navlab.pacer.terrain import TerrainBank, pyramid_level

REGION_SCALE_JITTER = 0.2  # per-region texture scale varies by up to exp(+-0.2) around the image's scale


def fov_mask(size: int, near_width: float) -> np.ndarray:
    """bool (size, size): the trapezoid seen by a forward camera, full width at the top (far) edge,
    ``near_width * size`` wide at the bottom (near) edge, symmetric about the centre column."""
    centres = np.arange(size, dtype=np.float64) + 0.5
    half_width = 0.5 * size * (1.0 - (1.0 - near_width) * centres / size)
    return np.abs(centres[None, :] - 0.5 * size) <= half_width[:, None]


def ground_homography(size: int, camera: PacerCameraParams) -> tuple[np.ndarray, tuple[int, int]]:
    """(3x3 homography BEV pixel -> camera pixel, camera (width, height)): the FOV trapezoid's corners go
    to the camera image's corners, which is what a flat-ground pinhole camera's view is."""
    width = max(2, round(size * camera.resolution))
    height = max(2, round(width * camera.aspect))
    half_near = 0.5 * size * camera.near_width
    bev = np.float32([[0, 0], [size, 0], [0.5 * size + half_near, size], [0.5 * size - half_near, size]])
    cam = np.float32([[0, 0], [width, 0], [width, height], [0, height]])
    return cv2.getPerspectiveTransform(bev, cam), (width, height)


def texels_per_pixel(rng: np.random.Generator, params: PacerDataParams) -> float:
    """One image's ground scale: a BEV image's width covers ``footprint_texels`` photograph pixels."""
    return float(rng.uniform(*params.footprint_texels)) / params.image_size


def texture_fill(terrain_map: np.ndarray, bank: TerrainBank, rng: np.random.Generator, scale: float) -> np.ndarray:
    """(H, W, 3) float32: every terrain id in ``terrain_map`` filled with a rotated, scaled crop of one of
    its photographs (a fresh photograph, angle, scale jitter and offset per terrain)."""
    height, width = terrain_map.shape
    out = np.zeros((height, width, 3), dtype=np.float32)
    for terrain in np.unique(terrain_map):
        instances = bank.image_parts[terrain]
        pyramid = instances[int(rng.integers(len(instances)))]
        s = scale * float(np.exp(rng.uniform(-REGION_SCALE_JITTER, REGION_SCALE_JITTER)))
        level = pyramid_level(s)
        photo, s = pyramid[level], s / 2**level
        angle = rng.uniform(0.0, 2.0 * np.pi)
        offset = rng.uniform(0.0, 1.0, size=2) * photo.shape[1::-1]
        c, d = s * np.cos(angle), s * np.sin(angle)
        inverse = np.float32([[c, -d, offset[0]], [d, c, offset[1]]])  # output pixel -> photo pixel
        crop = cv2.warpAffine(photo, inverse, (width, height), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                              borderMode=cv2.BORDER_REFLECT_101)
        np.copyto(out, crop, where=(terrain_map == terrain)[:, :, None])
    return out


def lighting(image: np.ndarray, rng: np.random.Generator, photometric: PacerPhotometricParams,
             unit: int, shadows: int) -> np.ndarray:
    """Gain with a slight colour cast, a linear lighting ramp across the image and up to ``shadows`` soft
    elliptical shadows, all multiplicative; shadow sizes are in BEV images of ``unit`` pixels."""
    height, width = image.shape[:2]
    gain = 1.0 + rng.uniform(-photometric.brightness, photometric.brightness)
    cast = 1.0 + rng.uniform(-photometric.brightness, photometric.brightness, size=3) / 3.0
    angle = rng.uniform(0.0, 2.0 * np.pi)
    slope = 2.0 * rng.uniform(-photometric.gradient, photometric.gradient)
    y = (np.arange(height, dtype=np.float32)[:, None] + 0.5) / height - 0.5
    x = (np.arange(width, dtype=np.float32)[None, :] + 0.5) / width - 0.5
    shade = (1.0 + slope * (np.cos(angle) * x + np.sin(angle) * y)).astype(np.float32)
    for _ in range(int(rng.integers(0, shadows + 1))):
        _add_shadow(shade, rng, photometric.shadow_strength, unit)
    out = image * (gain * cast)[None, None, :].astype(np.float32) * shade[:, :, None]
    return out.astype(np.float32)


def _add_shadow(shade: np.ndarray, rng: np.random.Generator, strength: float, unit: int) -> None:
    """Darken ``shade`` in place by one soft-edged ellipse, computed only inside its bounding box."""
    height, width = shade.shape
    cy, cx = rng.uniform(0.0, 1.0, size=2) * (height, width)
    ry, rx = rng.uniform(0.08, 0.3, size=2) * unit
    theta = rng.uniform(0.0, np.pi)
    darkness = strength * rng.uniform(0.5, 1.0)
    reach = 1.6 * max(ry, rx)
    y0, y1 = int(max(0, cy - reach)), int(min(height, cy + reach + 1))
    x0, x1 = int(max(0, cx - reach)), int(min(width, cx + reach + 1))
    y = np.arange(y0, y1, dtype=np.float32)[:, None] + 0.5 - cy
    x = np.arange(x0, x1, dtype=np.float32)[None, :] + 0.5 - cx
    u = (x * np.cos(theta) + y * np.sin(theta)) / rx
    v = (-x * np.sin(theta) + y * np.cos(theta)) / ry
    radius = np.sqrt(u**2 + v**2)
    shade[y0:y1, x0:x1] *= 1.0 - darkness / (1.0 + np.exp((radius - 1.0) / 0.15))


def render_bev(terrain_map: np.ndarray, bank: TerrainBank, rng: np.random.Generator,
               params: PacerDataParams) -> tuple[np.ndarray, np.ndarray]:
    """(image (S, S, 3) float32 in [0, 1] with zeros outside the FOV, fov mask bool (S, S)) for a square
    terrain-id raster of side S; everything random comes from ``rng``."""
    size = terrain_map.shape[0]
    if terrain_map.shape != (size, size):
        raise ValueError(f"terrain_map has shape {terrain_map.shape}; BEV rendering needs a square raster")
    scale = texels_per_pixel(rng, params)
    ground = lighting(texture_fill(terrain_map, bank, rng, scale), rng, params.photometric,
                      unit=size, shadows=params.photometric.shadows)
    homography, camera_size = ground_homography(size, params.camera)
    view = cv2.warpPerspective(ground, homography, camera_size, flags=cv2.INTER_LINEAR,
                               borderMode=cv2.BORDER_REFLECT_101)
    view += rng.normal(0.0, params.photometric.noise_std, size=view.shape).astype(np.float32)
    bev = cv2.warpPerspective(view, homography, (size, size), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                              borderMode=cv2.BORDER_REPLICATE)
    mask = fov_mask(size, params.camera.near_width)
    image = np.clip(bev, 0.0, 1.0) * mask[:, :, None]
    return image.astype(np.float32), mask


def render_aerial(terrain_map: np.ndarray, bank: TerrainBank, rng: np.random.Generator,
                  params: PacerDataParams) -> np.ndarray:
    """(H, W, 3) float32 in [0, 1]: a large top-down map at the BEV images' ground scale, no FOV mask.

    Shadows are as dense per area as in BEV images (their count scales with the map's area)."""
    height, width = terrain_map.shape
    scale = texels_per_pixel(rng, params)
    per_image = (height * width) / params.image_size**2
    image = lighting(texture_fill(terrain_map, bank, rng, scale), rng, params.photometric,
                     unit=params.image_size, shadows=round(params.photometric.shadows * per_image))
    image += rng.normal(0.0, params.photometric.noise_std, size=image.shape).astype(np.float32)
    return np.clip(image, 0.0, 1.0).astype(np.float32)
