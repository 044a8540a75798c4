"""A result never outlives the code that made it (issue 13): every cache keys on the code fingerprint.

Each test reproduces one observed case: an edit of a training module, an HJ module or a data generator
makes the next build give what a fresh build gives; fewer epochs give the shorter model; re-saving a
model gives the same bytes; a smoke data/ is refused by the default pipeline; two concurrent builds
never corrupt one folder. Code edits are made in a copy of the package (a subprocess runs the copy, or
the fingerprint is pointed at it), never in the checkout.
"""

from __future__ import annotations

import dataclasses
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
import torch

from navlab.core import fingerprint
from navlab.core.fingerprint import LIB, code_fingerprint, imported_modules
from navlab.core.io import DataError, folder_lock
from navlab.pacer.train import PhaseRun, train_phase
from navlab.pipeline import dataset

TESTS = Path(__file__).resolve().parent


def copy_lib(tmp_path: Path, edit: str | None = None, old: str = "", new: str = "") -> Path:
    """A copy of lib/ with ``old`` replaced by ``new`` in module file ``edit`` (must occur)."""
    lib = tmp_path / "lib"
    shutil.copytree(LIB / "navlab", lib / "navlab", ignore=shutil.ignore_patterns("__pycache__"))
    if edit:
        path = lib / edit
        text = path.read_text()
        assert old in text, f"{edit}: {old!r} not found (test out of date)"
        path.write_text(text.replace(old, new, 1))
    return lib


def run_copy(lib: Path, script: str, cwd: Path) -> str:
    """Run ``script`` on the package copy ``lib``, in ``cwd`` (given this checkout's params.yaml)."""
    shutil.copy(LIB.parent / "params.yaml", cwd / "params.yaml")
    env = {"PYTHONPATH": f"{lib}:{TESTS}", "PATH": str(Path(sys.executable).parent), "OMP_NUM_THREADS": "1",
           "HOME": str(Path.home())}
    proc = subprocess.run([sys.executable, "-c", textwrap.dedent(script)], cwd=cwd, env=env, capture_output=True,
                          text=True, check=False)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return proc.stdout


# --- the fingerprint itself ---------------------------------------------------------------------------------


def test_module_set_follows_imports_including_those_inside_functions():
    modules = imported_modules("navlab.hj.grids")
    assert "navlab.hj.reachability" in modules  # imported inside a function of grids
    assert "navlab.maps.rooms" in modules and "navlab.reach" in modules  # a dependency and a package __init__
    assert not any(m.startswith(("navlab.pacer", "navlab.surenav")) for m in modules)


def test_fingerprint_changes_with_the_source_it_runs_and_only_that(tmp_path):
    lib = copy_lib(tmp_path, "navlab/hj/reachability.py",
                   "collision_radius, backend.device, backend.dtype)",
                   "2 * collision_radius, backend.device, backend.dtype)")
    assert code_fingerprint("navlab.hj.grids", lib=lib) != code_fingerprint("navlab.hj.grids")
    assert code_fingerprint("navlab.pacer.artifacts", lib=lib) == code_fingerprint("navlab.pacer.artifacts")
    with pytest.raises(ValueError, match="no such navlab module"):
        code_fingerprint("navlab.no_such_module")


def test_a_new_field_in_one_params_section_leaves_other_results_current(tmp_path):
    """The section declarations compute nothing (results key on the values they read): a PACER field must
    not re-solve the HJ grids; an edit of the loader (profile resolution) still does."""
    field = copy_lib(tmp_path / "field", "navlab/core/params/pacer.py", "@section",
                     "# a new field\n@section")
    assert code_fingerprint("navlab.hj.grids", lib=field) == code_fingerprint("navlab.hj.grids")
    loader = copy_lib(tmp_path / "loader", "navlab/core/params/__init__.py", "tree.get(profile, tree[\"default\"])",
                      "tree.get(profile) or tree[\"default\"]")
    assert code_fingerprint("navlab.hj.grids", lib=loader) != code_fingerprint("navlab.hj.grids")


