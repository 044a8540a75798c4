"""The dataset snapshot is deterministic, checked against its pinned hashes, and reported clearly."""

import pytest

from navlab.core.io import DataError, require
from navlab.pipeline import dataset, sources
from navlab.pipeline.steps import data_steps


def test_build_twice_gives_same_digest(smoke_data, smoke_params, tmp_path):
    again = dataset.build(tmp_path / "data", smoke_params, data_steps(), log=lambda m: None)
    assert dataset.digest(again) == dataset.digest(smoke_data)


def test_real_inputs_present_and_licensed(smoke_data):
    for src in sources.SOURCES:
        for _, dest, _ in src.files:
            assert (smoke_data / "raw" / dest).stat().st_size > 1000
    text = (smoke_data / "SOURCES.md").read_text()
    for src in sources.SOURCES:
        assert src.package in text and src.version in text


def test_changed_file_is_detected(smoke_data, tmp_path):
    import shutil

    copy = tmp_path / "copy"
    shutil.copytree(smoke_data, copy)
    dvc_file = tmp_path / "dvc.lock"
    dvc_file.write_text(f"stages:\n  data:\n    outs:\n    - md5: {dataset.digest(copy)}\n      path: data\n")
    assert dataset.verify(copy, dvc_file)[0]
    victim = next((copy / "raw" / "osm").iterdir())
    victim.write_bytes(victim.read_bytes()[:-1])
    ok, msg = dataset.verify(copy, dvc_file)
    assert not ok and "differs" in msg and "--force" in msg


def test_pinned_hash_mismatch_is_an_error(tmp_path):
    src = sources.SOURCES[-1]  # the installed scikit-image photos: no download needed
    member, dest, _ = src.files[0]
    bad = sources.Source(src.kind, src.package, src.version, src.licence, src.what, ((member, dest, "0" * 64),))
    with pytest.raises(DataError, match="sha256"):
        sources.extract(bad, tmp_path)
    assert not (tmp_path / dest).exists()


def test_require_names_the_build_command(tmp_path):
    with pytest.raises(DataError, match="python -m navlab data build"):
        require(tmp_path, "raw", "osm")


# --- data check reads the content; a symlinked data/ is built through the link ----------------------------------


def _copy_with_record(data, dest):
    """``data`` and its build record copied to ``dest`` (a folder that may be edited)."""
    import shutil

    shutil.copytree(data, dest)
    shutil.copy(dataset.record_path(data), dataset.record_path(dest))
    return dest


def test_check_refuses_a_flipped_byte(smoke_data, smoke_params, tmp_path):
    import subprocess
    import sys

    copy = _copy_with_record(smoke_data, tmp_path / "data")
    assert dataset.check(copy, smoke_params, data_steps())[0]
    victim = next(p for p in sorted(copy.rglob("*")) if p.is_file() and p.stat().st_size > 100)
    good = victim.read_bytes()
    victim.write_bytes(good[:50] + bytes([good[50] ^ 1]) + good[51:])
    ok, msg = dataset.check(copy, smoke_params, data_steps())
    assert not ok and f"{copy}/ was changed after its build" in msg
    assert "python -m navlab data build --profile smoke --force" in msg and "\n" not in msg
    proc = subprocess.run([sys.executable, "-m", "navlab", "data", "check", "--profile", "smoke", "--data-dir",
                           str(copy)], capture_output=True, text=True, check=False)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "changed after its build" in proc.stderr
    victim.write_bytes(good)
    assert dataset.check(copy, smoke_params, data_steps())[0]


def test_check_refuses_a_record_without_digest(smoke_data, smoke_params, tmp_path):
    import json

    copy = _copy_with_record(smoke_data, tmp_path / "data")
    record = json.loads(dataset.record_path(copy).read_text())
    del record["digest"]
    dataset.record_path(copy).write_text(json.dumps(record))
    ok, msg = dataset.check(copy, smoke_params, data_steps())
    assert not ok and "without its content digest" in msg and "--force" in msg


def _toy_steps(text="r"):
    """One fast step that claims a real generator module (its stamp keys on that module's source)."""

    def raw(params, out):
        (out / "raw.txt").write_text(text)

    raw.__module__ = "navlab.pipeline.sources"
    return [("raw", raw)]


def test_symlinked_data_is_built_through_the_link(smoke_params, tmp_path):
    target, link = tmp_path / "disk" / "navlab-data", tmp_path / "repo" / "data"
    target.mkdir(parents=True)
    (target / "stale.txt").write_text("old snapshot")
    link.parent.mkdir()
    link.symlink_to(target)
    assert dataset.build(link, smoke_params, _toy_steps("new"), log=lambda m: None) == link
    assert link.is_symlink() and link.resolve() == target.resolve()
    assert sorted(p.name for p in target.iterdir()) == ["raw.txt"] and (link / "raw.txt").read_text() == "new"
    assert dataset.check(link, smoke_params, _toy_steps("new"))[0]
    assert sorted(p.name for p in link.parent.iterdir()) == ["data", "data.build.json"]  # no partial beside the link
    assert not (target.parent / "navlab-data.partial").exists()


def test_dangling_data_link_creates_its_target(smoke_params, tmp_path):
    target, link = tmp_path / "disk" / "new" / "navlab-data", tmp_path / "data"
    link.symlink_to(target)
    dataset.build(link, smoke_params, _toy_steps(), log=lambda m: None)
    assert link.is_symlink() and (target / "raw.txt").read_text() == "r"
    assert dataset.check(link, smoke_params, _toy_steps())[0]


# --- a full disk leaves no half-written file, and the error names the file -----------------------------------------


def test_write_that_hits_a_full_disk_leaves_the_old_file_and_names_it(tmp_path, monkeypatch):
    import errno
    from pathlib import Path

    from navlab.core.io import write_json

    target = tmp_path / "report.json"
    target.write_text("old\n")

    def half_then_full(self, data):
        with open(self, "wb") as fh:
            fh.write(data[: len(data) // 2])
        raise OSError(errno.ENOSPC, "No space left on device")  # a failed write() names no file

    monkeypatch.setattr(Path, "write_bytes", half_then_full)
    with pytest.raises(OSError) as err:
        write_json(target, {"numbers": list(range(100))})
    assert err.value.errno == errno.ENOSPC and err.value.filename == str(target)
    assert [p.name for p in tmp_path.iterdir()] == ["report.json"] and target.read_text() == "old\n"


def test_read_only_folder_names_the_target_not_the_temporary_file(tmp_path, monkeypatch):
    import errno

    from navlab.core import io

    def read_only(dir, prefix, suffix):
        raise OSError(errno.EROFS, "Read-only file system", f"{dir}/{prefix}x1y2{suffix}")

    monkeypatch.setattr(io.tempfile, "mkstemp", read_only)
    with pytest.raises(OSError) as err:
        io.write_text(tmp_path / "a.txt", "x")
    assert err.value.errno == errno.EROFS and err.value.filename == str(tmp_path / "a.txt")
    assert not any(tmp_path.iterdir())
