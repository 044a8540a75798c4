"""Bad input found in the issue-13 trial: each stops with one clear line naming the thing and the fix."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import torch

from navlab.core.io import DataError
from navlab.core.params import ParamsError, load_params
from navlab.pacer.train import load_model
from navlab.reach.grid import Grid
from navlab.reach.lookup import interpolate, interpolate_torch
from navlab.search.grid_astar import plan

GRID = Grid((0.0, 0.0), (1.0, 1.0), (5, 5), (False, False))


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_hj_lookup_of_a_non_finite_state_raises(bad):
    values = np.zeros(GRID.shape)
    with pytest.raises(ValueError, match="NaN or inf"):
        interpolate(values, GRID, np.array([[0.5, bad]]))
    with pytest.raises(ValueError, match="NaN or inf"):
        interpolate_torch(torch.zeros(GRID.shape), GRID, torch.tensor([[bad, 0.5]]))


@pytest.mark.parametrize("resolution", [0.0, -1.0, math.nan, math.inf])
def test_grid_astar_refuses_a_bad_resolution(resolution):
    with pytest.raises(ValueError, match=r"resolution = .*cell size in metres"):
        plan(np.ones((4, 4)), (0, 0), (3, 3), resolution=resolution)


@pytest.mark.parametrize("edit, message", [
    (("lr: {smoke: 0.003", "lr: {smoke: .nan"), "pacer.train.lr = nan: expected a finite number"),
    (("cfl: 0.75", "cfl: .inf"), "hj.grids.solver.cfl = inf: expected a finite number"),
    (("  train:\n    device: {smoke: cpu", "  train:\n    device: {smoke: cpuu"), "pacer.train.device = 'cpuu'"),
])
def test_params_refuse_non_finite_numbers_and_unknown_devices(tmp_path, edit, message):
    text = Path("params.yaml").read_text()
    assert edit[0] in text
    path = tmp_path / "params.yaml"
    path.write_text(text.replace(edit[0], edit[1], 1))
    with pytest.raises(ParamsError, match=message.replace("(", r"\(").replace("[", r"\[")):
        load_params("smoke", path)


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04 truncated zip", b"not a torch file at all"])
def test_unreadable_phase_model_names_the_file_and_the_stage(tmp_path, content):
    path = tmp_path / "phase1" / "model.pt"
    path.parent.mkdir()
    path.write_bytes(content)
    with pytest.raises(DataError, match=r"model\.pt is unreadable.*--only pacer_phase1"):
        load_model(path)


def test_missing_phase_model_names_the_stage(tmp_path):
    with pytest.raises(DataError, match=r"missing.*--only pacer_phase2"):
        load_model(tmp_path / "phase2" / "model.pt")


def test_mismatched_phase_model_names_the_file(tmp_path):
    path = tmp_path / "phase3" / "model.pt"
    path.parent.mkdir()
    torch.save({"model_config": {}, "context_pairs": 3, "weights": {}}, path)
    with pytest.raises(DataError, match=r"does not hold a network this code can load.*--only pacer_phase3"):
        load_model(path)


def test_truncated_terrain_photo_is_refused(tmp_path):
    import cv2

    from navlab.pacer.terrain import _read_photo

    path = tmp_path / "photo.jpg"
    cv2.imwrite(str(path), np.full((64, 64, 3), 120, np.uint8))
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    with pytest.raises(DataError, match="not a readable image.*data build --force"):
        _read_photo(str(path))


def test_an_empty_terrain_photo_is_refused(tmp_path):
    from navlab.pacer.terrain import _read_photo

    path = tmp_path / "empty.jpg"
    path.write_bytes(b"")
    with pytest.raises(DataError, match=r"empty.jpg: not a readable image \(the file is empty\)"):
        _read_photo(str(path))


def test_a_jpeg_with_zeroed_bytes_is_refused_with_the_decoders_warning(tmp_path):
    """A quarter of a JPEG's bytes zeroed, same size, end marker intact: libjpeg decodes it around the damage
    and only warns on stderr; the bank refuses it, quoting the warning."""
    import cv2
    import skimage.data

    from navlab.pacer.terrain import _read_photo

    data = bytearray(cv2.imencode(".jpg", skimage.data.astronaut()[:, :, ::-1])[1].tobytes())
    third, quarter = len(data) // 3, len(data) // 4
    data[third:third + quarter] = bytes(quarter)
    path = tmp_path / "zeroed.jpg"
    path.write_bytes(bytes(data))
    with pytest.raises(DataError, match=r"zeroed.jpg: not a readable image \(the decoder warns: Corrupt JPEG data"):
        _read_photo(str(path))


@pytest.mark.parametrize("suffix", [".jpg", ".png"])
def test_terrain_photo_with_data_after_its_end_is_read(tmp_path, suffix):
    """Phones append a motion-photo video or maker data after a JPEG's end: a JPEG or PNG whose image is
    complete is read, pixel for pixel as without the trailer; the same photograph cut short inside its image
    data is refused, with Pillow's reason (OpenCV alone would pad it with grey)."""
    import cv2

    from navlab.pacer.terrain import _read_photo

    pixels = np.random.default_rng(0).integers(0, 256, (48, 192, 3), dtype=np.uint8)
    plain, trailer, cut = (tmp_path / f"{name}{suffix}" for name in ("plain", "trailer", "cut"))
    cv2.imwrite(str(plain), pixels)
    data = plain.read_bytes()
    trailer.write_bytes(data + b"\x00\x00\x00\x18ftypmp42" + bytes(4096))
    cut.write_bytes(data[: len(data) * 3 // 4])
    np.testing.assert_array_equal(_read_photo(str(trailer)), _read_photo(str(plain)))
    with pytest.raises(DataError, match=r"not a readable image \(Pillow: .*truncated"):
        _read_photo(str(cut))


def test_oversized_terrain_photo_is_refused_before_decoding(tmp_path):
    """A PNG whose header declares 20000 x 10000 px (Pillow's decompression-bomb limit) is refused at its
    header, with the fix, never decoded into 2.4 GB of float pixels."""
    import struct
    import zlib

    from navlab.pacer.terrain import _read_photo

    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", 20000, 10000, 8, 2, 0, 0, 0)
    path = tmp_path / "huge.png"
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"\0" * 64))
                     + chunk(b"IEND", b""))
    with pytest.raises(DataError, match=r"huge.png: not a readable image \(.*200000000 pixels.*; resize it"):
        _read_photo(str(path))


