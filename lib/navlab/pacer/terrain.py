"""Terrain banks: the real photographs in data/, grouped into terrain classes and split three ways.

PACER (Mao et al., RA-L 2025, Sec. V-A) fills its BEV images and preference contexts from one bank of
image patches per terrain type. Our banks are the top-down photographs that data/ carries under
``raw/terrain/``: Extreme Tux Racer's tileable 256x256 colour terrains, scikit-image's 512x512
grayscale grass/gravel/brick, and Sweet Home 3D's floor and wall textures.

The split is fixed in params.yaml (``pacer.data``), never drawn at random:

* ``seen``: the classes of D_real and D_shuffled and of the seen evaluation environments (ETR pavers,
  gravel, pebbles, grass, dirt, sand, mud, rock);
* ``unseen``: held out, evaluation only, classes never shown in training (ETR limestone, lichen, snow,
  cracked rock and scikit-image's grayscale brick, gravel and grass);
* ``synthetic``: D_synthetic's second texture family (the 14 Sweet Home 3D textures standing in for the
  paper's 14 Poly Haven ones), only ever given random preference orderings.

Terrain ids are positions in :attr:`TerrainBank.terrains`: seen classes first (params order), then
unseen, then synthetic. Every photograph is cut along its width into an *image part* (left) that feeds
BEV images and a *context part* (the right ``context_fraction``) that feeds preference-context patches,
so a context patch never repeats a crop of the image it comes with.

Photographs of your own (terrains the repository never saw) go in the checkout's ``terrain_photos/``
folder and are listed in params.yaml as ``terrain_photos/<file>`` (README, "PACER on terrains of your
own"): ``data build`` replaces data/ whole, so they cannot live there.
"""

from __future__ import annotations

import hashlib
import io
import math
import os
import tempfile
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import cv2
import numpy as np
from PIL import Image

from navlab.core.fingerprint import source_fingerprint
from navlab.core.io import DataError, require, sha256_file
from navlab.core.params import ParamsError, repo_root
from navlab.core.params.pacer import PacerDataParams

Group = Literal["seen", "unseen", "synthetic"]
GROUPS: tuple[Group, ...] = ("seen", "unseen", "synthetic")
PYRAMID_LEVELS = 3  # texture copies at 1, 1/2, 1/4 resolution, so minified fills do not alias
OWN_PHOTOS = "terrain_photos"  # the checkout's folder of photographs of your own (a dep of every PACER stage)
_DECODED: dict[str, np.ndarray] = {}  # sha256 of a photograph's bytes -> its read-only pixels (_read_photo)


@dataclass(frozen=True)
class Terrain:
    id: int
    name: str
    group: Group
    sources: tuple[str, ...]  # photographs: under <data_dir>/raw/terrain, or terrain_photos/... (photo_path)

    @property
    def params_key(self) -> str:
        """The params.yaml key that lists this class's photographs (what an error about one names)."""
        return f"pacer.data.{self.group}.{self.name}"


@dataclass(frozen=True, eq=False)
class TerrainBank:
    """Photographs per terrain id, split into image and context parts, each as a small pyramid.

    ``image_parts[t][k][level]`` is photograph k of terrain t, image part, downsampled 2**level times:
    float32 (h, w, 3) RGB in [0, 1]; ``context_parts`` likewise. ``realistic_rank[t]`` is t's position in
    the realistic ordering (0 = most preferred; -1 for synthetic terrains). Cost tiers are not a property
    of a terrain: they come from the ordering of the terrains of each environment
    (``preferences.environment_tiers``).
    """

    terrains: tuple[Terrain, ...]
    image_parts: tuple[tuple[tuple[np.ndarray, ...], ...], ...]
    context_parts: tuple[tuple[tuple[np.ndarray, ...], ...], ...]
    realistic_rank: np.ndarray

    def __len__(self) -> int:
        return len(self.terrains)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(t.name for t in self.terrains)

    def ids(self, group: Group) -> np.ndarray:
        """Terrain ids of one group, ascending."""
        if group not in GROUPS:
            raise ValueError(f"terrain group {group!r}: allowed groups are {', '.join(GROUPS)}")
        return np.array([t.id for t in self.terrains if t.group == group], dtype=np.int64)

    def id_of(self, name: str) -> int:
        for terrain in self.terrains:
            if terrain.name == name:
                return terrain.id
        raise KeyError(f"terrain {name!r} is not in the bank; known terrains: {', '.join(self.names)}")


