"""PACER model, loss, staged training and baselines on tiny synthetic examples (shapes as navlab.pacer.datasets)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import torch

from navlab.core.params import load_params
from navlab.core.seeding import rng
from navlab.pacer.baselines.semantic_classifier import train_classifier
from navlab.pacer.baselines.sterling import SterlingEncoder, augment, train_sterling, vicreg_loss
from navlab.pacer.checkpoints import read_summary
from navlab.pacer.loss import contrast_loss, masked_bce, matching_loss
from navlab.pacer.model import build_model
from navlab.pacer.train import (
    PhaseRun,
    epoch_draws,
    load_model,
    resolve_device,
    train_phase,
    validation_loss,
)

H, W, PATCH = 32, 32, 8
COLOURS = {0: (0.8, 0.2, 0.2), 1: (0.2, 0.3, 0.9), 2: (0.2, 0.8, 0.3)}  # three flat, noisy "terrains"


def texture(label: int, shape, gen) -> np.ndarray:
    base = np.asarray(COLOURS[label], dtype=np.float32)[:, None, None]
    return np.clip(base + 0.05 * gen.standard_normal((3, *shape)), 0, 1).astype(np.float32)


class TinyTerrainSet(torch.utils.data.Dataset):
    """Two terrains split left/right, a trapezoid field of view, 3 context pairs: the datasets' item layout."""

    def __init__(self, size: int, ordering=(0, 1, 2), seed: int = 0):
        self.size, self.ordering, self.seed = size, tuple(ordering), seed

    def __len__(self):
        return self.size

    def __getitem__(self, i):
        gen = rng(self.seed, "tiny", i)
        a, b = gen.choice(3, size=2, replace=False)
        split = int(gen.integers(8, W - 8))
        labels = np.where(np.arange(W)[None, :] < split, a, b).repeat(H, 0).astype(np.int64)
        image = np.where(labels[None] == a, texture(a, (H, W), gen), texture(b, (H, W), gen))
        rows, cols = np.mgrid[0:H, 0:W]
        fov = np.abs(cols - W / 2) <= 4 + rows * 0.5  # widening towards the robot (bottom)
        rank = {lab: r for r, lab in enumerate(self.ordering)}
        costmap = np.vectorize(lambda v: rank[v] / 2)(labels).astype(np.float32)
        pairs = [(self.ordering[0], self.ordering[1]), (self.ordering[1], self.ordering[2]),
                 (self.ordering[0], self.ordering[2])]
        context = np.concatenate([np.concatenate([texture(p, (PATCH, PATCH), gen), texture(q, (PATCH, PATCH), gen)],
                                                 axis=1) for p, q in pairs])
        return {"image": image, "context": context, "costmap": costmap, "fov_mask": fov, "labels": labels,
                "ordering": self.ordering, "pairs": np.array(pairs, dtype=np.int64)}


@pytest.fixture(scope="module")
def smoke():
    return load_params("smoke").pacer


def tiny_train_cfg(smoke, **changes):
    """The smoke training sizes shrunk; selected on the validation loss (the tiny sets have no map windows)."""
    return dataclasses.replace(smoke.train, **{"examples_per_epoch": 8, "batch_size": 4, "threads": 1,
                                               "select_on": "val_loss", **changes})


def test_loss_ignores_pixels_outside_the_field_of_view():
    gen = torch.Generator().manual_seed(0)
    logits = torch.randn(2, H, W, generator=gen, requires_grad=True)
    target = torch.rand(2, H, W, generator=gen)
    fov = torch.as_tensor(np.stack([TinyTerrainSet(2)[i]["fov_mask"] for i in range(2)]))
    loss = masked_bce(logits, target, fov)
    loss.backward()
    assert torch.all(logits.grad[~fov] == 0) and torch.any(logits.grad[fov] != 0)
    changed = logits.detach().clone()
    changed[~fov] = torch.randn(int((~fov).sum()), generator=gen) * 100
    assert torch.allclose(masked_bce(changed, target, fov), loss)
    inside = torch.nn.functional.binary_cross_entropy_with_logits(logits[fov], target[fov])
    assert torch.allclose(loss, inside)
    with pytest.raises(ValueError, match="same shape"):
        masked_bce(logits, target[:, :-1], fov)


def test_matching_loss_is_the_prototypical_cross_entropy_over_shown_pixels():
    """Analytic value: a pixel whose own terrain's k patches have cosine 1 and the other 2n - k cosine 0 costs
    -log(k e^T / (k e^T + 2n - k)); pixels out of view or of a terrain the context does not show add nothing
    (their cosines can change freely); a batch showing none is 0 with a zero gradient; the gradient matches
    finite differences; a stride-s cosine map is upsampled to the labels."""
    n2, T = 6, torch.tensor(3.0, dtype=torch.float64)
    terrains = torch.tensor([[0, 1, 2, 1, 3, 4]])  # terrain 1 has two patches
    labels = torch.tensor([[[0, 1, -1, 9]]])  # (1, 1, 4): terrain 0, terrain 1, out of view, not in the context
    cos = torch.zeros(1, n2, 1, 4, dtype=torch.float64)
    cos[0, 0, 0, 0] = 1.0
    cos[0, [1, 3], 0, 1] = 1.0
    expected = -(math.log(math.e ** 3 / (math.e ** 3 + 5)) + math.log(2 * math.e ** 3 / (2 * math.e ** 3 + 4))) / 2
    assert float(matching_loss(cos, T, labels, terrains)) == pytest.approx(expected, rel=1e-12)
    moved = cos.clone()
    moved[:, :, :, 2:] = torch.randn(1, n2, 1, 2, dtype=torch.float64)
    assert float(matching_loss(moved, T, labels, terrains)) == pytest.approx(expected, rel=1e-12)
    free = torch.randn(1, n2, 1, 4, dtype=torch.float64, requires_grad=True)
    none = matching_loss(free, T, torch.full((1, 1, 4), -1), terrains)
    none.backward()
    assert float(none.detach()) == 0.0 and bool(torch.all(free.grad == 0))
    torch.autograd.gradcheck(lambda c, t: matching_loss(c, t, labels, terrains),
                             (torch.randn(1, n2, 1, 4, dtype=torch.float64, requires_grad=True), T.clone().requires_grad_()))
    coarse = torch.randn(1, n2, 2, 2, dtype=torch.float64)
    fine = torch.nn.functional.interpolate(coarse, size=(4, 4), mode="bilinear", align_corners=False)
    grid = torch.tensor([[[0, 1, 2, 3]] * 4])
    assert float(matching_loss(coarse, T, grid, terrains)) == pytest.approx(float(matching_loss(fine, T, grid, terrains)))