@pytest.mark.parametrize("content, message", [
    (None, "is a folder; name the params.yaml file in it"),
    (bytes(range(128, 256)) * 4, "is not a text file (not UTF-8); give a params.yaml"),
])
def test_params_check_names_a_params_path_that_is_no_text_file(tmp_path, content, message, capsys):
    from navlab.cli import main

    path = tmp_path / "params.yaml"
    path.mkdir() if content is None else path.write_bytes(content)
    with pytest.raises(SystemExit) as stop:
        main(["params", "check", "--params", str(path)])
    assert stop.value.code == 2
    assert f"error: argument --params: {path} {message}" in capsys.readouterr().err


@pytest.mark.parametrize("args, message", [
    (["notebook", "run", "notebooks/no_such.ipynb"], "no such notebook"),
    (["notebook", "run", "README.md"], "no such notebook"),
    (["reports", "index", "--reports-dir", "reprots"], "reprots/ does not exist"),
])
def test_cli_bad_paths_are_one_line_errors(args, message, capsys):
    from navlab.cli import main

    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert not Path("reprots").exists()


# --- HJ solver probed with degenerate arguments ------------------------------------------------------------


def _car(**kw):
    from navlab.reach.dynamics import DubinsCar4D

    return DubinsCar4D(**{"v_max": 1.0, "a_min": -0.5, "a_max": 0.5, "omega_max": 1.0, **kw})


