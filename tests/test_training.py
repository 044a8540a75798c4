"""navlab.core.training: the cosine schedule gives the very learning rates of the loops it replaced, a killed
and resumed ``fit`` ends where an unbroken one does, and ``fit`` keeps the best epoch.

Why bit-for-bit: the committed PACER and SuReNav weights were trained with the hand-written schedules; a
rate one ulp off changes every weight after it. All on a tiny synthetic model, no data.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch

from navlab.core.seeding import rng
from navlab.core.training import TrainingRun, cosine_factor, cosine_schedule, descend, fit


def pacer_lr(step: int, total: int, lr: float, final_fraction: float) -> float:
    """PACER's hand-written schedule before ``cosine_schedule`` (set before every step)."""
    progress = min(step, total) / max(total, 1)
    return lr * (final_fraction + (1.0 - final_fraction) * 0.5 * (1.0 + np.cos(np.pi * progress)))


def classifier_lr(step: int, total: int, lr: float) -> float:
    """The semantic classifier's hand-written schedule before ``cosine_schedule``."""
    return lr * 0.5 * (1.0 + math.cos(math.pi * step / total))


def scheduled_rates(total: int, lr: float, final_fraction: float = 0.0, pi_first: bool = False) -> list[float]:
    """The rate each of ``total`` optimiser steps runs at under ``cosine_schedule``."""
    optimiser = torch.optim.SGD([torch.nn.Parameter(torch.zeros(1))], lr=lr)
    schedule = cosine_schedule(optimiser, total, final_fraction, pi_first=pi_first)
    rates = []
    for _ in range(total):
        rates.append(optimiser.param_groups[0]["lr"])
        optimiser.step()
        schedule.step()
    return rates


# step counts of the profiles: PACER smoke (2 x 2), default-like phases; the classifier's default and paper runs
@pytest.mark.parametrize("total", [1, 4, 16, 130, 960, 3200])
def test_cosine_schedule_gives_the_hand_written_rates_bit_for_bit(total):
    for lr, final in ((3e-3, 0.02), (1e-3, 0.1), (2e-3, 0.0)):
        assert scheduled_rates(total, lr, final) == [pacer_lr(k, total, lr, final) for k in range(total)]
    assert scheduled_rates(total, 2e-3, pi_first=True) == [classifier_lr(k, total, 2e-3) for k in range(total)]


def test_the_two_angles_round_differently_which_is_why_both_exist():
    assert any(cosine_factor(k, 960) != cosine_factor(k, 960, pi_first=True) for k in range(960))


def test_cosine_factor_runs_from_one_to_the_final_fraction():
    assert cosine_factor(0, 100, 0.1) == 1.0
    assert cosine_factor(50, 100, 0.1) == pytest.approx(0.1 + 0.9 * 0.5)
    assert cosine_factor(100, 100, 0.1) == pytest.approx(0.1)
    assert cosine_factor(150, 100, 0.1) == cosine_factor(100, 100, 0.1)  # flat after the end
    assert all(np.diff([cosine_factor(k, 100) for k in range(101)]) <= 0)


def test_a_reloaded_schedule_continues_with_the_same_rates():
    whole = scheduled_rates(20, 1e-2, 0.05)
    optimiser = torch.optim.SGD([torch.nn.Parameter(torch.zeros(1))], lr=1e-2)
    schedule = cosine_schedule(optimiser, 20, 0.05)
    for _ in range(7):
        optimiser.step()
        schedule.step()
    states = optimiser.state_dict(), schedule.state_dict()
    optimiser = torch.optim.SGD([torch.nn.Parameter(torch.zeros(1))], lr=1e-2)
    schedule = cosine_schedule(optimiser, 20, 0.05)
    optimiser.load_state_dict(states[0])
    schedule.load_state_dict(states[1])
    rest = []
    for _ in range(13):
        rest.append(optimiser.param_groups[0]["lr"])
        optimiser.step()
        schedule.step()
    assert rest == whole[7:]


def test_descend_is_zero_grad_backward_step_then_schedule():
    torch.manual_seed(0)
    a, b = torch.nn.Linear(3, 1), torch.nn.Linear(3, 1)
    b.load_state_dict(a.state_dict())
    x = torch.randn(8, 3)
    opt_a, opt_b = torch.optim.Adam(a.parameters(), lr=0.1), torch.optim.Adam(b.parameters(), lr=0.1)
    sched = cosine_schedule(opt_a, 3)
    for k in range(3):
        descend(a(x).pow(2).mean(), opt_a, sched)
        for group in opt_b.param_groups:
            group["lr"] = 0.1 * cosine_factor(k, 3)
        opt_b.zero_grad()
        b(x).pow(2).mean().backward()
        opt_b.step()
    assert all(torch.equal(p, q) for p, q in zip(a.parameters(), b.parameters()))


