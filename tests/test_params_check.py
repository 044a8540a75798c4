"""Every profile checked on the CPU, in seconds, without data/ (issue 24 item 6): loading a profile refuses
keys of different sections that do not fit together (navlab.core.params.constraints), and
`python -m navlab params check` dry-runs each profile's stage shapes (navlab.pipeline.profile_check), so
`gpu` and `paper` cannot break unseen. A profile that does not fit is named with one line per key."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import torch

from navlab.cli import main
from navlab.core.grid import RasterFrame
from navlab.core.params import PROFILES, ParamsError, load_params, repo_root
from navlab.hj.profile_check import grid_problems as hj_problems
from navlab.maps.semantic_map import SemanticMap
from navlab.pacer.aerial import semantic_map_regions
from navlab.pacer.evaluate import costmap_over_map
from navlab.pipeline.profile_check import check_profile

GPU_AERIAL = "gpu: 896, paper: 1024}"  # pacer.data.aerial.size's gpu and paper values in params.yaml
ZOOM = ("street_zoom: 2\n", "street_zoom: 1\n")  # pacer.data.layout.street_zoom back to the old map scale


def _edited(tmp_path, *swaps: tuple[str, str]):
    """A copy of params.yaml with each (old, new) text swapped once; fails if ``old`` is not there."""
    text = (repo_root() / "params.yaml").read_text()
    for old, new in swaps:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = tmp_path / "params.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize("profile", PROFILES)
def test_profile_dry_run(profile):
    """Each stage family of the profile fits: data checks, PACER net and baselines on meta, the SuReNav
    estimator on a three-node graph, HJ grid specs and memory."""
    problems, notes = check_profile(load_params(profile))
    assert problems == []
    for family in ("pacer aerial", "pacer model", "surenav estimator", "hj "):
        assert sum(n.startswith(family) for n in notes) == 1, (family, notes)


def test_old_gpu_aerial_size_fails_at_load(tmp_path):
    """The bug this exists for: 512-px aerial maps cut from 500-px SuReNav test maps stopped the gpu
    profile at the tables after ~2 h of training; now load_params itself refuses it, naming key and fix."""
    path = _edited(tmp_path, (GPU_AERIAL, "gpu: 512, paper: 512}"), ZOOM)
    with pytest.raises(ParamsError, match=r"^pacer\.data\.aerial\.size = 512 at pacer\.data\.layout\.street_zoom = 1 "
                                          r"covers 512 px, more than the 500-px SuReNav test maps it is cut from "
                                          r"\(data\.maps\.tile_size_m / resolution_m = 500 / 1\);.*"
                                          r"use a size <= 500$"):
        load_params("gpu", path)
    path = _edited(tmp_path, (GPU_AERIAL, "gpu: 1002, paper: 1024}"))  # at zoom 2: 501 m
    with pytest.raises(ParamsError, match=r"^pacer\.data\.aerial\.size = 1002 at pacer\.data\.layout\.street_zoom = 2 "
                                          r"covers 501 px"):
        load_params("gpu", path)
    assert load_params("default", path).pacer.data.aerial.size == 512  # the other profiles are untouched


def test_aerial_rule_is_the_runtime_rule(tmp_path):
    """load_params accepts exactly the sizes semantic_map_regions can cut from a test map (size / zoom, rounded
    up, <= its side), at zoom 1 and 2."""
    blank = SemanticMap("test map", np.zeros((500, 500), np.uint8), RasterFrame((500, 500), 1.0))
    for zoom, fits in ((1, 500), (2, 1000)):
        zoomed = (ZOOM[0], f"street_zoom: {zoom}\n")
        accepted = load_params("gpu", _edited(tmp_path, (GPU_AERIAL, f"gpu: {fits}, paper: 512}}"), zoomed))
        assert accepted.pacer.data.aerial.size == fits
        assert semantic_map_regions([blank], fits, np.random.default_rng(0), zoom).shape == (fits, fits)
        with pytest.raises(ParamsError, match=rf"^pacer\.data\.aerial\.size = {fits + 1}"):
            load_params("gpu", _edited(tmp_path, (GPU_AERIAL, f"gpu: {fits + 1}, paper: 512}}"), zoomed))
        with pytest.raises(ValueError, match=rf"smaller than the aerial size {fits + 1} at zoom {zoom}"):
            semantic_map_regions([blank], fits + 1, np.random.default_rng(0), zoom)


def test_bev_window_rule_is_the_runtime_rule(tmp_path):
    """The aerial costmap reflect-pads the map by one BEV window, which needs window < map: refused at load."""
    with pytest.raises(ParamsError, match=r"^pacer\.data\.image_size = 128 must be smaller than pacer\.data\.aerial"):
        load_params("gpu", _edited(tmp_path, (GPU_AERIAL, "gpu: 128, paper: 512}")))
    with pytest.raises(RuntimeError):
        costmap_over_map(torch.nn.Identity(), torch.zeros(3, 32, 32), torch.zeros(3, 16, 8), np.ones((32, 32), bool))


def test_dry_run_names_each_misfit():
    """Shapes that only fail inside a stage: a U-Net too deep for the BEV image, a baseline too deep for
    its patches, attention heads that do not divide the SuReNav width: one line each, naming the key."""
    p = load_params("smoke")
    b = p.pacer.baselines
    bad = dataclasses.replace(p, pacer=dataclasses.replace(
        p.pacer, model=dataclasses.replace(p.pacer.model, image_channels=(4, 8, 16, 32, 64, 128)),
        baselines=dataclasses.replace(b, sterling=dataclasses.replace(b.sterling, channels=(8, 16, 32, 64)))),
        surenav=dataclasses.replace(p.surenav, model=dataclasses.replace(p.surenav.model, channels=18)))
    problems, _ = check_profile(bad)
    assert [q.split(" ")[0] for q in problems] == ["surenav.model.channels", "pacer.model",  # in TRACKS order
                                                    "pacer.baselines.sterling.channels"], problems


def test_misfits_are_one_line_per_key(tmp_path, capsys):
    """gpu aerial maps covering 501 m of the 500-px test maps and a default TTR grid over the CPU budget."""
    path = _edited(tmp_path, (GPU_AERIAL, "gpu: 1002, paper: 1024}"),
                   ("default: [81, 81, 16, 36], paper: [481", "default: [801, 801, 16, 36], paper: [481"))
    assert main(["params", "check", "--params", str(path)]) == 2
    errors = capsys.readouterr().err.splitlines()
    assert len(errors) == 2, errors  # gpu stops at load; its TTR grid (default's) fits its 96 GiB anyway
    assert sum("[gpu] pacer.data.aerial.size = 1002 at pacer.data.layout.street_zoom = 2 covers 501" in e for e in errors) == 1
    assert sum("[default] hj.grids.ttr.shape = [801, 801, 16, 36]" in e for e in errors) == 1


def test_one_profile(capsys):
    """--profile checks one profile; the paper HJ grids fit their machine."""
    assert main(["params", "check", "--profile", "gpu"]) == 0
    out = capsys.readouterr().out
    assert "[gpu] pacer model" in out and "[default]" not in out and "every profile fits" in out
    assert hj_problems(load_params("paper"), []) == []


def test_a_repeated_training_seed_is_one_line_naming_the_key():
    """An extra seed equal to pacer.seed would train the main model again and count it as a second seed."""
    p = load_params("smoke")
    bad = dataclasses.replace(p, pacer=dataclasses.replace(
        p.pacer, variants=dataclasses.replace(p.pacer.variants, seeds=(p.pacer.seed, 3))))
    problems, _ = check_profile(bad)
    assert len(problems) == 1 and problems[0].startswith("pacer.variants.seeds = [0, 3] repeats seed(s) [0]"), problems
    assert check_profile(p)[0] == []