def test_contrast_loss_is_the_mean_hinge_over_pixels_and_the_terrains_their_item_orders():
    """Analytic value: terrains at target costs 0, 0.5, 1 all predicted 0.5 cost the mean of each pixel's hinges
    (0.5, 1), (0.5, 0.5), (1, 0.5): 2/3 (margin 1) or 1/3 (margin 0.5); pixels out of view add nothing; a pair
    separated by its margin costs 0; two items that order the same look-alike terrains both ways push neither
    (the hinge is flat where the order cannot be told); no ordered pair is 0 with zero gradient; gradcheck."""
    labels = torch.tensor([[[0, 0, 1, 1, 2, 2, -1]]])
    target = torch.tensor([[[0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 0.0]]], dtype=torch.float64)
    logits = torch.zeros(1, 1, 7, dtype=torch.float64)
    assert float(contrast_loss(logits, target, labels)) == pytest.approx(2 / 3, rel=1e-12)
    assert float(contrast_loss(logits, target, labels, margin=0.5)) == pytest.approx(1 / 3, rel=1e-12)
    logits[..., -1] = 50.0  # out of view
    assert float(contrast_loss(logits, target, labels)) == pytest.approx(2 / 3, rel=1e-12)
    apart = torch.tensor([[[-9.0, -9.0, 0.0, 0.0, 9.0, 9.0, 0.0]]], dtype=torch.float64)
    assert float(contrast_loss(apart, target, labels, margin=0.9)) == 0.0
    shared = torch.tensor([[[0.3, 0.3, -0.2, -0.2]]], dtype=torch.float64, requires_grad=True)  # one look, two items
    pair_target = torch.tensor([[[0.0, 0.0, 1.0, 1.0]], [[1.0, 1.0, 0.0, 0.0]]], dtype=torch.float64)
    contrast_loss(shared.expand(2, 1, 4), pair_target, torch.tensor([[[0, 0, 1, 1]]] * 2)).backward()
    assert torch.allclose(shared.grad, torch.zeros_like(shared), atol=1e-15)
    one = torch.zeros(1, 1, 4, dtype=torch.float64, requires_grad=True)
    none = contrast_loss(one, torch.zeros(1, 1, 4, dtype=torch.float64), torch.tensor([[[0, 0, -1, 3]]]))
    none.backward()
    assert float(none.detach()) == 0.0 and bool(torch.all(one.grad == 0))
    torch.autograd.gradcheck(lambda x: contrast_loss(x, target, labels),
                             (torch.randn(1, 1, 7, dtype=torch.float64, requires_grad=True),))


def test_contrast_loss_charges_a_pixel_on_the_wrong_side_of_the_other_terrains_level():
    """Terrain means 0.3 and 1.0 are a margin 0.5 apart, yet one cheap-terrain pixel at cost 0.6 sits only
    0.4 below the costly terrain's mean: it alone is charged (0.1 over the 4 pixel-terrain terms) and only it is
    pushed down, the costly terrain's pixels up; a path follows pixels, not terrain means."""
    costs = torch.tensor([[[0.0, 0.6, 1.0 - 1e-9, 1.0 - 1e-9]]], dtype=torch.float64)
    logits = torch.logit(costs).requires_grad_(True)
    target = torch.tensor([[[0.0, 0.0, 1.0, 1.0]]], dtype=torch.float64)
    loss = contrast_loss(logits, target, torch.tensor([[[0, 0, 1, 1]]]), margin=0.5)
    assert float(loss.detach()) == pytest.approx(0.1 / 4, rel=1e-6)
    loss.backward()
    assert float(logits.grad[0, 0, 0]) == 0.0 and float(logits.grad[0, 0, 1]) > 0.0
    assert bool(torch.all(logits.grad[0, 0, 2:] <= 0.0))


def test_contrast_loss_matches_a_loop_over_pixels_and_terrains():
    """The vectorised hinge (each item's terrains packed into slots) equals the definition written as loops, on
    random batches with out-of-view pixels and terrain ids that repeat across items."""
    gen = torch.Generator().manual_seed(0)
    for _ in range(4):
        labels = torch.randint(-1, 9, (3, 5, 6), generator=gen)
        target = torch.rand(9, generator=gen, dtype=torch.float64)[labels.clamp_min(0)]
        logits = torch.randn(3, 5, 6, generator=gen, dtype=torch.float64)
        cost, terms = torch.sigmoid(logits), []
        for i in range(3):
            terrains = [int(t) for t in labels[i].unique() if t >= 0]
            level = {t: cost[i][labels[i] == t].mean() for t in terrains}
            wanted = {t: target[i][labels[i] == t].mean() for t in terrains}
            for r, c in torch.nonzero(labels[i] >= 0).tolist():
                own = int(labels[i, r, c])
                for other in terrains:
                    gap = float(wanted[other] - wanted[own])
                    if abs(gap) > 1e-6:
                        apart = (1 if gap > 0 else -1) * (level[other] - cost[i, r, c])
                        terms.append(torch.relu(0.7 * abs(gap) - apart))
        expected = torch.stack(terms).mean()
        assert float(contrast_loss(logits, target, labels, margin=0.7)) == pytest.approx(float(expected), rel=1e-12)


