"""`python -m navlab params check`: every profile of the checkout's params.yaml fits, and a profile that
does not is named with one line per mis-fitting key (without data/, without training)."""

from __future__ import annotations

from navlab.cli import main
from navlab.core.params import load_params, repo_root
from navlab.pipeline.profile_check import hj_problems, pacer_render_problems


def _edited(tmp_path, *swaps: tuple[str, str]):
    """A copy of params.yaml with each (old, new) text swapped once; fails if ``old`` is not there."""
    text = (repo_root() / "params.yaml").read_text()
    for old, new in swaps:
        assert text.count(old) == 1, old
        text = text.replace(old, new)
    path = tmp_path / "params.yaml"
    path.write_text(text)
    return path


def test_every_profile_fits(capsys):
    assert main(["params", "check"]) == 0
    out = capsys.readouterr().out
    assert "every profile fits" in out
    assert all(f"[{p}] pacer model" in out for p in ("smoke", "default", "gpu", "paper"))


def test_misfits_are_one_line_per_key(tmp_path, capsys):
    """The gpu profile's old 512-px aerial maps (500-px test maps) and a default TTR grid over the CPU budget."""
    path = _edited(tmp_path, ("gpu: 448, paper: 512}", "gpu: 512, paper: 512}"),
                   ("default: [81, 81, 11, 36], paper: [481", "default: [801, 801, 11, 36], paper: [481"))
    assert main(["params", "check", "--params", str(path)]) == 2
    errors = capsys.readouterr().err.splitlines()
    assert len(errors) == 2, errors  # gpu takes default's TTR grid too, but its machine has 96 GiB, not 16
    assert sum("[gpu] pacer.data.aerial.size = 512 exceeds the 500-px" in e for e in errors) == 1
    assert sum("[default] hj.grids.ttr.shape = [801, 801, 11, 36]" in e for e in errors) == 1


def test_one_profile_and_the_runtime_rule(tmp_path):
    """--profile checks one profile; the aerial rule is aerial.semantic_map_regions' own (size <= map side)."""
    path = _edited(tmp_path, ("gpu: 448, paper: 512}", "gpu: 500, paper: 512}"))
    assert main(["params", "check", "--profile", "gpu", "--params", str(path)]) == 0
    path = _edited(tmp_path, ("gpu: 448, paper: 512}", "gpu: 501, paper: 512}"))
    assert pacer_render_problems(load_params("gpu", path), [])[0].startswith("pacer.data.aerial.size = 501")
    assert hj_problems(load_params("paper"), []) == []
