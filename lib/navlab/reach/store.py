"""Value-function grids on disk: a raw ``.npy`` array plus a JSON sidecar (metadata and sha256).

Why this format: the paper-size grids are 1.2-1.4 GB. A raw ``.npy`` is written in one sequential pass
and opened with ``np.load(mmap_mode="r")`` without copying, so a lookup touches only the pages it reads;
compressed ``.npz`` would cost minutes of deflate per build and a full decompression on every load, and
gains little on smooth float fields. The sidecar carries the sha256 of the ``.npy`` bytes (a truncated or
corrupted file is detected, never used, and rebuilt by the next build) and the ``inputs`` the grid was
built from, which include the code fingerprint of the modules that solve it (``navlab.core.fingerprint``):
a loader compares them with what params.yaml and the current code ask for and names the DVC stage to
re-run when they disagree. No hand-bumped format version: a change of code is a change of inputs.

Both files are written atomically (temporary file, then rename); the sidecar is written last and is the
commit record: a ``.npy`` without a matching sidecar is treated as missing.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from navlab.core.io import DataError, atomic_path, sha256_file, sha256_json, write_json
from navlab.reach.grid import Grid

SIDECAR_KEYS = ("file", "sha256", "nbytes", "dtype", "grid", "inputs", "inputs_hash")
REBUILD = "rebuild it with `dvc repro hj_grids` (or `python -m navlab artifacts build --only hj_grids`)"


def grid_to_dict(grid: Grid) -> dict[str, Any]:
    return {"lo": list(grid.lo), "hi": list(grid.hi), "shape": list(grid.shape), "periodic": list(grid.periodic)}


def grid_from_dict(d: dict[str, Any]) -> Grid:
    return Grid(tuple(map(float, d["lo"])), tuple(map(float, d["hi"])), tuple(map(int, d["shape"])),
                tuple(map(bool, d["periodic"])))


@dataclass(frozen=True)
class StoredGrid:
    """A value function on its grid, with the metadata it was built from (``inputs`` + ``inputs_hash``)."""

    values: np.ndarray  # read-only memory map of shape grid.shape
    grid: Grid
    meta: dict[str, Any]


def sidecar_path(path: str | Path) -> Path:
    return Path(path).with_suffix(".json")


def save_grid(path: str | Path, values: np.ndarray, grid: Grid, inputs: dict[str, Any],
              info: dict[str, Any] | None = None) -> Path:
    """Write ``values`` (shape ``grid.shape``) and its sidecar; ``inputs`` is everything it depends on,
    ``info`` what the build observed (solve time, convergence) — recorded, not compared."""
    path = Path(path)
    values = np.ascontiguousarray(values)
    if values.shape != grid.shape:
        raise ValueError(f"{path.name}: values of shape {values.shape} do not match grid {grid.shape}")
    if not np.isfinite(values).all():
        raise ValueError(f"{path.name}: values contain NaN or inf; refusing to store them")
    sidecar_path(path).unlink(missing_ok=True)  # the old record must not vouch for the new array
    with atomic_path(path, suffix=".npy") as tmp:
        with open(tmp, "wb") as fh:
            np.lib.format.write_array(fh, values, allow_pickle=False)
        digest, nbytes = sha256_file(tmp), tmp.stat().st_size
    write_json(sidecar_path(path), {
        "file": path.name,
        "sha256": digest,
        "nbytes": nbytes,
        "dtype": str(values.dtype),
        "grid": grid_to_dict(grid),
        "inputs": _json(inputs),
        "inputs_hash": sha256_json(inputs),
        "info": info or {},
    })
    return path


def _json(tree: Any) -> Any:
    """``tree`` as its JSON round trip (tuples become lists), the form a sidecar stores."""
    return json.loads(json.dumps(tree, default=str))


def read_meta(path: str | Path) -> dict[str, Any]:
    side = sidecar_path(path)
    if not Path(path).is_file() or not side.is_file():
        raise DataError(f"{path} (or its sidecar {side.name}) is missing; {REBUILD}")
    try:
        meta = json.loads(side.read_text())
    except (OSError, ValueError) as err:
        raise DataError(f"{side} is unreadable ({err}); {REBUILD}") from None
    missing = [k for k in SIDECAR_KEYS if k not in meta] if isinstance(meta, dict) else list(SIDECAR_KEYS)
    if missing:
        raise DataError(f"{side} lacks {', '.join(missing)} (written by other code); {REBUILD}")
    return meta


def stale_keys(stored: Any, expected: Any, prefix: str = "") -> list[str]:
    """The dotted keys where two JSON-like trees differ (for a message that says *what* changed)."""
    if isinstance(stored, dict) and isinstance(expected, dict):
        out = []
        for k in sorted(set(stored) | set(expected)):
            out += stale_keys(stored.get(k), expected.get(k), f"{prefix}.{k}" if prefix else str(k))
        return out
    return [] if stored == expected else [prefix or "(root)"]


def _grid_changes(meta: dict[str, Any], json_inputs: dict[str, Any] | None) -> list[str]:
    """Where the sidecar's ``grid`` differs from the grid its inputs (the caller's, else the recorded ones)
    name, as dotted keys ([] when they agree or the inputs name no grid).

    Why: the inputs hash covers ``inputs.grid`` but a loader builds the grid from the sidecar's own ``grid``;
    an edited one put every value on shifted coordinates while the hash still matched."""
    source = meta["inputs"] if json_inputs is None else json_inputs
    expected = source.get("grid") if isinstance(source, dict) else None
    return [] if expected is None else stale_keys(meta["grid"], expected, "grid")


def is_current(path: str | Path, inputs: dict[str, Any]) -> bool:
    """True when an intact file built from exactly ``inputs`` (code fingerprint included) exists.

    The sha256 is checked too (about 1 s per GB), so a corrupt grid of the right size is rebuilt by
    the command that ``load_grid``'s message names instead of being reported "up to date".
    """
    try:
        meta = read_meta(path)
    except DataError:
        return False
    return (meta["inputs_hash"] == sha256_json(inputs) and not _grid_changes(meta, _json(inputs))
            and Path(path).stat().st_size == meta["nbytes"] and sha256_file(path) == meta["sha256"])


def load_grid(path: str | Path, inputs: dict[str, Any] | None = None, verify: bool = True) -> StoredGrid:
    """Open a stored grid read-only (memory-mapped).

    ``inputs``: what the caller's params.yaml implies; a mismatch raises DataError naming the changed
    keys and the stage to re-run. ``verify``: recompute the sha256 (about 1 s per GB); the size is
    always checked, so truncation is caught even with ``verify=False``.
    """
    path = Path(path)
    meta = read_meta(path)
    json_inputs = _json(inputs) if inputs is not None else None
    if json_inputs is not None and meta["inputs_hash"] != sha256_json(inputs):
        changed = stale_keys(meta["inputs"], json_inputs) or ["(inputs)"]
        raise DataError(f"{path} is stale: built with different {', '.join(changed[:5])} than params.yaml "
                        f"asks for; {REBUILD}")
    changed = _grid_changes(meta, json_inputs)
    if changed:
        raise DataError(f"{path} is stale: its sidecar's grid ({', '.join(changed)}) is not the grid it was "
                        f"built for; {REBUILD}")
    size = path.stat().st_size
    if size != meta["nbytes"]:
        raise DataError(f"{path} is truncated or padded ({size} bytes, expected {meta['nbytes']}); {REBUILD}")
    if verify and sha256_file(path) != meta["sha256"]:
        raise DataError(f"{path} is corrupt (sha256 does not match its sidecar); {REBUILD}")
    try:
        values = np.load(path, mmap_mode="r", allow_pickle=False)
    except (OSError, ValueError) as err:
        raise DataError(f"{path} is unreadable ({err}); {REBUILD}") from None
    grid = grid_from_dict(meta["grid"])
    if values.shape != grid.shape or str(values.dtype) != meta["dtype"]:
        raise DataError(f"{path}: array {values.shape} {values.dtype} does not match its sidecar; {REBUILD}")
    return StoredGrid(values, grid, meta)
