"""The dataset snapshot in data/: built by steps, staged, renamed into place, checked against dvc.lock.

A build writes into ``data.partial/``; each finished step leaves a stamp there keyed on the code
fingerprint of the step's modules, the data parameters and the previous step's stamp, so a killed
build resumes where it stopped and a build resumed under edited generator code redoes what that code
makes. Only a complete build is renamed to ``data/``, and ``data.build.json`` beside it records the
profile, generator code and parameters that built it, and the snapshot's content digest: ``data check``
refuses a snapshot of another profile, of older code, or edited after its build (one flipped byte), and
``data build`` (the ``data`` stage of dvc.yaml, after which DVC records data/ in dvc.lock) rebuilds such
a snapshot instead of vouching for it. ``data.lock`` keeps two builds apart. The digest is DVC's own
directory hash (dvc-data), so ``data verify`` agrees with the ``data`` stage's out in dvc.lock. A data/
that is a symlink (the snapshot kept on another disk) is built through the link, beside its target.
"""

from __future__ import annotations

import dataclasses
import json
import shutil
import tempfile
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import yaml

from navlab.core.fingerprint import code_fingerprint
from navlab.core.io import BUILD_STAMPS, folder_lock, sha256_json, write_json, write_text
from navlab.core.io import DATA_BUILD_COMMAND as BUILD_COMMAND
from navlab.core.params import Params

Step = tuple[str, Callable[[Params, Path], None]]
STAGE = "data"  # the dvc.yaml stage whose out is data/
DATA_PARAMS = ("data", "surenav.graph")  # the params.yaml sections the generators read (the stage's params)


def digest(data_dir: str | Path) -> str:
    """DVC's md5 directory hash of ``data_dir`` (the ``md5:`` value dvc.lock records for it)."""
    from dvc_data.hashfile.build import build
    from dvc_data.hashfile.db.local import LocalHashFileDB
    from dvc_objects.fs.local import LocalFileSystem

    fs = LocalFileSystem()
    with tempfile.TemporaryDirectory() as tmp:
        _, _, obj = build(LocalHashFileDB(fs, tmp), str(data_dir), fs, "md5")
    return obj.hash_info.value


def recorded_digest(lock_file: str | Path) -> str | None:
    """The md5 that dvc.lock records for the ``data`` stage's out, or None when nothing is recorded."""
    lock_file = Path(lock_file)
    if not lock_file.is_file():
        return None
    stage = ((yaml.safe_load(lock_file.read_text()) or {}).get("stages") or {}).get(STAGE) or {}
    outs = stage.get("outs") or [{}]
    return outs[0].get("md5")


def verify(data_dir: str | Path, lock_file: str | Path) -> tuple[bool, str]:
    """(matches, one-line explanation) for ``data_dir`` against ``lock_file``."""
    data_dir = Path(data_dir)
    if not data_dir.is_dir():
        return False, f"{data_dir}/ does not exist; build it with `{BUILD_COMMAND}`"
    want = recorded_digest(lock_file)
    if want is None:
        return False, f"{lock_file} records no data/; record the snapshot with `dvc repro data`"
    got = digest(data_dir)
    if got == want:
        return True, f"{data_dir}/ matches {lock_file} ({got})"
    return False, (f"{data_dir}/ differs from {lock_file}: digest {got}, recorded {want}; rebuild with "
                   f"`{BUILD_COMMAND} --force`, or if the builder changed on purpose, `dvc repro data`")


def data_params(params: Params) -> dict[str, Any]:
    """The parameter sections the generators read, as JSON-able dicts."""
    out = {}
    for dotted in DATA_PARAMS:
        section: Any = params
        for part in dotted.split("."):
            section = getattr(section, part)
        out[dotted] = dataclasses.asdict(section)
    return out


def generator_code(steps: Sequence[Step]) -> str:
    """Code fingerprint of every module the steps run."""
    return code_fingerprint(*sorted({fn.__module__ for _, fn in steps}))


def record_path(data_dir: str | Path) -> Path:
    """``data.build.json`` beside ``data/``: what built the snapshot now in data/."""
    data_dir = Path(data_dir)
    return data_dir.with_name(data_dir.name + ".build.json")