def pyramid_level(scale: float) -> int:
    """The pyramid level to sample at ``scale`` photograph pixels per output pixel: the coarsest one that
    still leaves at least one texel per pixel, so linear interpolation never skips texels (no aliasing)."""
    return int(np.clip(np.floor(np.log2(max(scale, 1.0))), 0, PYRAMID_LEVELS - 1))


def load_terrain_bank(data_dir: str | Path, params: PacerDataParams) -> TerrainBank:
    """The bank for ``params`` (``params.pacer.data``), its photographs found by :func:`photo_path`."""
    check_terrain_params(params)
    require(data_dir, "raw", "terrain")
    check_distinct_photos(data_dir, params)
    terrains = terrain_classes(params)
    parts = [[_split_photo(read_listed_photo(data_dir, t.params_key, source, params), params)
              for source in t.sources] for t in terrains]
    index = {t.name: t.id for t in terrains}
    rank = np.full(len(terrains), -1, dtype=np.int64)
    rank[[index[n] for n in params.realistic_ordering]] = np.arange(len(params.realistic_ordering))
    return TerrainBank(terrains, tuple(tuple(p[0] for p in photos) for photos in parts),
                       tuple(tuple(p[1] for p in photos) for photos in parts), rank)


def terrain_classes(params: PacerDataParams) -> tuple[Terrain, ...]:
    """Every class ``pacer.data`` lists, its id its position: seen, unseen, then synthetic, each in params
    order."""
    listed = [(group, name, tuple(sources))
              for group in GROUPS for name, sources in getattr(params, group).items()]
    return tuple(Terrain(i, name, group, sources) for i, (group, name, sources) in enumerate(listed))


def listed_photos(params: PacerDataParams) -> Iterator[tuple[str, str]]:
    """(params key, source) of every photograph a class lists, in bank order: the one walk the bank, its
    fingerprint and ``params check`` share."""
    return ((t.params_key, source) for t in terrain_classes(params) for source in t.sources)


def read_listed_photo(data_dir: str | Path, key: str, source: str, params: PacerDataParams) -> np.ndarray:
    """The photograph ``source`` that ``key`` lists, as float32 RGB in [0, 1]; a DataError naming ``key``
    when it is missing or unreadable, or when its context strip (the right ``context_fraction`` of the width)
    cannot hold the widest crop a context patch takes (``footprint_texels``' max per ``image_size``: a smaller
    strip would be stretched to the patch, a blur and a ground scale no other terrain shows). ``params check``
    runs it on photographs of your own, so a profile that cannot read one is refused before training."""
    path = _existing_photo(data_dir, key, source)
    try:
        photo = _read_photo(str(path))
    except (DataError, OSError) as error:  # OSError: there but not readable (permissions, a folder)
        raise DataError(f"{key}: {error}") from None
    height, width = photo.shape[:2]
    strip = math.ceil(params.patch_size * params.footprint_texels[1] / params.image_size)
    least = math.ceil(strip / params.context_fraction)
    if height < strip or width < least:
        raise DataError(f"{key}: {path} is {width} x {height} px, too small for this profile (its context "
                        f"strip, the right {params.context_fraction:g} of the width, must hold a {strip}-px "
                        f"crop): use a photograph at least {least} px wide and {strip} px high")
    return photo


def photo_path(data_dir: str | Path, source: str) -> Path:
    """Where the photograph ``source`` (an entry of a ``pacer.data`` class list) lives: in the checkout's
    ``terrain_photos/`` when it begins with that folder (photographs of your own, kept by git), else under
    ``<data_dir>/raw/terrain`` (the packages' photographs, which ``data build`` writes)."""
    return repo_root() / source if is_own_photo(source) else Path(data_dir, "raw", "terrain", source)


def photos_fingerprint(data_dir: str | Path, params: PacerDataParams) -> str:
    """sha256 over (source, content) of every photograph the bank reads: what a trained model keys on, so a
    photograph replaced under the same name retrains what learned from it."""
    sources = {source for _, source in listed_photos(params)}
    return source_fingerprint((source, photo_path(data_dir, source)) for source in sources)