class Killed(Exception):
    pass


def tiny_run(folder, key: str = "k", epochs: int = 4, kill_at: int | None = None):
    """A small regression with dropout (torch's RNG) and a cosine schedule, trained by ``fit`` in ``folder``;
    raises Killed at the start of epoch ``kill_at``."""
    gen = torch.Generator().manual_seed(1)
    x = torch.randn(24, 5, generator=gen)
    y = x @ torch.randn(5, 1, generator=gen)
    torch.manual_seed(0)
    model = torch.nn.Sequential(torch.nn.Linear(5, 8), torch.nn.Dropout(0.3), torch.nn.Linear(8, 1))
    optimiser = torch.optim.Adam(model.parameters(), lr=0.05)
    schedule = cosine_schedule(optimiser, epochs * 3, 0.1)

    def train_epoch(epoch: int) -> dict[str, float]:
        if epoch == kill_at:
            raise Killed
        order = torch.from_numpy(rng(0, "test.training", epoch).permutation(len(x)))
        losses = []
        for lo in range(0, len(x), 8):
            idx = order[lo:lo + 8]
            loss = (model(x[idx]) - y[idx]).pow(2).mean()
            descend(loss, optimiser, schedule)
            losses.append(float(loss.detach()))
        with torch.no_grad():
            val = float((model.eval()(x) - y).pow(2).mean())
        return {"train_loss": float(np.mean(losses)), "val_loss": val}

    fitted = fit(model, optimiser, TrainingRun(folder / "checkpoint.pt", key, epochs, progress=False), train_epoch,
                 lambda row, best: row["val_loss"] < best["val_loss"], scheduler=schedule)
    return model, fitted


def test_a_killed_and_resumed_fit_ends_at_the_weights_of_an_unbroken_one(tmp_path):
    whole, whole_fit = tiny_run(tmp_path / "whole")
    with pytest.raises(Killed):
        tiny_run(tmp_path / "resumed", kill_at=2)
    assert [r["epoch"] for r in torch.load(tmp_path / "resumed" / "checkpoint.pt", weights_only=False)["log"]] == [1, 2]
    torch.manual_seed(123)  # whatever the process drew since: the checkpoint's RNG state is put back
    resumed, resumed_fit = tiny_run(tmp_path / "resumed")
    assert resumed_fit.log == whole_fit.log and resumed_fit.best == whole_fit.best
    a, b = whole.state_dict(), resumed.state_dict()
    assert all(torch.equal(a[k], b[k]) for k in a)
    # another key never resumes this checkpoint: it trains from scratch (and so agrees with the unbroken run)
    with pytest.raises(Killed):
        tiny_run(tmp_path / "other", kill_at=2)
    _, other_fit = tiny_run(tmp_path / "other", key="another")
    assert other_fit.log == whole_fit.log


def scripted(folder, val: list[float], patience: int):
    """``fit`` over epochs whose validation losses are ``val``; returns (fitted, model's weight, weights by epoch)."""
    model = torch.nn.Linear(1, 1, bias=False)
    optimiser = torch.optim.SGD(model.parameters(), lr=0.1)
    seen = {}

    def train_epoch(epoch: int) -> dict[str, float]:
        with torch.no_grad():
            model.weight.fill_(float(epoch + 1))  # the epoch's weights name it
        seen[epoch + 1] = model.weight.item()
        return {"val_loss": val[epoch]}

    fitted = fit(model, optimiser, TrainingRun(folder / "checkpoint.pt", "k", len(val), patience, progress=False),
                 train_epoch, lambda row, best: row["val_loss"] < best["val_loss"])
    return fitted, model.weight.item(), seen


def test_fit_keeps_the_best_epoch_and_stops_after_patience(tmp_path):
    fitted, weight, seen = scripted(tmp_path / "a", [0.5, 0.3, 0.4, 0.2, 0.6, 0.7, 0.1], patience=2)
    assert fitted.best_epoch == 4 and weight == seen[4] == 4.0
    assert [r["epoch"] for r in fitted.log] == [1, 2, 3, 4, 5, 6]  # no better epoch in 5 and 6: stopped
    fitted, weight, _ = scripted(tmp_path / "b", [0.5, 0.3, 0.4, 0.2, 0.6, 0.7, 0.1], patience=0)
    assert fitted.best_epoch == 7 and weight == 7.0 and len(fitted.log) == 7  # patience 0: every epoch
    fitted, weight, _ = scripted(tmp_path / "c", [0.5, 0.5, 0.5], patience=0)
    assert fitted.best_epoch == 1 and weight == 1.0  # a tie keeps the earlier epoch
