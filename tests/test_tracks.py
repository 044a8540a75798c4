"""A track declares itself (issue 62): a toy track, one package plus one entry in ``navlab.tracks.TRACKS``,
reaches dvc.yaml, `artifacts build`, the results page and `params check`, and the pipeline names no track."""

from __future__ import annotations

import json
import re
import shutil
import sys
from pathlib import Path

import pytest
import yaml

import navlab
import navlab.tracks
from navlab.core.params import load_params
from navlab.metrics.tables import Table
from navlab.pipeline.dvc_yaml import render_dvc_yaml
from navlab.pipeline.profile_check import check_profile
from navlab.pipeline.reports import write_table
from navlab.pipeline.results import headline_block, read_tracks, registries, render_page, shown_figures
from navlab.pipeline.steps import artifact_steps, data_steps

ROOT = Path(__file__).resolve().parents[1]

MANIFEST = '''
from navlab.core.track import Figure, Paper, Track, artifact_stage, notebook_stage

TRACK = Track(
    name="toy",
    paper=Paper("ToyNav", "A Toy Paper", "https://example.org/toy"),
    stages=(artifact_stage("toy_model", ("seed",), ("data",), ("artifacts/toy/model",)),
            notebook_stage("toy_01_table", "notebooks/toy/01_table.ipynb", ("seed",), ("artifacts/toy/model",),
                           ("reports/toy/figures",), ("reports/toy/table1.json",))),
    steps="navlab.toy.steps:artifact_steps",
    data_steps="navlab.toy.steps:data_steps",
    claims="navlab.toy.claims",
    figures=(Figure("toy/figures/fig1.png", "Fig. 1: the toy", "table1"),),
    headline=(("table1", ("Toy",), ("score",)),),
    before=("fig0_setup",),
    shown=(("fig0_setup", ("width",)),),
    plots=(("artifacts/toy/model/log.tsv", "epoch", ("loss",), "Toy loss per epoch"),),
    profile_checks=("navlab.toy.steps:problems",),
)
'''
STEPS = '''
from navlab.core.seeding import rng


def build_model(params, data_dir, artifacts_dir):
    return rng(params.seed, "toy").uniform()


def artifact_steps():
    return [("toy_model", build_model)]


def build_cells(params, data_dir):
    return None


def data_steps():
    return [("cells", build_cells)]


def problems(params, notes):
    notes.append("toy model: 3 parameters")
    return ["toy.width = 3: the toy needs at least 4"]
'''
CLAIMS = '''
from navlab.metrics.claims import PaperClaim

CLAIMS = {"beats": PaperClaim("beats", "Toy beats chance", "toy beats chance", "Table 1", report="table1")}
'''
NOTEBOOK = {"cells": [{"cell_type": "code", "id": "0", "metadata": {}, "execution_count": None, "outputs": [],
                       "source": ["from navlab.core.seeding import rng\n"]}],
            "metadata": {}, "nbformat": 4, "nbformat_minor": 5}


@pytest.fixture
def toy_checkout(tmp_path, monkeypatch):
    """A copy of the checkout's library, notebooks and params with a toy track added as lib/navlab/toy/, importable as
    ``navlab.toy`` and listed last in TRACKS."""
    shutil.copytree(ROOT / "lib" / "navlab", tmp_path / "lib" / "navlab",
                    ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "notebooks", tmp_path / "notebooks", ignore=shutil.ignore_patterns(".ipynb_checkpoints"))
    shutil.copy(ROOT / "params.yaml", tmp_path / "params.yaml")
    toy = tmp_path / "lib" / "navlab" / "toy"
    toy.mkdir()
    for name, text in {"__init__.py": "", "track.py": MANIFEST, "steps.py": STEPS, "claims.py": CLAIMS}.items():
        (toy / name).write_text(text, encoding="utf8")
    (tmp_path / "notebooks" / "toy").mkdir()
    (tmp_path / "notebooks" / "toy" / "01_table.ipynb").write_text(json.dumps(NOTEBOOK), encoding="utf8")
    monkeypatch.setattr(navlab, "__path__", [*navlab.__path__, str(tmp_path / "lib" / "navlab")])
    from navlab.toy.track import TRACK

    monkeypatch.setattr(navlab.tracks, "TRACKS", (*navlab.tracks.TRACKS, TRACK))
    yield tmp_path
    for name in [m for m in sys.modules if m == "navlab.toy" or m.startswith("navlab.toy.")]:
        del sys.modules[name]  # the package lived in the temporary folder