def build_record(params: Params, steps: Sequence[Step]) -> dict[str, Any]:
    return {"profile": params.profile, "code": generator_code(steps), "params": sha256_json(data_params(params))}


def check(data_dir: str | Path, params: Params, steps: Sequence[Step]) -> tuple[bool, str]:
    """(usable, one line): was ``data_dir`` built by ``params.profile`` with the current generator code?"""
    data_dir = Path(data_dir)
    fix = f"rebuild it with `{BUILD_COMMAND} --profile {params.profile} --force`"
    if not data_dir.is_dir():
        return False, f"{data_dir}/ does not exist; build it with `{BUILD_COMMAND} --profile {params.profile}`"
    path = record_path(data_dir)
    try:
        built = json.loads(path.read_text())
    except (OSError, ValueError):
        return False, f"{data_dir}/ has no readable build record ({path.name}); {fix}"
    want = build_record(params, steps)
    if built.get("profile") != want["profile"]:
        return False, (f"{data_dir}/ was built with the {built.get('profile')!r} profile but params.yaml asks for "
                       f"{want['profile']!r}; {fix}")
    if built.get("code") != want["code"]:
        return False, f"{data_dir}/ was built by older generator code (maps, demos or sources changed); {fix}"
    if built.get("params") != want["params"]:
        return False, f"{data_dir}/ was built with other {' / '.join(DATA_PARAMS)} parameters; {fix}"
    if built.get("digest") is None:
        return False, f"{data_dir}/ has a build record without its content digest (an older build); {fix}"
    got = digest(data_dir)  # last: the cheap checks first (a default data/ hashes in well under a second)
    if got != built["digest"]:
        return False, (f"{data_dir}/ was changed after its build (digest {got}, built {built['digest']}); "
                       f"{fix}")
    return True, f"{data_dir}/ was built with the {params.profile!r} profile by the current generator code"


def build_target(data_dir: Path) -> Path:
    """The folder a build replaces: ``data_dir`` itself, or where it links to (created if it dangles).

    Why: a data/ symlinked to another disk used to fail after minutes of building, at the final rmtree
    (which refuses a link) or the rename (across file systems); the link itself must stay.
    """
    return data_dir.resolve() if data_dir.is_symlink() else data_dir


def _run_step(step: Callable[[Params, Path], None], params: Params, partial: Path) -> None:
    """Run one step; an OSError that names no file (a full disk on write) is made to name ``partial``."""
    try:
        step(params, partial)
    except OSError as err:
        if err.filename is None and err.errno is not None:
            raise OSError(err.errno, err.strerror, str(partial)) from err
        raise


def build(data_dir: str | Path, params: Params, steps: Sequence[Step], log: Callable[[str], None] = print) -> Path:
    """Run ``steps`` into ``<data_dir>.partial`` (resuming finished ones), then rename it to ``data_dir``.

    Holds ``<data_dir>.lock`` throughout: a second build of the same folder stops with a DataError.
    When ``data_dir`` is a symlink, the partial folder and the lock sit beside its target, which is
    replaced; the link stays. The build record (beside ``data_dir``) ends with the content digest.
    """
    data_dir = Path(data_dir)
    target = build_target(data_dir)
    partial = target.with_name(target.name + ".partial")
    with folder_lock(target.with_name(target.name + ".lock"), f"{data_dir}/"):
        stamps = partial / BUILD_STAMPS
        stamps.mkdir(parents=True, exist_ok=True)
        previous = None
        for name, step in steps:
            key = sha256_json({"params": data_params(params), "step": name, "code": code_fingerprint(step.__module__),
                               "after": previous})
            previous = key
            stamp = stamps / f"{name}.done"
            if stamp.is_file() and stamp.read_text() == key:
                log(f"[data] {name}: already built in {partial} (resuming)")
                continue
            start = time.perf_counter()
            log(f"[data] {name}: building …")
            _run_step(step, params, partial)
            write_text(stamp, key)
            log(f"[data] {name}: done in {time.perf_counter() - start:.1f} s")
        shutil.rmtree(stamps)
        record_path(data_dir).unlink(missing_ok=True)  # the old record must not vouch for the new snapshot
        if target.exists():
            shutil.rmtree(target)
        partial.rename(target)
        write_json(record_path(data_dir), {**build_record(params, steps), "digest": digest(target)})
    return data_dir
