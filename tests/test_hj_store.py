"""Grid artefacts: round trip, corruption and truncation detected, stale metadata names the stage."""

import json

import numpy as np
import pytest

from navlab.core.io import DataError
from navlab.reach.grid import Grid
from navlab.reach.store import grid_to_dict, is_current, load_grid, save_grid, sidecar_path

GRID = Grid((-1.0, -1.0, 0.0), (1.0, 1.0, 2 * np.pi), (5, 4, 6), (False, False, True))
INPUTS = {"kind": "test", "robot": {"v_max": 1.0}, "solver": {"scheme": "weno5", "cfl": 0.75}}


@pytest.fixture
def stored(tmp_path):
    values = np.random.default_rng(0).normal(size=GRID.shape).astype(np.float32)
    path = save_grid(tmp_path / "v.npy", values, GRID, INPUTS)
    return path, values


def test_round_trip(stored):
    path, values = stored
    got = load_grid(path, INPUTS)
    np.testing.assert_array_equal(got.values, values)
    assert got.grid == GRID and got.values.dtype == np.float32
    assert got.meta["inputs"] == INPUTS and is_current(path, INPUTS)
    assert not list(path.parent.glob(".*"))  # no temporary files left behind


def test_stale_metadata_names_key_and_stage(stored):
    path, _ = stored
    changed = {**INPUTS, "solver": {"scheme": "eno2", "cfl": 0.75}}
    assert not is_current(path, changed)
    with pytest.raises(DataError, match=r"stale.*solver\.scheme.*dvc repro hj_grids.*--only hj_grids"):
        load_grid(path, changed)


def test_corrupt_byte_detected(stored):
    path, _ = stored
    raw = bytearray(path.read_bytes())
    raw[-7] ^= 0xFF
    path.write_bytes(bytes(raw))
    with pytest.raises(DataError, match="corrupt.*dvc repro hj_grids"):
        load_grid(path, INPUTS)


def test_truncation_detected_even_without_checksum(stored):
    path, _ = stored
    path.write_bytes(path.read_bytes()[:-100])
    assert not is_current(path, INPUTS)
    with pytest.raises(DataError, match="truncated"):
        load_grid(path, INPUTS, verify=False)


def test_missing_sidecar_or_file(stored):
    path, _ = stored
    sidecar_path(path).unlink()
    with pytest.raises(DataError, match="missing.*hj_grids"):
        load_grid(path)
    assert not is_current(path, INPUTS)


def test_bad_sidecar_and_bad_values(stored, tmp_path):
    path, values = stored
    sidecar_path(path).write_text("{not json")
    with pytest.raises(DataError, match="unreadable"):
        load_grid(path)
    with pytest.raises(ValueError, match="NaN"):
        save_grid(tmp_path / "w.npy", np.full(GRID.shape, np.nan), GRID, INPUTS)
    with pytest.raises(ValueError, match="do not match grid"):
        save_grid(tmp_path / "w.npy", values[:2], GRID, INPUTS)


def test_sidecar_is_plain_json_with_checksum(stored):
    path, _ = stored
    meta = json.loads(sidecar_path(path).read_text())
    assert len(meta["sha256"]) == 64 and meta["nbytes"] == path.stat().st_size
    assert meta["grid"]["shape"] == [5, 4, 6] and meta["grid"]["periodic"] == [False, False, True]


@pytest.mark.parametrize("edit", [("lo", [-1.0, -0.9, 0.0]), ("shape", [4, 5, 6]), ("periodic", [False, True, True])])
def test_edited_sidecar_grid_is_stale(tmp_path, edit):
    """The inputs (and their hash) record the grid, but the loader places the values on the sidecar's own
    ``grid``: an edited one must not load on shifted coordinates while the hash still matches."""
    inputs = {**INPUTS, "grid": grid_to_dict(GRID)}
    path = save_grid(tmp_path / "v.npy", np.zeros(GRID.shape, np.float32), GRID, inputs)
    meta = json.loads(sidecar_path(path).read_text())
    meta["grid"][edit[0]] = edit[1]
    sidecar_path(path).write_text(json.dumps(meta))
    assert not is_current(path, inputs)  # so `dvc repro hj_grids` rebuilds it
    for expected in (inputs, None):  # checked against the caller's inputs, else the recorded ones
        with pytest.raises(DataError, match=rf"stale: its sidecar's grid \(grid\.{edit[0]}\).*dvc repro hj_grids"):
            load_grid(path, expected)