def photo_digests(data_dir: str | Path, params: PacerDataParams) -> dict[str, str]:
    """{source: sha256 of its bytes} of every photograph the bank reads: what a trained phase records beside
    its model (``photographs.json``), so a later change to a photograph of your own is seen by name."""
    return {source: sha256_file(photo_path(data_dir, source)) for source in sorted({s for _, s in listed_photos(params)})}


def is_own_photo(source: str) -> bool:
    """Whether ``source`` is a photograph of your own (in the checkout's ``terrain_photos/``, not data/)."""
    return Path(source).parts[:1] == (OWN_PHOTOS,)


def check_terrain_params(params: PacerDataParams) -> None:
    """One clear ParamsError for ``pacer.data`` settings no bank can be built from (the class lists, the
    ordering, the [min, max] ranges, terrains per image), before any photograph is read."""
    _check_classes(params)
    _check_ranges(params)


def check_distinct_photos(data_dir: str | Path, params: PacerDataParams) -> None:
    """One ParamsError when one photograph, by content (a copy under another name counts), is listed by two
    classes: the held-out groups of Tables II/IV would then hold a photograph PACER trained on, under a
    second preference rank. Photographs not there yet are skipped (reading them says so)."""
    owner: dict[str, str] = {}
    for key, source in listed_photos(params):
        path = photo_path(data_dir, source)
        if not path.is_file():
            continue
        digest = sha256_file(path)
        first = owner.setdefault(digest, key)
        if first != key:
            raise ParamsError(f"{key}: {source} holds the same photograph as one {first} lists; a photograph "
                              "belongs to one class (a held-out class must hold photographs no seen class has): "
                              "remove it from one of them")


def _existing_photo(data_dir: str | Path, key: str, source: str) -> Path:
    """The photograph's path, or a DataError naming the params key (a typo in params.yaml is likelier than a
    half-built data/, which ``data check`` would already refuse)."""
    path = photo_path(data_dir, source)
    if path.is_file():
        return path
    if is_own_photo(source):
        raise DataError(f"{key}: {path} does not exist; put the photograph there or correct {key} in params.yaml")
    raise DataError(f"{key}: {source!r} is not a packaged photograph ({path} does not exist); list a photograph of "
                    f"your own as {OWN_PHOTOS}/<file>, or rebuild data/ with `python -m navlab data build --force`")


def _check_classes(params: PacerDataParams) -> None:
    """One clear ParamsError when a class lists no photograph, a photograph outside the checkout's folders
    (an absolute path or one through ``..``), a photograph another class lists too, or the class lists and
    the ordering disagree."""
    classes = terrain_classes(params)
    empty = [t.params_key for t in classes if not t.sources]
    if empty:
        raise ParamsError(f"{', '.join(empty)}: no photographs; list at least one photograph for each class")
    for t in classes:
        outside = [source for source in t.sources if Path(source).is_absolute() or ".." in Path(source).parts]
        if outside:
            raise ParamsError(f"{t.params_key}: {outside[0]!r} points outside the checkout's photographs, which no "
                              f"run records; copy it into {OWN_PHOTOS}/ and list it as {OWN_PHOTOS}/<file>")
    listers: dict[str, str] = {}
    for t in classes:
        for source in t.sources:
            first = listers.setdefault(source, t.params_key)
            if first != t.params_key:
                raise ParamsError(f"{t.params_key}: {source!r} is also listed by {first}; a photograph belongs to "
                                  "one class: remove it from one of them")
    names = [t.name for t in classes]
    duplicated = sorted({n for n in names if names.count(n) > 1})
    if duplicated:
        raise ParamsError(f"pacer.data: terrain classes {duplicated} appear in more than one group; "
                          "give every class one group")
    ranked = set(params.seen) | set(params.unseen)
    ordering = list(params.realistic_ordering)
    if sorted(ordering) != sorted(ranked):
        raise ParamsError(f"pacer.data.realistic_ordering = {ordering}: must list every seen and unseen class "
                          f"exactly once ({sorted(ranked)})")