@pytest.mark.parametrize("share, weight, gap", [(0.5, 1.0, (0.0, 0.0)), (0.8, 0.0, (0.6, 0.6)),
                                                  (0.8, 1.0, (0.7, 1.0)), (0.8, 3.0, (0.85, 1.0))])
def test_contrast_hinge_widens_a_majority_order_and_leaves_a_tie_alone(share, weight, gap):
    """Two terrains one look apiece (one cost each) over 10 items, terrain 0 preferred in ``share`` of them:
    Eq. 3 alone is minimised at the calibrated costs (gap 2 share - 1: 0.6 at 0.8); the hinge widens a
    majority's gap towards the full target gap of 1 and leaves a 50/50 tie at Eq. 3's optimum (no gap)."""
    z = torch.zeros(2, dtype=torch.float64, requires_grad=True)
    k = round(10 * share)
    target = torch.tensor([[[0.0, 1.0]]] * k + [[[1.0, 0.0]]] * (10 - k), dtype=torch.float64)
    labels, fov = torch.tensor([[[0, 1]]] * 10), torch.ones(10, 1, 2, dtype=torch.bool)
    optimiser = torch.optim.LBFGS([z], max_iter=500, line_search_fn="strong_wolfe")

    def closure():
        optimiser.zero_grad()
        logits = z.expand(10, 1, 2)
        loss = masked_bce(logits, target, fov) + weight * contrast_loss(logits, target, labels)
        loss.backward()
        return loss

    optimiser.step(closure)
    cost = torch.sigmoid(z).detach()
    assert gap[0] - 1e-4 <= float(cost[1] - cost[0]) <= gap[1] + 1e-4


def test_matching_loss_trains_the_matcher_to_recognise_and_needs_one(smoke, tmp_path):
    """Trained by the matching loss alone (no cost targets), a fresh matcher's nearest context patch comes to name
    the right terrain for more pixels of held-out items than at the start; asking for the loss without a matcher
    is one clear error naming both parameters."""
    from navlab.pacer.model import TextureMatcher

    torch.manual_seed(0)
    torch.set_num_threads(1)
    matcher = TextureMatcher(tuple(smoke.model.match_channels), dilated=smoke.model.match_dilated)
    held_out = ContextOnlySet(16, seed=1)

    def accuracy() -> float:
        right = total = 0
        with torch.no_grad():
            for i in range(len(held_out)):
                item = held_out[i]
                cos = matcher.cosines(torch.as_tensor(item["image"])[None], *matcher.keys(torch.as_tensor(item["context"])[None]))
                cos = torch.nn.functional.interpolate(cos, size=item["labels"].shape, mode="bilinear", align_corners=False)
                found = np.concatenate([item["pairs"][:, 0], item["pairs"][:, 1]])[cos[0].argmax(0).numpy()]
                named = np.isin(item["labels"], item["pairs"])
                right, total = right + int((found == item["labels"])[named].sum()), total + int(named.sum())
        return right / total

    before = accuracy()
    optimiser = torch.optim.Adam(matcher.parameters(), lr=3e-3)
    train = ContextOnlySet(256, seed=0)
    for step in range(40):
        batch = [train[(8 * step + k) % len(train)] for k in range(8)]
        image, context, labels, pairs = (torch.as_tensor(np.stack([b[k] for b in batch]))
                                         for k in ("image", "context", "labels", "pairs"))
        loss = matching_loss(matcher.cosines(image, *matcher.keys(context)), matcher.log_temperature.exp(), labels,
                             torch.cat([pairs[:, :, 0], pairs[:, :, 1]], dim=1))
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
    assert accuracy() > before + 0.1, (before, accuracy())
    no_matcher = dataclasses.replace(smoke.model, match_channels=())
    with pytest.raises(ValueError, match="match_loss_weight.*match_channels"):
        train_phase(no_matcher, tiny_train_cfg(smoke, match_loss_weight=1.0), [TinyTerrainSet(8)], [TinyTerrainSet(4)],
                    tmp_path, PhaseRun("phase1", epochs=1, seed=0), progress=False)
    assert not any(tmp_path.iterdir())  # refused before anything was written


@pytest.mark.parametrize("profile", ["smoke", "default"])
def test_model_output_shape_and_range(profile):
    torch.manual_seed(0)
    model = build_model(load_params(profile).pacer.model).eval()
    item = TinyTerrainSet(1)[0]
    image = torch.as_tensor(item["image"])[None].repeat(2, 1, 1, 1)
    context = torch.as_tensor(item["context"])[None].repeat(2, 1, 1, 1)
    logits = model(image, context)
    assert logits.shape == (2, H, W)
    cost = model.costmap(image * 0 + 10, context)  # extreme input: still a cost in [0, 1]
    assert cost.min() >= 0 and cost.max() <= 1
    with pytest.raises(ValueError, match="multiples of"):
        model(image[..., :30], context)