# --- PACER training ------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def pacer_smoke():
    from navlab.core.params import load_params

    p = load_params("smoke").pacer
    return p.model, dataclasses.replace(p.train, examples_per_epoch=8, batch_size=4, threads=1, select_on="val_loss")


def _train(cfg, out, epochs, **kw):
    from test_pacer_model import TinyTerrainSet

    model, train = cfg
    return train_phase(model, train, [TinyTerrainSet(16)], [TinyTerrainSet(4, seed=1)], out, PhaseRun("phase1",
                       epochs=epochs, seed=0), progress=False, **kw)


def test_fewer_epochs_give_the_shorter_model_and_resaving_gives_the_same_bytes(pacer_smoke, tmp_path):
    long = _train(pacer_smoke, tmp_path / "run", epochs=2)
    long_bytes = long.read_bytes()
    assert _train(pacer_smoke, tmp_path / "run", epochs=2).read_bytes() == long_bytes  # finished: same bytes
    short = _train(pacer_smoke, tmp_path / "run", epochs=1)  # 2 -> 1 epochs: not the 2-epoch model
    fresh = _train(pacer_smoke, tmp_path / "fresh", epochs=1)
    assert short.read_bytes() == fresh.read_bytes() != long_bytes
    assert torch.load(short, weights_only=False)["epochs"] == 1


def test_corrupt_checkpoint_is_discarded_with_a_warning(pacer_smoke, tmp_path):
    fresh = _train(pacer_smoke, tmp_path / "fresh", epochs=1)
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "checkpoint.pt").write_bytes(b"PK\x03\x04 truncated")
    with pytest.warns(UserWarning, match=r"checkpoint\.pt.*discarded it, training starts over"):
        again = _train(pacer_smoke, tmp_path / "run", epochs=1)
    assert again.read_bytes() == fresh.read_bytes()


def test_edited_training_code_retrains_instead_of_resuming(pacer_smoke, tmp_path):
    old = _train(pacer_smoke, tmp_path / "run", epochs=1).read_bytes()
    lib = copy_lib(tmp_path, "navlab/pacer/loss.py", "return inside.sum()", "return 100.0 * inside.sum()")
    script = """
        import dataclasses
        from navlab.core.params import load_params
        from navlab.pacer.train import PhaseRun, train_phase
        from test_pacer_model import TinyTerrainSet
        p = load_params("smoke").pacer
        train = dataclasses.replace(p.train, examples_per_epoch=8, batch_size=4, threads=1, select_on="val_loss")
        for out in ("run", "fresh"):
            train_phase(p.model, train, [TinyTerrainSet(16)], [TinyTerrainSet(4, seed=1)], out, PhaseRun("phase1",
                        epochs=1, seed=0), progress=False)
    """
    run_copy(lib, script, tmp_path)
    rebuilt = (tmp_path / "run" / "model.pt").read_bytes()
    assert rebuilt == (tmp_path / "fresh" / "model.pt").read_bytes()  # what a fresh build gives
    assert rebuilt != old  # the loss edit changed the weights, so the old model was not kept


