"""The recognition reference (benchmarks/pacer_recognition_reference.py, the one script that uses its terrain
segmenter): its cost rule, its plumbing, and that it learns."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch
from torch.nn import functional as F

from navlab.core.params import load_params
from navlab.pacer.aerial import AerialMap
from navlab.pacer.preferences import IGNORE, target_costmap

SCRIPT = Path(__file__).resolve().parents[1] / "benchmarks" / "pacer_recognition_reference.py"
_spec = importlib.util.spec_from_file_location("pacer_recognition_reference", SCRIPT)
reference = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = reference  # dataclasses resolve their module's annotations through sys.modules
_spec.loader.exec_module(reference)
SegmenterSettings, TerrainSegmenter, _targets = reference.SegmenterSettings, reference.TerrainSegmenter, reference._targets
expected_rank_costs, segmenter_method = reference.expected_rank_costs, reference.segmenter_method

LABELS = (3, 5, 8, 11)


def one_hot(labels: np.ndarray, known=LABELS) -> torch.Tensor:
    index = torch.as_tensor(np.searchsorted(known, labels))
    return F.one_hot(index, len(known)).permute(2, 0, 1).float()[None]


def test_expected_rank_costs_of_certain_labels_is_the_target_costmap():
    gen = np.random.default_rng(0)
    labels = gen.choice([3, 8, 11], size=(9, 7))
    ordering = np.array([11, 3, 8])
    costs = expected_rank_costs(one_hot(labels), LABELS, ordering)[0].numpy()
    np.testing.assert_allclose(costs, target_costmap(labels, ordering), atol=1e-7)


def test_expected_rank_costs_renormalise_over_the_maps_terrains():
    p = torch.tensor([0.5, 0.2, 0.1, 0.2]).reshape(1, 4, 1, 1)  # terrain 5 is not on this map
    ordering = np.array([3, 8, 11])  # costs 0, 0.5, 1
    expected = (0.5 * 0 + 0.1 * 0.5 + 0.2 * 1) / 0.8
    assert expected_rank_costs(p, LABELS, ordering).item() == pytest.approx(expected)
    with pytest.raises(ValueError, match="not trained on"):
        expected_rank_costs(p, LABELS, np.array([3, 4]))


def test_targets_ignore_outside_the_view_and_unknown_terrains():
    labels = torch.tensor([[3, 5, IGNORE], [11, 12, 8]])
    assert _targets(labels, LABELS).tolist() == [[0, 1, -100], [3, -100, 2]]


class _ColourReader(torch.nn.Module):
    """A perfect segmenter of images whose red channel is label/16: certain of the true label."""

    labels = LABELS

    def forward(self, image):
        index = torch.as_tensor(np.searchsorted(LABELS, (image[:, 0] * 16).round().numpy()))
        inside = image.abs().sum(1) > 0  # zero outside the field of view: no evidence there
        return 50.0 * F.one_hot(index.clamp_max(len(LABELS) - 1), len(LABELS)).permute(0, 3, 1, 2).float() * inside[:, None]


def test_a_perfect_segmenter_costs_the_map_as_its_ordering_says():
    params = load_params("smoke")
    gen = np.random.default_rng(1)
    size = 2 * params.pacer.data.image_size
    blocks = gen.choice([3, 8, 11], size=(4, 4))
    labels = np.kron(blocks, np.ones((size // 4, size // 4), dtype=np.int64))
    image = np.stack([labels / 16.0, np.full(labels.shape, 0.5), np.full(labels.shape, 0.5)]).astype(np.float32)
    amap = AerialMap(image, labels, np.unique(labels), (0, 0), (size - 1, size - 1))
    ordering = np.array([8, 11, 3])
    costs = segmenter_method(_ColourReader(), params)(amap, ordering, None, None)
    np.testing.assert_allclose(costs, target_costmap(labels, ordering), atol=1e-5)


def test_a_perfect_segmenter_told_the_context_costs_the_mean_consistent_ranks():
    """A chain over every terrain decides the order (the costs are the ordering's); pairs naming only other
    terrains decide nothing (every terrain at the middle rank, 0.5); one pair over three terrains gives the
    mean ranks by hand: a > b allows (a, b, c), (a, c, b), (c, a, b), so a 1/3, b 5/3, c 1 of ranks 0..2, / 2."""
    params = load_params("smoke")
    size = 2 * params.pacer.data.image_size
    labels = np.kron(np.array([[3, 8], [11, 3]]), np.ones((size // 2, size // 2), dtype=np.int64))
    image = np.stack([labels / 16.0, np.full(labels.shape, 0.5), np.full(labels.shape, 0.5)]).astype(np.float32)
    amap = AerialMap(image, labels, np.unique(labels), (0, 0), (size - 1, size - 1))
    ordering = np.array([8, 11, 3])
    told = segmenter_method(_ColourReader(), params, told="context")
    chain = np.array([[8, 11], [11, 3]])
    np.testing.assert_allclose(told(amap, ordering, None, chain), target_costmap(labels, ordering), atol=1e-5)
    np.testing.assert_allclose(told(amap, ordering, None, np.array([[5, 4]])), 0.5, atol=1e-5)
    by_hand = {8: 1 / 6, 11: 5 / 6, 3: 1 / 2}
    expected = np.vectorize(by_hand.__getitem__)(labels)
    np.testing.assert_allclose(told(amap, ordering, None, np.array([[8, 11]])), expected, atol=1e-5)
    with pytest.raises(ValueError, match="told="):
        segmenter_method(_ColourReader(), params, told="labels")


def test_the_segmenter_learns_two_textures_apart(single_thread):
    """Stripes against noise, split by a random diagonal: 100 Adam steps must separate them."""
    torch.manual_seed(0)
    gen = torch.Generator().manual_seed(0)
    model = TerrainSegmenter((0, 1), width=8)
    optimiser = torch.optim.Adam(model.parameters(), lr=5e-3)

    def batch(n):
        yy, xx = torch.meshgrid(torch.arange(32.0), torch.arange(32.0), indexing="ij")
        offsets = torch.randint(-10, 10, (n, 1, 1), generator=gen)
        target = (xx + yy - 32 > offsets).long()
        stripes = (torch.sin(xx * 1.5) > 0).float().expand(n, 32, 32)
        noise = torch.rand(n, 32, 32, generator=gen)
        grey = torch.where(target.bool(), stripes, noise)
        return grey[:, None].expand(n, 3, 32, 32).contiguous(), target

    for _ in range(100):
        images, target = batch(8)
        loss = F.cross_entropy(model(images), target)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
    model.eval()
    images, target = batch(16)
    with torch.no_grad():
        accuracy = (model(images).argmax(1) == target).float().mean().item()
    assert accuracy > 0.9


def test_settings_reject_nonsense():
    with pytest.raises(ValueError, match="epochs"):
        SegmenterSettings(epochs=0)
    with pytest.raises(ValueError, match="street_windows"):
        SegmenterSettings(street_windows=1.5)


def test_the_recognition_reference_script_runs_end_to_end(smoke_data, tmp_path):
    """benchmarks/pacer_recognition_reference.py on the smoke data (one tiny epoch): it once broke unnoticed when
    the held-out BEV sets became procedural; every row of both preferences must come back as low-tier shares."""
    out = tmp_path / "reference.json"
    script = SCRIPT
    command = [sys.executable, str(script), "--profile", "smoke", "--terrains", "seen", "--epochs", "1",
               "--examples", "8", "--threads", "1", "--data-dir", str(smoke_data), "--out", str(out)]
    done = subprocess.run(command, check=False, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    results = json.loads(out.read_text())["results"]
    assert [r["preference"] for r in results] == ["realistic", "inverted"]
    for result in results:
        rows = {row["method"]: row["low"] for row in result["rows"]}
        assert {"Segmenter told the ordering", "Segmenter told the context's pairs", "Context-limited oracle",
                "Window oracle (ceiling)", "Uniform costmap (chance)"} <= set(rows)
        assert all(0.0 <= low <= 1.0 for low in rows.values())
