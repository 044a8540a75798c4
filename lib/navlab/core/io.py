"""File I/O that is atomic and byte-deterministic.

Atomic: write to a temporary file beside the target, then rename, so a killed run never leaves a
half-written file under the real name. Deterministic: archives carry no timestamps, so rebuilding
data/ on another machine gives the same bytes.
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import io
import json
import os
import tempfile
import zipfile
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

_EPOCH = (1980, 1, 1, 0, 0, 0)


DATA_BUILD_COMMAND = "python -m navlab data build"
BUILD_STAMPS = ".steps"  # hidden folder of a data build's resume stamps inside data.partial/, removed at the end


class DataError(RuntimeError):
    """A missing, unreadable or stale input; the message names the file and the command that fixes it."""


def require(data_dir: str | Path, *parts: str) -> Path:
    """A path inside data/ that must exist; otherwise a DataError that says which command builds it."""
    path = Path(data_dir, *parts)
    if not path.exists():
        raise DataError(f"{path} is missing: build the dataset with `{DATA_BUILD_COMMAND}` (or `make repro`)")
    return path


def cache_dir() -> Path:
    """Where package downloads are cached (``$NAVLAB_CACHE``, default ``~/.cache/navlab``)."""
    return Path(os.environ.get("NAVLAB_CACHE", Path.home() / ".cache" / "navlab")) / "packages"


def _naming(err: OSError, target: Path) -> OSError:
    """``err`` naming ``target`` when it names no file or our temporary one (meaningless to the user).

    Why: a full disk fails the write itself, whose OSError carries no file name, and a read-only folder
    fails the temporary file; the one-line error (cli.main) must name the file that was being written.
    """
    name = Path(os.fsdecode(err.filename)) if isinstance(err.filename, str | bytes | os.PathLike) else None
    ours = err.filename is None or (name is not None and name.parent == target.parent
                                    and name.name.startswith(f".{target.name}."))
    if not ours or err.errno is None:
        return err
    return OSError(err.errno, err.strerror, str(target))


@contextlib.contextmanager
def atomic_path(target: str | Path, suffix: str = "") -> Iterator[Path]:
    """Yield a temporary path beside ``target``; on success it is renamed to ``target``, else removed.

    An OSError on the way (a full disk, a read-only folder) names ``target``, never the temporary file.
    """
    target, tmp = Path(target), None
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=suffix or target.suffix)
        os.close(fd)
        tmp = Path(name)
        yield tmp
        os.replace(tmp, target)
    except OSError as err:
        renamed = _naming(err, target)
        if renamed is err:
            raise
        raise renamed from err
    finally:
        if tmp is not None:
            tmp.unlink(missing_ok=True)


def write_bytes(target: str | Path, data: bytes) -> None:
    with atomic_path(target) as tmp:
        tmp.write_bytes(data)


def write_text(target: str | Path, text: str) -> None:
    write_bytes(target, text.encode())


def write_json(target: str | Path, obj: Any) -> None:
    """Pretty, key-sorted JSON with a trailing newline (stable diffs)."""
    write_text(target, json.dumps(obj, indent=2, sort_keys=True, allow_nan=False) + "\n")


def save_npz(target: str | Path, arrays: Mapping[str, np.ndarray], compress: bool = True) -> None:
    """Like ``np.savez_compressed`` but with fixed zip timestamps, so equal arrays give equal bytes."""
    buf = io.BytesIO()
    method = zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED
    with zipfile.ZipFile(buf, "w", compression=method) as zf:
        for name in sorted(arrays):
            member = io.BytesIO()
            np.lib.format.write_array(member, np.require(arrays[name], requirements="C"), allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", date_time=_EPOCH)
            info.compress_type = method
            info.external_attr = 0o644 << 16
            zf.writestr(info, member.getvalue())
    write_bytes(target, buf.getvalue())


def load_npz(path: str | Path, fix: str) -> dict[str, np.ndarray]:
    """Load every array of an .npz; a missing or corrupt file raises DataError naming ``fix``."""
    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path} is missing; {fix}")
    try:
        with np.load(path, allow_pickle=False) as npz:
            return {k: npz[k] for k in npz.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as err:
        raise DataError(f"{path} is unreadable ({err}); {fix}") from None


def sha256_file(path: str | Path, chunk: int = 1 << 20) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        while block := fh.read(chunk):
            digest.update(block)
    return digest.hexdigest()


def sha256_json(obj: Any) -> str:
    """Hash of a JSON-able object in canonical form (for input fingerprints in artefact metadata)."""
    return hashlib.sha256(json.dumps(obj, sort_keys=True, default=str).encode()).hexdigest()


@contextlib.contextmanager
def folder_lock(lock_file: str | Path, what: str) -> Iterator[None]:
    """Hold an exclusive lock on ``lock_file`` while building ``what``; a second builder refuses at once.

    Why: two builds into one folder share its staging area and both end with a rename, which left an
    incomplete snapshot (issue 13). The lock is an OS lock (flock), so a killed build releases it.
    """
    lock_file = Path(lock_file)
    lock_file.parent.mkdir(parents=True, exist_ok=True)
    with open(lock_file, "a+") as fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            fh.seek(0)
            holder = fh.read().strip() or "another process"
            raise DataError(f"{what} is being built by {holder} (lock {lock_file}); wait for it to finish, "
                            "then run the command again") from None
        fh.seek(0)
        fh.truncate()
        fh.write(f"pid {os.getpid()}")
        fh.flush()
        try:
            yield
        finally:
            fh.seek(0)
            fh.truncate()
            fcntl.flock(fh, fcntl.LOCK_UN)


def read_index(path: str | Path) -> Any:
    """A data index (``index.json``); a truncated or corrupt one is a DataError naming the rebuild."""
    try:
        return json.loads(Path(path).read_text())
    except ValueError as err:
        raise DataError(f"{path} is unreadable ({err}); rebuild the dataset with `{DATA_BUILD_COMMAND} --force`") \
            from None