def test_a_data_parameter_or_street_map_change_retrains_a_phase_instead_of_resuming(tmp_path):
    """DVC re-runs a phase when pacer.data or data/ changes, and the phases' outputs persist: the checkpoint
    must key on what the datasets read, or the re-run resumes the finished run and returns its weights."""
    from navlab.core.params import load_params
    from navlab.pacer.artifacts import phase_inputs
    from navlab.pacer.terrain import listed_photos
    from navlab.pacer.train import run_key

    data = tmp_path / "data"
    base = load_params("default")
    listed = [source for _, source in listed_photos(base.pacer.data)]
    for path, text in (*((f"raw/terrain/{src}", src) for src in listed), ("raw/terrain/unlisted.png", "u"),
                       ("surenav/maps/train/m0.npz", "m"), ("surenav/maps/val/m1.npz", "v"),
                       ("surenav/maps/test/m2.npz", "t")):
        (data / path).parent.mkdir(parents=True, exist_ok=True)
        (data / path).write_text(text)
    streets = base.pacer.data.layout.street_windows
    assert streets > 0

    def with_data(**change):
        layout = dataclasses.replace(base.pacer.data.layout, **change.pop("layout", {}))
        pacer_data = dataclasses.replace(base.pacer.data, layout=layout, **change)
        return dataclasses.replace(base, pacer=dataclasses.replace(base.pacer, data=pacer_data))

    def key(params):
        p = params.pacer
        return run_key(p.model, p.train, seed=p.seed, phase="phase1", epochs=1, sizes=[1], init_from=None,
                       code="c", inputs=phase_inputs(params, data))

    first = key(base)
    assert key(with_data()) == first  # the same data: the finished run resumes
    assert key(with_data(layout={"street_windows": streets / 2})) != first
    assert key(with_data(n_pairs=base.pacer.data.n_pairs + 1)) != first
    (data / "surenav/maps/train/m0.npz").write_text("edited")
    assert key(base) != first  # the street maps training windows are cut from
    edited = key(base)
    (data / "surenav/maps/test/m2.npz").write_text("edited")
    assert key(base) == edited  # the test tiles (the evaluation maps) are never cut into training items
    no_streets = with_data(layout={"street_windows": 0.0})
    before = key(no_streets)
    (data / "surenav/maps/train/m0.npz").write_text("edited again")
    assert key(no_streets) == before  # without street windows the maps are not read
    (data / "raw/terrain/unlisted.png").write_text("a photograph no class lists")
    assert key(no_streets) == before
    (data / "raw/terrain" / listed[0]).write_text("another photograph under the same name")
    assert key(no_streets) != before


# --- HJ grids --------------------------------------------------------------------------------------------------


def test_edited_hj_module_rebuilds_the_grids(smoke_params, tmp_path):
    from navlab.hj.grids import build_hj_grids, grid_path

    build_hj_grids(smoke_params, None, tmp_path / "run", progress=False, log=lambda m: None)
    old = grid_path(tmp_path / "run", "human_brt").read_bytes()
    lib = copy_lib(tmp_path, "navlab/hj/reachability.py",
                   "collision_radius, backend.device, backend.dtype)",
                   "2 * collision_radius, backend.device, backend.dtype)")
    run_copy(lib, """
        from navlab.core.params import load_params
        from navlab.hj.grids import build_hj_grids
        for out in ("run", "fresh"):
            build_hj_grids(load_params("smoke"), None, out, progress=False, log=lambda m: None)
    """, tmp_path)
    for name in ("ttr", "human_brt", "map_ttr"):
        rebuilt = grid_path(tmp_path / "run", name).read_bytes()
        assert rebuilt == grid_path(tmp_path / "fresh", name).read_bytes(), name
    assert grid_path(tmp_path / "run", "human_brt").read_bytes() != old


def test_corrupt_grid_of_the_right_size_is_rebuilt(smoke_params, tmp_path):
    from navlab.hj.grids import build_hj_grids, grid_path, load_human_brt

    build_hj_grids(smoke_params, None, tmp_path, progress=False, log=lambda m: None)
    path = grid_path(tmp_path, "human_brt")
    good = path.read_bytes()
    path.write_bytes(good[:-8] + b"\x00" * 8)
    with pytest.raises(DataError, match="corrupt.*--only hj_grids"):
        load_human_brt(smoke_params, tmp_path)
    messages = []
    build_hj_grids(smoke_params, None, tmp_path, progress=False, log=messages.append)
    assert path.read_bytes() == good and any("human_brt" in m and "solved" in m for m in messages)


# --- data build ------------------------------------------------------------------------------------------------