def _check_ranges(params: PacerDataParams) -> None:
    """[min, max] pairs must be ordered, and a BEV image needs as many distinct terrains per group as it
    can have regions (every region gets its own terrain)."""
    pairs = {"footprint_texels": params.footprint_texels, "layout.regions": params.layout.regions,
             "layout.path_width": params.layout.path_width, "aerial.regions": params.aerial.regions,
             "aerial.terrains": params.aerial.terrains, "aerial.paths": params.aerial.paths}
    for key, (lo, hi) in pairs.items():
        if lo > hi:
            raise ParamsError(f"pacer.data.{key} = [{lo}, {hi}]: give [min, max] with min <= max")
    most = params.layout.regions[1] + (1 if params.layout.path_probability > 0 else 0)
    for group in ("seen", "unseen"):
        if len(getattr(params, group)) < most:
            raise ParamsError(f"pacer.data.{group}: {len(getattr(params, group))} classes, but a BEV image can "
                              f"show {most} terrains (layout.regions max + trail); add classes or lower regions")
    if len(params.synthetic) < 1:
        raise ParamsError("pacer.data.synthetic: no classes; D_synthetic needs at least one synthetic terrain")


def _split_photo(photo: np.ndarray,
                 params: PacerDataParams) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...]]:
    """(image part, context part) pyramids of one photograph, cut along its width."""
    cut = photo.shape[1] - max(1, round(photo.shape[1] * params.context_fraction))
    return _pyramid(photo[:, :cut]), _pyramid(photo[:, cut:])


def _read_photo(path: str) -> np.ndarray:
    """float32 RGB in [0, 1]; grayscale photographs are repeated over the three channels. Decoded once per
    content (a photograph replaced in a running kernel is read anew)."""
    data = Path(path).read_bytes()
    key = hashlib.sha256(data).hexdigest()
    if key not in _DECODED:
        _DECODED[key] = _decode(path, data)
    return _DECODED[key]


def _decode(path: str, data: bytes) -> np.ndarray:
    problem = "the file is empty" if not data else _incomplete_image(data)
    bgr, warned = (None, "") if problem else _with_c_stderr(
        lambda: cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR))
    if bgr is not None and warned:  # libjpeg/libpng decoded around damaged data: grey or shifted blocks
        bgr, problem = None, f"the decoder warns: {' / '.join(warned.splitlines())[:200]}"
    if bgr is None:
        raise DataError(f"{path}: not a readable image ({problem or 'OpenCV cannot decode it'}); replace it (a "
                        "packaged photograph: `python -m navlab data build --force`)")
    rgb = cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB).astype(np.float32) / 255.0
    rgb.setflags(write=False)
    return rgb


def _with_c_stderr(decode):
    """(``decode()``, what C libraries wrote to stderr meanwhile): libjpeg and libpng report damaged data
    (zeroed or corrupt blocks, with the end marker intact) only as warnings on file descriptor 2, never to
    OpenCV's caller, and decode the damage as grey or shifted blocks."""
    with tempfile.TemporaryFile() as captured:
        saved = os.dup(2)
        os.dup2(captured.fileno(), 2)
        try:
            result = decode()
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        captured.seek(0)
        return result, captured.read().decode(errors="replace").strip()


def _incomplete_image(data: bytes) -> str | None:
    """Why a JPEG or PNG does not hold all its image data, or None: Pillow decodes it in full and refuses one
    cut short, which OpenCV would pad with grey. Data after the image's end is allowed (phones append
    motion-photo videos and maker trailers to their JPEGs); other formats are left to OpenCV."""
    if not data.startswith((b"\xff\xd8", b"\x89PNG\r\n\x1a\n")):
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)  # a large photograph, not an attack
            with Image.open(io.BytesIO(data), formats=("JPEG", "PNG")) as image:
                image.load()
    except Image.DecompressionBombError as error:
        return f"{error}; resize it (README, \"PACER on terrains of your own\", says to what)"
    except (OSError, SyntaxError, ValueError) as error:
        return f"Pillow: {error}"
    return None


def _pyramid(image: np.ndarray) -> tuple[np.ndarray, ...]:
    levels = [np.ascontiguousarray(image)]
    for _ in range(PYRAMID_LEVELS - 1):
        levels.append(cv2.pyrDown(levels[-1], borderType=cv2.BORDER_REFLECT_101))
    for level in levels:
        level.setflags(write=False)
    return tuple(levels)