def test_context_changes_the_costmap(smoke):
    torch.manual_seed(0)
    model = build_model(smoke.model).eval()
    for film in model.film:  # FiLM starts as identity; give it weights so the context can act
        torch.nn.init.normal_(film.affine.weight, std=0.5)
    a, b = TinyTerrainSet(2)[0], TinyTerrainSet(2, ordering=(2, 1, 0))[0]
    image = torch.as_tensor(a["image"])[None]
    out_a = model(image, torch.as_tensor(a["context"])[None])
    out_b = model(image, torch.as_tensor(b["context"])[None])
    assert not torch.allclose(out_a, out_b)


def test_context_encoder_tells_the_preferred_patch_from_the_other(smoke):
    """Swapping the two patches of every pair (the inverted context) exchanges the two feature blocks the
    head reads, so a context and its inversion embed differently."""
    torch.manual_seed(0)
    encoder = build_model(smoke.model).context_encoder.eval()
    context = torch.as_tensor(TinyTerrainSet(1)[0]["context"])[None]
    swapped = torch.cat(context.chunk(2, dim=2)[::-1], dim=2)
    seen = []
    hook = encoder.head.register_forward_hook(lambda module, args, out: seen.append(args[0].detach()))
    with torch.no_grad():
        z, z_swapped = encoder(context), encoder(swapped)
    hook.remove()
    preferred, other = seen[0].chunk(2, dim=1)
    assert torch.allclose(seen[1], torch.cat([other, preferred], dim=1), atol=1e-6)
    assert not torch.allclose(preferred, other, atol=1e-3) and not torch.allclose(z, z_swapped, atol=1e-4)


def test_early_stopping_keeps_the_best_validation_checkpoint(smoke, tmp_path):
    cfg = tiny_train_cfg(smoke, lr=0.05, patience=2, lr_final_fraction=0.5)
    train, val = TinyTerrainSet(16), TinyTerrainSet(6, seed=1)
    path = train_phase(smoke.model, cfg, [train], [val], tmp_path, PhaseRun("phase1", epochs=12, seed=0), progress=False)
    log = np.loadtxt(tmp_path / "val_loss.tsv", skiprows=1, ndmin=2)
    summary = read_summary(tmp_path)
    best = int(np.argmin(log[:, 2]))
    assert summary["best_epoch"] == best + 1 and summary["best_val_loss"] == pytest.approx(log[best, 2], abs=1e-6)
    # the saved model is the best epoch's, not the last one's (the last epochs are worse when it stopped)
    assert validation_loss(load_model(path), [val], 4) == pytest.approx(log[best, 2], rel=1e-5)
    if summary["stopped_early"]:
        assert len(log) - summary["best_epoch"] == cfg.patience and log[-1, 2] > log[best, 2]
    else:
        assert len(log) == 12
    # BCE against soft targets is bounded below by their entropy: here 1/2-cost pixels give ln 2 each
    pixels = [(it["costmap"][it["fov_mask"]]) for it in (val[i] for i in range(len(val)))]
    half = np.mean(np.concatenate(pixels) == 0.5)
    assert summary["entropy_floor"] == pytest.approx(half * np.log(2), rel=1e-6)
    assert summary["best_val_loss"] >= summary["entropy_floor"]


def test_asking_for_cuda_without_a_gpu_is_one_clear_error(monkeypatch):
    monkeypatch.setattr(torch.cuda, "is_available", lambda: False)
    with pytest.raises(ValueError, match="sees no CUDA GPU"):
        resolve_device("cuda")
    assert resolve_device("cpu").type == "cpu"


def test_epoch_draws_cover_every_dataset_and_repeat():
    draws = epoch_draws([5, 100], 400, seed=0, phase="phase2", epoch=3)
    which = np.array([d for d, _ in draws])
    assert 0.4 < which.mean() < 0.6  # datasets uniformly, not examples
    assert all(0 <= i < (5, 100)[d] for d, i in draws)
    assert draws == epoch_draws([5, 100], 400, seed=0, phase="phase2", epoch=3)
    assert draws != epoch_draws([5, 100], 400, seed=0, phase="phase2", epoch=4)


class Killed(Exception):
    pass


class KillAfter(torch.utils.data.Dataset):
    """Raises after ``limit`` reads, as a killed process stops mid-epoch."""

    def __init__(self, inner, limit):
        self.inner, self.limit, self.reads = inner, limit, 0

    def __len__(self):
        return len(self.inner)

    def __getitem__(self, i):
        self.reads += 1
        if self.reads > self.limit:
            raise Killed
        return self.inner[i]


def test_resume_after_a_kill_matches_an_uninterrupted_run(smoke, tmp_path):
    cfg = tiny_train_cfg(smoke)
    train, val = TinyTerrainSet(16), TinyTerrainSet(4, seed=1)
    whole = train_phase(smoke.model, cfg, [train], [val], tmp_path / "whole", PhaseRun("phase1", epochs=2, seed=0),
                        progress=False)
    with pytest.raises(Killed):  # dies in the middle of epoch 2, after epoch 1's checkpoint
        train_phase(smoke.model, cfg, [KillAfter(train, 12)], [val], tmp_path / "resumed", PhaseRun("phase1",
                    epochs=2, seed=0), progress=False)
    assert (tmp_path / "resumed" / "checkpoint.pt").is_file() and not (tmp_path / "resumed" / "model.pt").exists()
    resumed = train_phase(smoke.model, cfg, [train], [val], tmp_path / "resumed",
                          PhaseRun("phase1", epochs=2, seed=0), progress=False)
    a, b = load_model(whole).state_dict(), load_model(resumed).state_dict()
    assert all(torch.equal(a[k], b[k]) for k in a)
    log = (tmp_path / "resumed" / "val_loss.tsv").read_text().splitlines()
    assert log[0].split("\t") == ["epoch", "train_loss", "val_loss", "select_score"] and len(log) == 3
    assert log == (tmp_path / "whole" / "val_loss.tsv").read_text().splitlines()


