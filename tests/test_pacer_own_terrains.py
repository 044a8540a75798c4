"""PACER on photographs of your own (docs/data.md, "PACER on terrains of your own"): terrains this repository
has never seen, put in the checkout's terrain_photos/ and listed in params.yaml, run through the bank, the
fingerprint trained models key on, the aerial maps and the navigation tables."""

from __future__ import annotations

import hashlib
import re
import shutil

import cv2
import numpy as np
import pytest

from navlab.core.io import DataError
from navlab.core.params import ParamsError, repo_root
from navlab.pacer.aerial import aerial_maps
from navlab.pacer.artifacts import phase_inputs
from navlab.pacer.experiments import navigation_rows, pacer_method, uniform_method, window_oracle_method
from navlab.pacer.profile_check import data_problems as pacer_data_problems
from navlab.pacer.terrain import OWN_PHOTOS, load_terrain_bank, photo_digests, photos_fingerprint
from navlab.pacer.train import load_model
from pacer_support import with_pacer_data

NAMES = ("planks", "cobbles", "moss", "tarmac")


def _rgb(path) -> np.ndarray:
    """float32 RGB in [0, 1] as the bank reads a photograph."""
    return cv2.cvtColor(cv2.imread(str(path)), cv2.COLOR_BGR2RGB).astype(np.float32) / 255.0


