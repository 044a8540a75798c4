"""The dataset snapshot is deterministic, checked against its pinned hashes, and reported clearly."""

import pytest

from navlab.pipeline.steps import data_steps
from navlab.core.io import DataError, require
from navlab.pipeline import dataset, sources


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