class CountReads(torch.utils.data.Dataset):
    """Counts the items read (each read renders an item in the real datasets)."""

    def __init__(self, inner):
        self.inner, self.reads = inner, 0

    def __len__(self):
        return len(self.inner)

    def __getitem__(self, i):
        self.reads += 1
        return self.inner[i]


def test_validation_items_are_rendered_once_per_phase_and_weights_saved_in_standard_layout(smoke, tmp_path):
    cfg = tiny_train_cfg(smoke, patience=10)
    val = CountReads(TinyTerrainSet(6, seed=1))
    path = train_phase(smoke.model, cfg, [TinyTerrainSet(16)], [val], tmp_path, PhaseRun("phase1", epochs=3, seed=0),
                       progress=False)
    assert read_summary(tmp_path)["epochs_run"] == 3 and val.reads == len(val)
    saved = torch.load(path, weights_only=False)["weights"]
    assert all(w.is_contiguous() for w in saved.values())  # channels-last is a training detail, not the file's


def test_phase_two_starts_from_phase_one_weights(smoke, tmp_path):
    cfg = tiny_train_cfg(smoke)
    train, val = TinyTerrainSet(16), TinyTerrainSet(4, seed=1)
    first = train_phase(smoke.model, cfg, [train], [val], tmp_path / "p1", PhaseRun("phase1", epochs=2, seed=0),
                        progress=False)
    slow = dataclasses.replace(cfg, lr=1e-6)
    second = train_phase(smoke.model, slow, [train, TinyTerrainSet(16, (2, 0, 1))], [val], tmp_path / "p2",
                         PhaseRun("phase2", epochs=1, seed=0, init_from=first), progress=False)
    fresh = train_phase(smoke.model, slow, [train], [val], tmp_path / "fresh", PhaseRun("phase2", epochs=1, seed=0),
                        progress=False)
    w1, w2, w0 = (dict(load_model(p).named_parameters()) for p in (first, second, fresh))
    moved_from_phase1 = max((w2[k] - w1[k]).abs().max().item() for k in w1)
    fresh_gap = max((w0[k] - w1[k]).abs().max().item() for k in w1)
    assert moved_from_phase1 < 1e-4 < fresh_gap


def test_semantic_classifier_separates_terrains(smoke, tmp_path):
    data = [TinyTerrainSet(12)]
    cfg = dataclasses.replace(smoke.baselines.classifier, epochs=3, patches_per_epoch=96, batch_size=16, lr=0.01,
                              val_patches=64)
    model, summary = train_classifier(data, cfg, PATCH, seed=0, checkpoint=tmp_path / "classifier.pt", progress=False,
                                      val_datasets=[TinyTerrainSet(6, seed=3)])
    assert set(model.labels) <= {0, 1, 2}
    assert 1 <= summary["best_epoch"] <= 3 and summary["val_accuracy"] > 0.9
    item = TinyTerrainSet(4, seed=7)[0]
    predicted = model.label_map(torch.as_tensor(item["image"])).numpy()
    split = int(np.argmax(item["labels"][0] != item["labels"][0, 0]))
    cols = np.arange(W)[None, :].repeat(H, 0)
    interior = (np.abs(cols - split) >= PATCH) & (cols < W - PATCH)  # away from the boundary and the edge
    assert (predicted[interior] == item["labels"][interior]).mean() > 0.9
    costs = model.costmap(torch.as_tensor(item["image"]), {0: 0.0, 1: 0.5, 2: 1.0})
    assert costs.shape == (H, W)
    with pytest.raises(ValueError, match="lacks seen labels"):
        model.costmap(torch.as_tensor(item["image"]), {0: 0.0})