def _texture(kind: int, size: int, seed: int) -> np.ndarray:
    """uint8 (size, size, 3) BGR: a seeded procedural surface no package ships (stripes, cells, blotches,
    speckle), each in its own colour."""
    gen = np.random.default_rng(seed)
    y, x = np.mgrid[:size, :size].astype(np.float32)
    noise = gen.normal(size=(size, size)).astype(np.float32)
    base = [np.sin(x / 3.0) + 0.3 * noise,
            ((x // 12 + y // 12) % 2) + 0.2 * noise,
            cv2.GaussianBlur(noise, (0, 0), 6) * 4,
            0.5 * noise][kind]
    shade = (base - base.min()) / (np.ptp(base) + 1e-6)
    colour = np.array([[40, 90, 160], [120, 120, 130], [60, 150, 70], [50, 50, 55]][kind], dtype=np.float32)
    return np.clip(shade[..., None] * colour * 1.5 + 20, 0, 255).astype(np.uint8)


@pytest.fixture
def own_params(tmp_path, monkeypatch, smoke_params):
    """The smoke profile with its unseen group replaced by four generated photographs in a checkout's
    terrain_photos/ (a copy of params.yaml marks tmp_path as the checkout)."""
    shutil.copy(repo_root() / "params.yaml", tmp_path / "params.yaml")
    (tmp_path / OWN_PHOTOS).mkdir()
    for k, name in enumerate(NAMES):
        cv2.imwrite(str(tmp_path / OWN_PHOTOS / f"{name}.png"), _texture(k, 192 + 32 * k, k))
    (tmp_path / "notebooks" / "pacer").mkdir(parents=True)
    monkeypatch.chdir(tmp_path / "notebooks" / "pacer")  # as papermill runs a notebook: the checkout is above
    data = smoke_params.pacer.data
    ordering = (NAMES[3], NAMES[1], *[n for n in data.realistic_ordering if n in data.seen], NAMES[0], NAMES[2])
    return with_pacer_data(smoke_params, unseen={n: (f"{OWN_PHOTOS}/{n}.png",) for n in NAMES},
                           realistic_ordering=ordering)


def test_own_photographs_form_the_unseen_group(own_params, smoke_data, tmp_path):
    bank = load_terrain_bank(smoke_data, own_params.pacer.data)
    unseen = bank.ids("unseen")
    assert bank_names(bank, "unseen") == list(NAMES)
    assert bank.realistic_rank[bank.id_of("tarmac")] == 0  # the ordering params gives, new classes included
    photo = _rgb(tmp_path / OWN_PHOTOS / "moss.png")
    image, context = bank.image_parts[bank.id_of("moss")][0][0], bank.context_parts[bank.id_of("moss")][0][0]
    assert np.array_equal(np.concatenate([image, context], axis=1), photo)
    for amap in aerial_maps(own_params, smoke_data, "unseen", bank):
        assert set(amap.terrains.tolist()) <= set(unseen.tolist())


def test_navigation_tables_run_on_own_terrains(own_params, smoke_data, smoke_artifacts):
    """Table II's protocol on maps painted only with the new terrains: the smoke PACER model, chance and the
    window oracle each get a row whose tier shares are a distribution per map."""
    P = own_params.pacer
    bank = load_terrain_bank(smoke_data, P.data)
    maps = aerial_maps(own_params, smoke_data, "unseen", bank)
    methods = {"PACER": (pacer_method(load_model(smoke_artifacts / "pacer" / "phase3" / "model.pt"), P.data), True),
               "uniform": (uniform_method(), True), "window oracle": (window_oracle_method(P.data), True)}
    result = navigation_rows(maps, methods, bank, P.data, "realistic", P.evaluation.cost_scale, P.seed)
    for name, shares in result.shares.items():
        assert shares.shape == (len(maps), 3) and np.allclose(shares.sum(axis=1), 1.0), name


def test_a_replaced_photograph_changes_what_models_key_on(own_params, smoke_data, tmp_path):
    data = own_params.pacer.data
    before, inputs = photos_fingerprint(smoke_data, data), phase_inputs(own_params, smoke_data)["terrain"]
    assert inputs == before
    recorded = photo_digests(smoke_data, data)  # what a phase writes beside its model, photograph by photograph
    assert recorded[f"{OWN_PHOTOS}/planks.png"] == hashlib.sha256((tmp_path / OWN_PHOTOS / "planks.png").read_bytes()).hexdigest()
    old = load_terrain_bank(smoke_data, data)
    cv2.imwrite(str(tmp_path / OWN_PHOTOS / "unlisted.png"), _texture(0, 192, 9))  # not in params: not read
    assert photos_fingerprint(smoke_data, data) == before
    path = tmp_path / OWN_PHOTOS / "planks.png"
    cv2.imwrite(str(path), _texture(0, 192, 7))  # same name, new content
    assert photos_fingerprint(smoke_data, data) != before
    changed = photo_digests(smoke_data, data)
    assert [s for s in recorded if recorded[s] != changed[s]] == [f"{OWN_PHOTOS}/planks.png"]
    new = load_terrain_bank(smoke_data, data)
    planks = new.id_of("planks")
    assert not np.array_equal(new.image_parts[planks][0][0], old.image_parts[planks][0][0])  # read anew
    assert np.array_equal(new.image_parts[planks][0][0][:, :4], _rgb(path)[:, :4])


def test_missing_mistyped_or_too_small_photographs_are_named(own_params, smoke_data, tmp_path):
    data = own_params.pacer.data
    (tmp_path / OWN_PHOTOS / "moss.png").unlink()
    with pytest.raises(DataError, match=r"pacer.data.unseen.moss: .*moss.png does not exist; put the photograph"):
        load_terrain_bank(smoke_data, data)
    assert [p for p in pacer_data_problems(own_params, []) if "moss.png does not exist" in p]  # `params check` too
    typo = with_pacer_data(own_params, unseen={**data.unseen, "moss": ("moss.png",)}).pacer.data
    with pytest.raises(DataError, match=r"pacer.data.unseen.moss: 'moss.png' is not a packaged photograph .* as "
                                        r"terrain_photos/<file>"):
        load_terrain_bank(smoke_data, typo)
    strip = int(np.ceil(data.patch_size * data.footprint_texels[1] / data.image_size))
    least = int(np.ceil(strip / data.context_fraction))
    cv2.imwrite(str(tmp_path / OWN_PHOTOS / "moss.png"), _texture(2, least - 1, 2))
    with pytest.raises(DataError, match=rf"pacer.data.unseen.moss: .*moss.png is {least - 1} x {least - 1} px, too "
                                        rf"small .* at least {least} px"):
        load_terrain_bank(smoke_data, data)
    assert [p for p in pacer_data_problems(own_params, []) if f"at least {least} px" in p]
    ok = cv2.imencode(".png", _texture(2, least, 2))[1].tobytes()
    (tmp_path / OWN_PHOTOS / "moss.png").write_bytes(ok[: len(ok) // 2])  # cut short
    with pytest.raises(DataError, match=r"pacer.data.unseen.moss: .*moss.png: not a readable image \(Pillow"):
        load_terrain_bank(smoke_data, data)
    assert [p for p in pacer_data_problems(own_params, []) if "moss.png: not a readable image (Pillow" in p]
    empty = with_pacer_data(own_params, unseen={**data.unseen, "moss": ()})
    assert pacer_data_problems(empty, []) == [
        "pacer.data.unseen.moss: no photographs; list at least one photograph for each class"]
    cv2.imwrite(str(tmp_path / OWN_PHOTOS / "moss.png"), _texture(2, least, 2))
    assert bank_names(load_terrain_bank(smoke_data, data), "unseen") == list(NAMES)  # the least size is enough
    assert pacer_data_problems(own_params, []) == []


def test_the_same_photograph_renamed_in_a_seen_and_an_unseen_class_is_refused(own_params, smoke_data, tmp_path):
    """Held-out integrity by content: a copy of an unseen photograph under another name, added to a seen class,
    is refused by `params check` and by the bank; so is a packaged seen photograph copied in as an unseen one."""
    data = own_params.pacer.data
    shutil.copy(tmp_path / OWN_PHOTOS / "planks.png", tmp_path / OWN_PHOTOS / "boards.png")
    leaked = with_pacer_data(own_params, seen={**data.seen, "grass": (*data.seen["grass"], f"{OWN_PHOTOS}/boards.png")})
    refusal = (r"pacer.data.unseen.planks: terrain_photos/planks.png holds the same photograph as one "
               r"pacer.data.seen.grass lists")
    assert [p for p in pacer_data_problems(leaked, []) if re.search(refusal, p)]
    with pytest.raises(ParamsError, match=refusal):
        load_terrain_bank(smoke_data, leaked.pacer.data)
    packaged = data.seen["grass"][0]
    shutil.copy(smoke_data / "raw" / "terrain" / packaged, tmp_path / OWN_PHOTOS / "moss.png")
    with pytest.raises(ParamsError, match=r"pacer.data.unseen.moss: terrain_photos/moss.png holds the same "
                                          r"photograph as one pacer.data.seen.grass lists"):
        load_terrain_bank(smoke_data, data)


def test_a_photograph_listed_twice_or_outside_the_checkout_is_refused(own_params, tmp_path):
    data = own_params.pacer.data
    twice = with_pacer_data(own_params, seen={**data.seen, "grass": (f"{OWN_PHOTOS}/planks.png",)})
    assert pacer_data_problems(twice, []) == [(
        "pacer.data.unseen.planks: 'terrain_photos/planks.png' is also listed by pacer.data.seen.grass; a photograph "
        "belongs to one class: remove it from one of them")]
    for source in (str(tmp_path / OWN_PHOTOS / "planks.png"), f"{OWN_PHOTOS}/../{OWN_PHOTOS}/planks.png"):
        outside = with_pacer_data(own_params, unseen={**data.unseen, "planks": (source,)})
        problems = pacer_data_problems(outside, [])
        assert len(problems) == 1 and problems[0].startswith(f"pacer.data.unseen.planks: {source!r} points outside")
        assert "copy it into terrain_photos/" in problems[0]


def bank_names(bank, group: str) -> list[str]:
    return [bank.names[t] for t in bank.ids(group)]


def test_every_stage_that_reads_the_bank_depends_on_the_photographs_folder():
    from navlab.pipeline.dvc_yaml import all_stages

    stages = all_stages()
    reads = ("pacer_", "stack_")  # the stack paints its aerial images with the bank's photographs
    readers = [s for s in stages if s.name.startswith(reads)]
    assert len(readers) == 12  # the phases, both baselines, three variant stages, three notebooks, the stack
    assert all(OWN_PHOTOS in s.inputs for s in readers)
    assert all(OWN_PHOTOS not in s.inputs for s in stages if not s.name.startswith(reads))