@pytest.mark.parametrize("make, message", [
    (lambda: _car(omega_max=math.inf), "every bound must be a finite number"),
    (lambda: _car(v_max=math.nan), "every bound must be a finite number"),
    (lambda: Grid((0.0, math.nan), (1.0, 1.0), (5, 5), (False, False)), "bounds must be finite"),
])
def test_hj_degenerate_systems_and_grids_are_refused(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_hj_solver_refuses_an_infinite_horizon_a_short_periodic_axis_and_a_negative_radius():
    from navlab.hj.reachability import disk_signed_distance
    from navlab.reach.settings import SolverSettings
    from navlab.reach.solver import Backend, solve
    from reach_dynamics_support import SingleIntegrator

    grid = Grid((-1.0, -1.0), (1.0, 1.0), (11, 11), (False, False))
    with pytest.raises(ValueError, match="horizon must be a finite number"):
        solve(SingleIntegrator(1.0), grid, disk_signed_distance(grid, 0.5), math.inf,
              backend=Backend(progress=False))
    ring = Grid((-1.0, 0.0), (1.0, 1.0), (11, 2), (False, True))
    with pytest.raises(ValueError, match="periodic axis 1 has 2 nodes.*at least 3 nodes"):
        solve(SingleIntegrator(1.0), ring, disk_signed_distance(ring, 0.5), 0.1, SolverSettings(scheme="weno5"),
              backend=Backend(progress=False))
    with pytest.raises(ValueError, match="disk radius = -0.3"):
        disk_signed_distance(grid, -0.3)


def test_map_ttr_goal_outside_the_room_is_a_params_error(smoke_params):
    import dataclasses

    from navlab.hj.grids import map_ttr_spec

    g = smoke_params.hj.grids
    params = dataclasses.replace(smoke_params, hj=dataclasses.replace(smoke_params.hj, grids=dataclasses.replace(
        g, map_ttr=dataclasses.replace(g.map_ttr, goal_xy=(40.0, 3.2)))))
    with pytest.raises(ParamsError, match=r"map_ttr.goal_xy = \[40.0, 3.2\]: not in the free space"):
        map_ttr_spec(params)


# --- params.yaml ------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("old, new, message", [
    ("  city: helsinki\n", "  city: helsinki\n  city: monaco\n", r"line \d+: .*duplicate key 'city'"),
    ("cfl: 0.75", "cfl: [0.75", r"line \d+: not valid YAML"),
    ("lr: {smoke: 0.003,", "lr: {smoek: 0.003,", "pacer.train.lr: unknown profile 'smoek'"),
    ("cfl: 0.75", "cfl: {smoek: 0.5}", r"hj.grids.solver.cfl = .*unknown: smoek"),
    ("accel_min: -0.5\n      accel_max: 0.5", "accel_min: 0\n      accel_max: 0",
     r"hj.grids.robot.accel_min = 0.0: out of range, allowed between -10.0 and -0.01"),
    ("shape: {smoke: [21, 21, 7], default: [161, 161, 16]", "shape: {smoke: [21, 21, 7, 5], default: [161, 161, 16]",
     r"hj.grids.human_brt.shape = \[21, 21, 7, 5\]: expected a list of 3 items"),
])
def test_params_yaml_mistakes_name_the_line_or_the_profile(tmp_path, old, new, message):
    text = Path("params.yaml").read_text()
    assert old in text
    path = tmp_path / "params.yaml"
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(ParamsError, match=message):
        load_params("smoke", path)


# --- the dataset's indexes ------------------------------------------------------------------------------------


def test_demos_are_read_from_the_index_and_a_bad_index_is_named(smoke_data, tmp_path):
    import shutil

    from navlab.maps.dataset import load_index
    from navlab.surenav.experts import load_demos

    data = tmp_path / "data"
    shutil.copytree(smoke_data, data)
    folder = data / "surenav" / "demos" / "test"
    listed = load_demos(data, "test")
    shutil.copy(next(folder.glob("*.npz")), folder / "stray.npz")
    assert [m.map_name for m in load_demos(data, "test")] == [m.map_name for m in listed]  # a stray file is ignored
    (folder / f"{listed[0].map_name}.npz").unlink()
    with pytest.raises(DataError, match=rf"{listed[0].map_name}\.npz is missing.*data build"):
        load_demos(data, "test")
    index = data / "surenav" / "maps" / "index.json"
    index.write_text(index.read_text()[:20])
    with pytest.raises(DataError, match=r"index\.json is unreadable.*data build --force"):
        load_index(data)


@pytest.mark.parametrize("context_shape, message", [
    ((1, 6, 16, 8), r"takes \(B, 9, 2h, h\), 3 preference pairs"),
    ((1, 9, 16, 16), "two square patches stacked"),
])
def test_pacer_model_names_a_wrong_context(context_shape, message):
    from navlab.pacer.model import build_model

    model = build_model(load_params("smoke").pacer.model, context_pairs=3)
    with pytest.raises(ValueError, match=message):
        model(torch.zeros(1, 3, 32, 32), torch.zeros(context_shape))


@pytest.mark.parametrize("image, context, message", [
    ((2, 3, 32, 32), (1, 9, 16, 8), r"2 image\(s\) but 1 context\(s\): give one context per image"),
    ((1, 3, 32, 32), (1, 9, 64, 32), r"trained on 8-px patches \(pacer.data.patch_size\)"),
    ((1, 1, 32, 32), (1, 9, 16, 8), r"takes \(B, 3, H, W\) BEV images"),
    ("nan", (1, 9, 16, 8), "the image holds NaN or infinite values"),
])
def test_pacer_model_refuses_inputs_it_was_not_built_for(image, context, message):
    """A batch-1 context beside a batch-2 image (torch would broadcast it), a context cut at another patch size
    than the model's, a grey image, a NaN image (a NaN costmap): each one ValueError before any layer runs."""
    from navlab.pacer.model import build_model

    model = build_model(load_params("smoke").pacer.model, context_pairs=3, patch_size=8).eval()
    pixels = torch.full((1, 3, 32, 32), math.nan) if image == "nan" else torch.zeros(image)
    with pytest.raises(ValueError, match=message):
        model(pixels, torch.zeros(context))