def _toy_steps(behaviour: dict[str, str]):
    """Two steps that claim real generator modules, so their stamps key on those modules' source."""

    def raw(params, out):
        (out / "raw.txt").write_text(behaviour["raw"])

    def maps(params, out):
        (out / "maps.txt").write_text(behaviour["maps"] + (out / "raw.txt").read_text())

    raw.__module__, maps.__module__ = "navlab.pipeline.sources", "navlab.maps.dataset"
    return [("raw", raw), ("maps", maps)]


def test_data_build_resumed_under_edited_generator_redoes_what_it_makes(smoke_params, tmp_path, monkeypatch):
    class Killed(Exception):
        pass

    def killed(params, out):
        raise Killed

    killed.__module__ = "navlab.surenav.experts.store"
    old = {"raw": "r", "maps": "old maps "}
    with pytest.raises(Killed):
        dataset.build(tmp_path / "data", smoke_params, [*_toy_steps(old), ("demos", killed)], log=lambda m: None)
    # the maps generator is edited (its source in a copy of the package, its behaviour in the step)
    lib = copy_lib(tmp_path / "edited", "navlab/maps/dataset.py", '"""', '"""edited. ')
    monkeypatch.setattr(fingerprint, "LIB", lib)
    new = {"raw": "r", "maps": "new maps "}
    logs = []
    dataset.build(tmp_path / "data", smoke_params, _toy_steps(new), log=logs.append)
    assert any("raw: already built" in m for m in logs) and not any("maps: already built" in m for m in logs)
    fresh = dataset.build(tmp_path / "fresh", smoke_params, _toy_steps(new), log=lambda m: None)
    assert (tmp_path / "data" / "maps.txt").read_text() == (fresh / "maps.txt").read_text() == "new maps r"


def test_smoke_snapshot_is_refused_by_the_default_pipeline(smoke_params, tmp_path):
    from navlab.core.params import load_params

    steps = _toy_steps({"raw": "r", "maps": "m"})
    data = dataset.build(tmp_path / "data", smoke_params, steps, log=lambda m: None)
    assert dataset.check(data, smoke_params, steps)[0]
    ok, msg = dataset.check(data, load_params("default"), steps)
    assert not ok and "'smoke' profile" in msg and "data build --profile default --force" in msg
    dataset.record_path(data).unlink()
    ok, msg = dataset.check(data, smoke_params, steps)
    assert not ok and "no readable build record" in msg


def test_data_snapshot_built_by_older_code_is_refused(smoke_params, tmp_path, monkeypatch):
    steps = _toy_steps({"raw": "r", "maps": "m"})
    data = dataset.build(tmp_path / "data", smoke_params, steps, log=lambda m: None)
    monkeypatch.setattr(fingerprint, "LIB", copy_lib(tmp_path, "navlab/maps/dataset.py", '"""', '"""edited. '))
    ok, msg = dataset.check(data, smoke_params, steps)
    assert not ok and "older generator code" in msg and "--force" in msg


def test_a_second_build_of_the_same_folder_refuses_and_leaves_the_first_whole(smoke_params, tmp_path):
    steps = _toy_steps({"raw": "r", "maps": "m"})
    with folder_lock(tmp_path / "data.lock", "data/"):  # a first build is running
        with pytest.raises(DataError, match=r"being built by pid \d+.*wait for it"):
            dataset.build(tmp_path / "data", smoke_params, steps, log=lambda m: None)
        assert not (tmp_path / "data.partial").exists()
    data = dataset.build(tmp_path / "data", smoke_params, steps, log=lambda m: None)
    assert sorted(p.name for p in data.iterdir()) == ["maps.txt", "raw.txt"]


def test_cli_build_while_another_holds_the_folder_stops_with_one_line(tmp_path):
    out = tmp_path / "data"
    cmd = [sys.executable, "-m", "navlab", "data", "build", "--profile", "smoke", "--data-dir", str(out)]
    with folder_lock(tmp_path / "data.lock", "data/"):  # the first build, still running
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "being built by pid" in proc.stderr
    assert not out.exists() and not (tmp_path / "data.partial").exists()
