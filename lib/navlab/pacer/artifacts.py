"""Artefact builders of the pacer track (DVC stages ``pacer_*``): the three training phases and the baselines.

Each writes one folder under ``artifacts/pacer/``: ``phase1``-``phase3`` (``model.pt``, ``checkpoint.pt``,
``val_loss.tsv``, ``summary.json``, ``photographs.json``: the sha256 of every photograph it read),
``sterling`` (``encoder.pt``) and ``classifier`` (``classifier.pt``, ``summary.json``).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from torch.utils.data import Subset

from navlab.core.fingerprint import files_fingerprint
from navlab.core.io import require, write_json
from navlab.core.params import Params
from navlab.maps.dataset import FOLDER as MAPS_FOLDER
from navlab.pacer.baselines.semantic_classifier import save_classifier, train_classifier
from navlab.pacer.baselines.sterling import save_sterling, train_sterling
from navlab.pacer.datasets import STREET_SPLIT, pacer_dataset
from navlab.pacer.map_windows import map_windows
from navlab.pacer.terrain import load_terrain_bank, photo_digests, photos_fingerprint
from navlab.pacer.train import PHASE_DATASETS, PHASES, PhaseRun, Selection, resolve_device, train_phase


def phase_dir(artifacts_dir: str | Path, phase: str) -> Path:
    return Path(artifacts_dir) / "pacer" / phase


def selection_windows(params: Params, data_dir: Path, bank) -> list:
    """The fixed validation map windows checkpoints are selected on (``pacer.train.select_on``
    map_windows; none for val_loss): ``select_windows`` windows of the SuReNav *val* maps on seen terrains,
    realistic and inverted preferences taking turns (the two the navigation tables plan under)."""
    if params.pacer.train.select_on != "map_windows":
        return []
    return map_windows(params, data_dir, "val", "seen", ("realistic", "inverted"),
                       params.pacer.train.select_windows, bank)


def phase_inputs(params: Params, data_dir: Path) -> dict:
    """What a phase's checkpoint keys on besides code, model and train parameters (``train.run_key``): the
    terrain photographs (names and content, packaged and of your own), the street maps of the splits training
    items are cut from (train, val; never test), and every ``pacer.data`` parameter (layouts, street windows,
    photometrics, context draws). The phases' outputs persist so that a killed training resumes; without these,
    a data-only change would make DVC re-run a phase that then resumed its finished checkpoint and returned the
    old weights."""
    data = params.pacer.data
    return {"terrain": photos_fingerprint(data_dir, data),
            "street_maps": ({split: files_fingerprint(require(data_dir, *MAPS_FOLDER, split))
                             for split in sorted(set(STREET_SPLIT.values()))}
                            if data.layout.street_windows > 0 else None),
            "data": dataclasses.asdict(data)}


def phase_step(phase: str):
    """The step that trains ``phase`` into ``<artifacts_dir>/pacer/<phase>`` (resuming its checkpoint): the main
    stages' and, under another parameter set and artefacts root, every variant's (``pacer.variants``)."""
    def step(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
        bank = load_terrain_bank(data_dir, params.pacer.data)
        names = PHASE_DATASETS[phase]
        previous = PHASES.index(phase) - 1
        train_phase(
            params.pacer.model, params.pacer.train,
            [pacer_dataset(params, data_dir, n, "train", bank) for n in names],
            [Subset(ds, range(min(params.pacer.train.val_examples, len(ds))))
             for ds in (pacer_dataset(params, data_dir, n, "val", bank) for n in names)],
            phase_dir(artifacts_dir, phase),
            PhaseRun(phase, getattr(params.pacer.train.epochs, phase), params.pacer.seed, params.pacer.data.n_pairs,
                     phase_dir(artifacts_dir, PHASES[previous]) / "model.pt" if previous >= 0 else None,
                     params.pacer.data.patch_size),
            inputs=phase_inputs(params, data_dir),
            selection=Selection(selection_windows(params, data_dir, bank), params.pacer.evaluation.cost_scale),
        )
        write_json(phase_dir(artifacts_dir, phase) / "photographs.json", photo_digests(data_dir, params.pacer.data))
    return step


def build_sterling(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
    """VICReg patch encoder on D_real's training images (no labels used)."""
    real = pacer_dataset(params, data_dir, "real", "train")
    b = params.pacer.baselines
    device = str(resolve_device(params.pacer.train.device))
    out = phase_dir(artifacts_dir, "sterling")
    encoder = train_sterling([real], b.sterling, b.patch_size, params.pacer.seed, out / "checkpoint.pt", device)
    save_sterling(encoder, out / "encoder.pt")


def build_classifier(params: Params, data_dir: Path, artifacts_dir: Path) -> None:
    """Patch classifier over the seen terrain labels of D_real's training images, its best epoch chosen by
    patch accuracy on D_real's validation images (``summary.json``)."""
    bank = load_terrain_bank(data_dir, params.pacer.data)
    real, val = (pacer_dataset(params, data_dir, "real", split, bank) for split in ("train", "val"))
    b = params.pacer.baselines
    device = str(resolve_device(params.pacer.train.device))
    out = phase_dir(artifacts_dir, "classifier")
    model, summary = train_classifier([real], b.classifier, b.patch_size, params.pacer.seed, out / "checkpoint.pt",
                                      device, val_datasets=[val])
    save_classifier(model, out / "classifier.pt")
    write_json(out / "summary.json", summary)


def artifact_steps() -> list:
    """(name, fn(params, data_dir, artifacts_dir)) in dependency order."""
    return [*[(f"pacer_{p}", phase_step(p)) for p in PHASES], ("pacer_sterling", build_sterling),
            ("pacer_classifier", build_classifier)]
