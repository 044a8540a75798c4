"""Issue 26's sensitivity sweeps: the points asked for, their cache keys and reuse, and the rows along each
curve (the checks along them, ours: tests/test_hj_claims.py)."""

from __future__ import annotations

import dataclasses

import pytest

from navlab.core.params import load_params
from navlab.hj import sensitivity as hs
from navlab.hj import sweeps as hj_sweeps
from navlab.hj.sweeps import Point, point_key, run_sweep, sweep_points


def test_loop_curve_keeps_the_other_two_settings_at_the_tables_own():
    rows = [{"replan_hz": hz, "human_noise_m": noise, "human_prediction_s": 1.5}
            for hz, noise in ((12.0, 0.0), (3.0, 0.0), (3.0, 0.1), (12.0, 0.1))]
    assert hs.loop_curve(rows, "replan_hz", (12.0, 0.0, 1.5)) == rows[:2]
    assert hs.loop_curve(rows, "human_noise_m", (12.0, 0.0, 1.5)) == [rows[0], rows[3]]


def test_sweep_points_share_the_tables_own_setting_once():
    params = load_params("default")
    points = sweep_points(params)
    loops = [p.value for p in points if p.kind == "loop"]
    assert len(loops) == len(set(loops))
    own = (params.hj.dynamic.closed_loop.replan_hz, params.hj.dynamic.table6.human_noise_m,
           params.hj.dynamic.closed_loop.human_prediction_s)
    assert own in loops and [p.value for p in points if p.kind == "budget"] == list(params.hj.sensitivity.budgets)
    with pytest.raises(ValueError, match="sweep point kind"):
        hj_sweeps._applied(params, Point("period", 3.0))


def test_point_results_are_cached_on_their_inputs_and_resumed(tmp_path, monkeypatch):
    params = load_params("smoke")
    params = dataclasses.replace(params, hj=dataclasses.replace(params.hj, sensitivity=dataclasses.replace(
        params.hj.sensitivity, budgets=(10, 20), replan_hz=(), human_noise_m=(), human_prediction_s=())))
    (tmp_path / "hj").mkdir()
    (tmp_path / "hj_margins").mkdir()
    calls = []

    def fake(p, point, artifacts_dir):
        calls.append(point.value)
        applied = hj_sweeps._applied(p, point).hj.dynamic.closed_loop.max_expansions
        return {"kind": point.kind, "value": point.value, "rows": [{"expansions": applied}]}

    monkeypatch.setattr(hj_sweeps, "run_point", fake)
    first = run_sweep(params, tmp_path, progress=False)
    assert calls == [10, 20] and [r["rows"][0]["expansions"] for r in first] == [10, 20]  # the point's change applied
    assert run_sweep(params, tmp_path, progress=False) == first and calls == [10, 20]  # read back, not re-run
    (tmp_path / "hj" / "grid.npz").write_bytes(b"changed")  # an input changed: every point re-runs
    run_sweep(params, tmp_path, progress=False)
    assert calls == [10, 20, 10, 20]
    assert len(list((tmp_path / "hj_sensitivity").glob("*.json"))) == 2  # stale results removed
    assert point_key(params, Point("budget", 10), tmp_path) != point_key(params, Point("budget", 20), tmp_path)