def test_a_toy_track_reaches_dvc_yaml_the_build_steps_the_results_page_and_params_check(toy_checkout, tmp_path):
    stages = yaml.safe_load(render_dvc_yaml(toy_checkout))["stages"]
    assert stages["toy_model"]["cmd"] == "python -m navlab artifacts build --only toy_model"
    assert "lib/navlab/toy/steps.py" in stages["toy_model"]["deps"]
    assert stages["toy_01_table"]["deps"][0] == "notebooks/toy/01_table.ipynb"
    assert {"reports/toy/figures": {"cache": False}} in stages["toy_01_table"]["outs"]  # the page shows its figure
    assert "reports/toy/table1.json" in stages["reports_index"]["deps"]  # the index reads its report
    assert "lib/navlab/toy/claims.py" in stages["reports_index"]["deps"]  # and its claims registry
    assert list(stages)[-1] == "reports_index"
    plots = yaml.safe_load(render_dvc_yaml(toy_checkout))["plots"]
    assert {"artifacts/toy/model/log.tsv": {"x": "epoch", "y": ["loss"], "title": "Toy loss per epoch"}} in plots

    assert [name for name, _ in data_steps()][-1] == "cells"  # the house's raw inputs and maps come first
    steps = dict(artifact_steps())
    assert steps["toy_model"](load_params("smoke"), None, None) == steps["toy_model"](load_params("smoke"), None, None)

    reports = tmp_path / "reports"
    write_table(reports, Table("table1", "ToyNav Table 1", ["method", "score"], [{"method": "Toy", "score": 0.5}],
                               [{"method": "Toy", "score": 0.7}], "set-up"), track="toy", profile="smoke", seeds=[0])
    write_table(reports, Table("fig0_setup", "ToyNav Fig. 0", ["method", "width", "extra"],
                               [{"method": "Toy", "width": 3, "extra": 9}], [], "set-up"),
                track="toy", profile="smoke", seeds=[0])
    (reports / "toy" / "figures").mkdir()
    (reports / "toy" / "figures" / "fig1.png").write_bytes(b"\x89PNG")
    page = render_page(read_tracks(reports), shown_figures(reports), registries())
    section = page.split("## ToyNav\n", 1)[1]
    assert "[*A Toy Paper*](https://example.org/toy)" in section and "](toy/figures/fig1.png)" in section
    assert "| Toy | 0.5 | 0.7 |" in section
    assert section.index("| Toy | 0.5 | 0.7 |") < section.index("](toy/figures/fig1.png)")  # beside its table
    assert "| [table1](toy/table1.md) | Toy beats chance |" in section  # its registry, though no report decides it
    assert section.index("ToyNav Fig. 0") < section.index("ToyNav Table 1")  # `before`: the figure first
    assert "| method | width |\n" in section  # `shown`: the columns chosen where the paper prints no table
    block = headline_block(read_tracks(reports), shown_figures(reports), "reports/README.md", registries())
    toy = block.split("### ToyNav\n", 1)[1]
    assert toy.startswith("\n![Fig. 1: the toy](reports/toy/figures/fig1.png)")
    assert "| [ToyNav Table 1](reports/toy/table1.md) | Toy | score | 0.5 | 0.7 |" in toy

    problems, notes = check_profile(load_params("smoke"))
    assert "toy.width = 3: the toy needs at least 4" in problems and "toy model: 3 parameters" in notes


def test_the_pipeline_names_no_track():
    """The track names appear in no module of ``pipeline/`` but those that wait for the next full re-run (their
    stages' code: the report writer's table list, the data build's parameter sections, the HJ sweep queue)."""
    names = re.compile(r"\b(surenav|pacer|hj)\b")
    waiting = {"reports.py", "dataset.py", "experiments.py"}
    named = [p.name for p in (ROOT / "lib" / "navlab" / "pipeline").glob("*.py")
             if p.name not in waiting and names.search(re.sub(r'""".*?"""|#.*', "", p.read_text(encoding="utf8"),
                                                              flags=re.DOTALL))]
    assert named == []