def test_a_killed_classifier_run_resumes_to_the_uninterrupted_weights(smoke, tmp_path, monkeypatch):
    """Issue 62: the baselines train through core.training.fit; a run killed after its first epoch and started
    again continues from the checkpoint (each epoch's shuffle has its own generator) to the same weights."""
    from navlab.pacer.baselines import semantic_classifier

    data, val = [TinyTerrainSet(12)], [TinyTerrainSet(6, seed=3)]
    cfg = dataclasses.replace(smoke.baselines.classifier, epochs=3, patches_per_epoch=64, batch_size=16, lr=0.01,
                              val_patches=32)
    whole, summary = train_classifier(data, cfg, PATCH, seed=0, checkpoint=tmp_path / "whole.pt", progress=False,
                                      val_datasets=val)
    measured = semantic_classifier.patch_accuracy
    calls = []

    def killed_in_epoch_two(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return measured(*args, **kwargs)

    monkeypatch.setattr(semantic_classifier, "patch_accuracy", killed_in_epoch_two)
    with pytest.raises(KeyboardInterrupt):
        train_classifier(data, cfg, PATCH, seed=0, checkpoint=tmp_path / "killed.pt", progress=False, val_datasets=val)
    monkeypatch.setattr(semantic_classifier, "patch_accuracy", measured)
    resumed, resumed_summary = train_classifier(data, cfg, PATCH, seed=0, checkpoint=tmp_path / "killed.pt",
                                                progress=False, val_datasets=val)
    assert resumed_summary == summary
    for name, weight in whole.state_dict().items():
        assert torch.equal(weight, resumed.state_dict()[name]), name


def test_vicreg_terms():
    gen = torch.Generator().manual_seed(0)
    z = torch.randn(64, 8, generator=gen) * 2
    collapsed = torch.zeros(64, 8)
    assert vicreg_loss(z, z, (25, 25, 1)) < vicreg_loss(collapsed, collapsed, (25, 25, 1))
    assert vicreg_loss(z, z, (1, 0, 0)) == 0 and vicreg_loss(z, z + 1, (1, 0, 0)) == pytest.approx(1.0)
    views = augment(torch.rand(4, 3, 8, 8, generator=gen), gen)
    assert views.shape == (4, 3, 8, 8) and views.min() >= 0 and views.max() <= 1


def test_sterling_utility_follows_the_context(smoke, tmp_path):
    cfg = dataclasses.replace(smoke.baselines.sterling, epochs=2, patches_per_epoch=64, batch_size=32)
    model = train_sterling([TinyTerrainSet(12)], cfg, PATCH, seed=0, checkpoint=tmp_path / "sterling.pt", progress=False)
    assert isinstance(model, SterlingEncoder)
    for ordering in ((0, 1, 2), (2, 1, 0)):
        item = TinyTerrainSet(4, ordering=ordering, seed=3)[1]
        utility = model.fit_utility(torch.as_tensor(item["context"]), steps=100)
        cost = model.costmap(torch.as_tensor(item["image"]), utility).numpy()
        present = np.unique(item["labels"])
        means = {lab: cost[item["labels"] == lab].mean() for lab in present}
        best, worst = sorted(present, key=ordering.index)
        assert means[best] < means[worst]


class PixelModel(torch.nn.Module):
    """A per-pixel 'network' (logit = 4·(red − 0.5)): stitched windows must reproduce it exactly."""

    def forward(self, image, context):
        return 4 * (image[:, 0] - 0.5)


def test_costmap_over_map_stitches_fov_windows_exactly():
    from navlab.pacer.bev import fov_mask
    from navlab.pacer.evaluate import costmap_over_map

    gen = torch.Generator().manual_seed(0)
    image = torch.rand(3, 48, 40, generator=gen)
    mask = fov_mask(16, 0.35)
    for overlap in (2, 4):
        cost = costmap_over_map(PixelModel(), image, torch.zeros(9, 16, 8), mask, overlap=overlap)
        assert cost.shape == (48, 40)
        assert torch.allclose(cost, torch.sigmoid(4 * (image[0] - 0.5)), atol=1e-5)


def test_context_pair_agreement_counts_visible_pairs():
    from navlab.pacer.evaluate import context_pair_agreement

    labels = np.array([[0, 0, 1, 1], [2, 2, 1, 1]])
    mask = np.ones_like(labels, dtype=bool)
    predicted = np.array([[0.1, 0.1, 0.5, 0.5], [0.9, 0.9, 0.5, 0.5]])
    # 0 ≻ 1 agrees, 2 ≻ 1 disagrees, 3 is not in view, a self-pair is skipped
    assert context_pair_agreement(predicted, labels, mask, np.array([[0, 1], [2, 1], [3, 0], [1, 1]])) == (1, 2)
    mask[1] = False  # terrain 2 leaves the view
    assert context_pair_agreement(predicted, labels, mask, np.array([[0, 1], [2, 1]])) == (1, 1)


def test_crossing_queries_span_opposite_edges():
    from navlab.pacer.evaluate import crossing_queries

    queries = crossing_queries(100, 40, rng(0, "queries"))
    assert queries == crossing_queries(100, 40, rng(0, "queries"))
    for start, goal in queries:
        assert all(0 <= v < 100 for v in (*start, *goal))
        # one coordinate goes from one edge band to the other: the path must cross the map
        assert max(abs(start[0] - goal[0]), abs(start[1] - goal[1])) >= 90


class ContextOnlySet(torch.utils.data.Dataset):
    """Two flat, noisy terrains of colours drawn per item (never the same two twice), split left/right;
    which one is preferred is drawn per item too and shown only by the context (3 pairs, preferred on
    top). No terrain identity carries a cost: only following the context fits the target."""

    def __init__(self, size: int, seed: int):
        self.size, self.seed = size, seed

    def __len__(self):
        return self.size

    def __getitem__(self, i):
        gen = rng(self.seed, "context-only", i)
        colours = gen.uniform(0.1, 0.9, size=(2, 3))
        while np.abs(colours[0] - colours[1]).max() < 0.3:
            colours[1] = gen.uniform(0.1, 0.9, size=3)

        def flat(k, shape):
            return np.clip(colours[k][:, None, None] + 0.05 * gen.standard_normal((3, *shape)), 0, 1)

        split = int(gen.integers(10, W - 10))
        labels = np.where(np.arange(W)[None, :] < split, 0, 1).repeat(H, 0).astype(np.int64)
        image = np.where(labels[None] == 0, flat(0, (H, W)), flat(1, (H, W))).astype(np.float32)
        preferred = int(gen.integers(2))
        context = np.concatenate([np.concatenate([flat(preferred, (PATCH, PATCH)), flat(1 - preferred, (PATCH, PATCH))],
                                                 axis=1) for _ in range(3)]).astype(np.float32)
        return {"image": image, "context": context, "costmap": (labels != preferred).astype(np.float32),
                "fov_mask": np.ones((H, W), dtype=bool), "labels": labels,
                "pairs": np.array([[preferred, 1 - preferred]] * 3)}


def test_match_evidence_flips_with_the_context_and_ignores_pair_order(smoke):
    """The texture matcher's evidence S changes sign when every pair is swapped (the inverted context)
    and does not depend on the order of the pairs."""
    torch.manual_seed(0)
    model = build_model(smoke.model).eval()
    assert model.matcher is not None
    item = ContextOnlySet(1, seed=5)[0]
    image, context = torch.as_tensor(item["image"])[None], torch.as_tensor(item["context"])[None]
    swapped = torch.cat(context.chunk(2, dim=2)[::-1], dim=2)
    reordered = torch.cat([context[:, 6:9], context[:, 0:3], context[:, 3:6]], dim=1)
    with torch.no_grad():
        match, match_swapped, match_reordered = (model.matcher(image, c) for c in (context, swapped, reordered))
    # float32 sums in another order (another thread count, another kernel) differ by a few ulps of the
    # summands; a sign or pairing error would be of the evidence's own size
    atol = 1e-4 * float(match.abs().max().clamp(min=1.0))
    torch.testing.assert_close(match_swapped[:, 0], -match[:, 0], rtol=0, atol=atol)
    torch.testing.assert_close(match_swapped[:, 1], match[:, 1], rtol=0, atol=atol)
    torch.testing.assert_close(match_reordered, match, rtol=0, atol=atol)
    assert float(match[:, 0].abs().max()) > 100 * atol  # the evidence is not ~0, so the sign test bites


@pytest.mark.parametrize("channels", [(8, 8), (4, 4, 4)])
def test_dilated_matcher_keeps_full_resolution_and_its_receptive_field(channels):
    """The dilated tower (issue 24) gives one cosine per image pixel, and a pixel's cosines depend on the image
    within 1 + 4 (2^K - 1) px around it only (K stages, dilations 1, 2, 4, ...): a change of one pixel moves the
    cosines inside that window and nowhere else, so a thin strip is matched on its own texture and its near
    surroundings, not on a pooled cell. The pooled tower (``dilated=False``) gives one cell per 2^K pixels."""
    from navlab.pacer.model import TextureMatcher

    torch.manual_seed(0)
    dilated, pooled = TextureMatcher(channels, dilated=True).double(), TextureMatcher(channels).double()
    image, context = torch.rand(1, 3, 48, 48, dtype=torch.float64), torch.rand(1, 9, 16, 8, dtype=torch.float64)
    keys, centre = dilated.keys(context)
    base = dilated.cosines(image, keys, centre)
    assert base.shape == (1, 6, 48, 48)
    assert pooled.cosines(image, *pooled.keys(context)).shape == (1, 6, 48 // 2 ** len(channels), 48 // 2 ** len(channels))
    poked = image.clone()
    poked[0, :, 24, 24] += 0.5
    moved = (dilated.cosines(poked, keys, centre) - base).abs().amax(dim=(0, 1)) > 1e-12
    reach = 2 * (2 ** len(channels) - 1)  # half the receptive field
    rows, cols = torch.nonzero(moved, as_tuple=True)
    assert moved[24, 24]
    assert int(rows.min()) >= 24 - reach and int(rows.max()) <= 24 + reach
    assert int(cols.min()) >= 24 - reach and int(cols.max()) <= 24 + reach
    assert int(rows.max() - rows.min()) > reach  # it does reach beyond the pixel's own neighbourhood


def test_luminance_branch_concatenates_a_tower_blind_to_colour():
    """With ``luminance`` the matcher's features are the colour tower's (the very features of a colour-only
    matcher with the same weights) followed by a grey tower's, one cosine over both. The grey tower is blind to
    any change of colour that keeps each pixel's channel mean (here: the channels permuted), the colour tower
    is not."""
    from navlab.pacer.model import TextureMatcher

    torch.manual_seed(0)
    both = TextureMatcher((8, 8), dilated=True, luminance=True).double()
    colour = TextureMatcher((8, 8), dilated=True).double()
    colour.load_state_dict({k: v for k, v in both.state_dict().items() if not k.startswith("grey_")})
    image, context = torch.rand(2, 3, 32, 32, dtype=torch.float64), torch.rand(2, 9, 16, 8, dtype=torch.float64)
    features = both.embed(image)
    assert features.shape == (2, 16, 32, 32)
    assert torch.equal(features[:, :8], colour.embed(image))
    keys, centre = both.keys(context)
    assert torch.allclose(keys.norm(dim=2), torch.ones(2, 6, dtype=torch.float64))
    cos = both.cosines(image, keys, centre)
    assert cos.shape == (2, 6, 32, 32) and float(cos.detach().abs().max()) <= 1 + 1e-12
    permute = [2, 0, 1]
    hue = image[:, permute]
    assert torch.allclose(both.embed(hue)[:, 8:], features[:, 8:], atol=1e-12)
    assert not torch.allclose(both.embed(hue)[:, :8], features[:, :8], atol=1e-3)
    hue_context = context.reshape(2, 3, 3, 16, 8)[:, :, permute].reshape(2, 9, 16, 8)
    assert not torch.allclose(both.cosines(hue, *both.keys(hue_context)), cos, atol=1e-3)


def test_brief_training_follows_the_context_on_terrains_it_never_saw(smoke):
    """Trained briefly (30 steps) where only the context tells which terrain is preferred, the model gives
    the preferred terrain the lower cost on held-out items of colours it never saw, and swaps its costs
    when the context is inverted (the two patches of every pair exchanged). The texture matcher binds
    context patches to image locations by appearance, so this holds from the first few steps; the same
    network without it (FiLM only: ``match_channels: []``) gets 27/32 both ways here and needs
    ~150 steps for what the matcher does in 20."""
    torch.manual_seed(0)
    torch.set_num_threads(1)
    model = build_model(smoke.model)
    optimiser = torch.optim.Adam(model.parameters(), lr=3e-3)
    train = ContextOnlySet(512, seed=0)
    for step in range(30):
        batch = [train[(8 * step + k) % len(train)] for k in range(8)]
        stack = {k: torch.as_tensor(np.stack([b[k] for b in batch])) for k in ("image", "context", "costmap", "fov_mask")}
        loss = masked_bce(model(stack["image"], stack["context"]), stack["costmap"], stack["fov_mask"])
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
    model.eval()
    held_out = ContextOnlySet(32, seed=1)
    follows = flips = 0
    for i in range(len(held_out)):
        item = held_out[i]
        image, context = torch.as_tensor(item["image"])[None], torch.as_tensor(item["context"])[None]
        swapped = torch.cat(context.chunk(2, dim=2)[::-1], dim=2)
        preferred = item["labels"] == item["pairs"][0, 0]
        cost, cost_swapped = (model.costmap(image, c)[0].numpy() for c in (context, swapped))
        follows += cost[preferred].mean() < cost[~preferred].mean()
        flips += cost_swapped[preferred].mean() > cost_swapped[~preferred].mean()
    assert follows >= 30 and flips >= 30, (follows, flips)


def _terrain_keys(terrains: list[int]) -> torch.Tensor:
    """(1, 2n, 8) keys: one unit vector per terrain id, so patches of a terrain are identical and others orthogonal."""
    return torch.eye(8)[terrains][None]


@pytest.mark.parametrize("pairs, places", [
    ([(0, 1), (1, 2), (2, 3)], {0: 1.0, 1: 1 / 3, 2: -1 / 3, 3: -1.0}),       # a chain: its order
    ([(0, 1), (2, 3), (4, 5)], {0: 1.0, 2: 1.0, 4: 1.0, 1: -1.0, 3: -1.0, 5: -1.0}),  # disjoint: the roles
    ([(0, 1), (0, 2), (3, 0)], {3: 1.0, 0: 1 / 3, 1: -1.0, 2: -1.0}),          # 3 > 0 > {1, 2}
])
def test_patch_ranks_place_each_terrain_in_the_order_the_pairs_imply(smoke, pairs, places):
    """The matcher's order inference: transitive wins and losses over distinct terrains (a Copeland score)
    give a chain's terrains evenly spaced places, disjoint pairs +1 / -1, and every patch of a terrain the
    same place; swapping every pair negates the places, reordering the pairs permutes them."""
    matcher = build_model(smoke.model).matcher
    with torch.no_grad():
        matcher.log_same_sharpness.fill_(math.log(100.0))  # crisp identities: exact places
    preferred, other = zip(*pairs)
    keys = _terrain_keys([*preferred, *other])
    with torch.no_grad():
        ranks = matcher.patch_ranks(keys)[0]
        swapped = matcher.patch_ranks(_terrain_keys([*other, *preferred]))[0]
        order = [2, 0, 1]
        reordered = matcher.patch_ranks(_terrain_keys([preferred[i] for i in order] + [other[i] for i in order]))[0]
    expected = torch.tensor([places[t] for t in [*preferred, *other]])
    torch.testing.assert_close(ranks, expected, rtol=0, atol=1e-4)
    torch.testing.assert_close(swapped, -torch.cat([ranks[3:], ranks[:3]]), rtol=0, atol=1e-4)
    torch.testing.assert_close(reordered, torch.cat([ranks[:3][order], ranks[3:][order]]), rtol=0, atol=1e-4)


def test_patch_ranks_pass_gradients_to_the_patch_features(smoke):
    """The identities are soft, so the order inference trains the patch features too (a gradient check
    against finite differences in double precision)."""
    matcher = build_model(smoke.model).matcher.double()
    keys = torch.nn.functional.normalize(torch.randn(1, 6, 8, dtype=torch.float64, generator=torch.Generator().manual_seed(0)), dim=2)
    keys.requires_grad_(True)
    assert torch.autograd.gradcheck(lambda k: matcher.patch_ranks(k), (keys,))


def test_imagenet_matcher_trains_its_projection_and_never_its_features(smoke):
    """``match_features: imagenet`` (issue 61): a training step of the whole model moves the matcher's 1 x 1
    projection and leaves the ImageNet layers bit for bit as loaded (frozen, eval mode); the scratch matcher
    trains its towers. The saved model carries the layers it runs (up to stride 8), so it loads alone."""
    from navlab.pacer.pretrained import ImageNetFeatures

    for kind in ("imagenet", "scratch"):
        torch.manual_seed(0)
        model = build_model(dataclasses.replace(smoke.model, match_features=kind)).train()
        features = model.matcher.features
        assert isinstance(features, ImageNetFeatures) == (kind == "imagenet")
        before = {k: v.clone() for k, v in model.matcher.state_dict().items()}
        item = ContextOnlySet(2, seed=3)
        batch = {k: torch.stack([torch.as_tensor(item[i][k]) for i in range(2)])
                 for k in ("image", "context", "costmap", "fov_mask")}
        optimiser = torch.optim.Adam(model.parameters(), lr=0.01)
        masked_bce(model(batch["image"], batch["context"]), batch["costmap"], batch["fov_mask"]).backward()
        optimiser.step()
        after = model.matcher.state_dict()
        moved = {k for k in before if not torch.equal(before[k], after[k])}
        assert any(k.startswith("project.") for k in moved)
        if kind == "imagenet":
            assert not features.training and not any(k.startswith("features.") for k in moved)
        else:
            assert any(k.startswith("features.") for k in moved)
