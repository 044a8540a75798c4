"""The dataset snapshot in data/: built by steps, staged, renamed into place, checked against data.dvc.

A build writes into ``data.partial/``; each finished step leaves a stamp there, so a killed build
resumes where it stopped. Only a complete build is renamed to ``data/``. The digest is DVC's own
directory hash (dvc-data), so ``data verify`` agrees with what ``dvc add`` recorded in data.dvc.
"""

from __future__ import annotations

import shutil
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import yaml

from navlab.core.io import DATA_BUILD_COMMAND as BUILD_COMMAND
from navlab.core.io import sha256_json, write_text
from navlab.core.params import Params

Step = tuple[str, Callable[[Params, Path], None]]
RECORDED_PROFILE = "default"


def digest(data_dir: str | Path) -> str:
    """DVC's md5 directory hash of ``data_dir`` (the ``md5:`` value ``dvc add`` writes)."""
    from dvc_data.hashfile.build import build
    from dvc_data.hashfile.db.local import LocalHashFileDB
    from dvc_objects.fs.local import LocalFileSystem

    fs = LocalFileSystem()
    with tempfile.TemporaryDirectory() as tmp:
        _, _, obj = build(LocalHashFileDB(fs, tmp), str(data_dir), fs, "md5")
    return obj.hash_info.value


def recorded_digest(dvc_file: str | Path) -> str | None:
    """The md5 that data.dvc records, or None when there is no data.dvc yet."""
    dvc_file = Path(dvc_file)
    if not dvc_file.is_file():
        return None
    outs = (yaml.safe_load(dvc_file.read_text()) or {}).get("outs") or [{}]
    return outs[0].get("md5")


def verify(data_dir: str | Path, dvc_file: str | Path) -> tuple[bool, str]:
    """(matches, one-line explanation) for ``data_dir`` against ``dvc_file``."""
    data_dir = Path(data_dir)
    if not data_dir.is_dir():
        return False, f"{data_dir}/ does not exist; build it with `{BUILD_COMMAND}`"
    want = recorded_digest(dvc_file)
    if want is None:
        return False, f"{dvc_file} is missing; record the snapshot with `{BUILD_COMMAND} --record`"
    got = digest(data_dir)
    if got == want:
        return True, f"{data_dir}/ matches {dvc_file} ({got})"
    return False, (f"{data_dir}/ differs from {dvc_file}: digest {got}, recorded {want}; rebuild with "
                   f"`{BUILD_COMMAND} --force`, or if the builder changed on purpose, `{BUILD_COMMAND} --record`")


def build(data_dir: str | Path, params: Params, steps: Sequence[Step], log: Callable[[str], None] = print) -> Path:
    """Run ``steps`` into ``<data_dir>.partial`` (resuming finished ones), then rename it to ``data_dir``."""
    data_dir = Path(data_dir)
    partial = data_dir.with_name(data_dir.name + ".partial")
    stamps = partial / ".steps"
    stamps.mkdir(parents=True, exist_ok=True)
    for name, step in steps:
        # all of params, not only `data`: a step may read other sections too (demos read surenav.graph)
        fingerprint = sha256_json({"params": params, "step": name})
        stamp = stamps / f"{name}.done"
        if stamp.is_file() and stamp.read_text() == fingerprint:
            log(f"[data] {name}: already built in {partial} (resuming)")
            continue
        start = time.perf_counter()
        log(f"[data] {name}: building …")
        step(params, partial)
        write_text(stamp, fingerprint)
        log(f"[data] {name}: done in {time.perf_counter() - start:.1f} s")
    shutil.rmtree(stamps)
    if data_dir.exists():
        shutil.rmtree(data_dir)
    partial.rename(data_dir)
    return data_dir