def test_failed_notebook_run_keeps_the_executed_notebook(tmp_path):
    import nbformat

    from navlab.pipeline.notebooks import run_notebook

    nb = nbformat.v4.new_notebook(metadata={"kernelspec": {"name": "python3", "language": "python",
                                                          "display_name": "Python 3"}})
    params = nbformat.v4.new_code_cell("profile = 'smoke'\ndata_dir = artifacts_dir = reports_dir = ''")
    params.metadata["tags"] = ["parameters"]
    nb.cells = [params, nbformat.v4.new_code_cell("raise ValueError('boom')")]
    source = tmp_path / "broken.ipynb"
    nbformat.write(nb, source)
    with pytest.raises(DataError, match=r"failed in cell .*ValueError: boom.*broken\.failed\.ipynb"):
        run_notebook(source, profile="smoke", output=tmp_path / "out" / "broken.ipynb", progress=False)
    kept = nbformat.read(tmp_path / "out" / "broken.failed.ipynb", as_version=4)
    assert any(o.get("ename") == "ValueError" for c in kept.cells for o in c.get("outputs", []))
    assert not (tmp_path / "out" / "broken.ipynb").exists()


def test_notebook_run_with_another_profile_keeps_the_tracked_reports(tmp_path, monkeypatch):
    from navlab import cli

    calls = {}
    monkeypatch.setattr("navlab.pipeline.notebooks.run_notebook", lambda nb, **kw: calls.update(kw) or Path("x"))
    cli.main(["notebook", "run", "notebooks/00_quickstart.ipynb", "--profile", "smoke",
              "--artifacts-dir", str(tmp_path)])
    assert calls["reports_dir"] == str(tmp_path / "reports" / "smoke")


# --- SuReNav context artefacts: each names its own stage's rebuild ----------------------------------------------


@pytest.mark.parametrize("content", [b"", b"PK\x03\x04 truncated zip", b"garbage, not a torch file"])
def test_an_unreadable_context_estimator_names_its_stage(tmp_path, content):
    from navlab.surenav.context.training import EstimatorRun, context_model_path, load_context_estimator

    run = EstimatorRun("context", "blackbox")
    path = context_model_path(tmp_path, run, 0)
    path.parent.mkdir(parents=True)
    path.write_bytes(content)
    with pytest.raises(DataError, match=r"model\.pt is unreadable.*--only surenav_context_estimator"):
        load_context_estimator(tmp_path, run, 0)
    torch.save({"weights": {}}, path)  # a torch file, but no estimator
    with pytest.raises(DataError, match=r"does not hold an estimator this code can load.*--only "
                                        r"surenav_context_estimator"):
        load_context_estimator(tmp_path, run, 0)


@pytest.mark.parametrize("index, message", [
    ('{"maps": {"train": [', r"index\.json is unreadable \(not complete JSON\)"),
    ('{"seed": 0}', r"index\.json does not list the tiles of each split \(train, val, test\)"),
    ('{"maps": {"train": [], "val": []}}', r"does not list the tiles of each split"),
])
def test_a_truncated_or_incomplete_context_demos_index_names_its_stage(tmp_path, index, message):
    from navlab.surenav.context.dataset import FOLDER, load_index

    folder = tmp_path.joinpath(*FOLDER)
    folder.mkdir(parents=True)
    (folder / "index.json").write_text(index)
    with pytest.raises(DataError, match=message + r".*--only surenav_context_demos"):
        load_index(tmp_path)


def test_a_truncated_context_demos_tile_names_its_stage(tmp_path):
    from navlab.surenav.context.dataset import FOLDER, load_context_demos

    folder = tmp_path.joinpath(*FOLDER)
    (folder / "test").mkdir(parents=True)
    (folder / "index.json").write_text('{"maps": {"train": [], "val": [], "test": ["t0"]}}')
    np.savez(folder / "test" / "t0.npz", superpixels=np.zeros((2, 2), np.int32))
    (folder / "test" / "t0.map.npz").write_bytes(b"PK\x03\x04 cut short")
    with pytest.raises(DataError, match=r"t0\.map\.npz is unreadable.*--only surenav_context_demos"):
        load_context_demos(tmp_path, "test")

