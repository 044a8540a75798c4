"""Issue 26's sensitivity sweeps: the points asked for, their cache keys and reuse, and the rows along each
curve (the checks along them, ours: tests/test_hj_claims.py)."""

from __future__ import annotations

import dataclasses
import json

import pytest

from navlab.core.io import DataError
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


def _with_loop_points(params, prediction_s):
    return dataclasses.replace(params, hj=dataclasses.replace(params.hj, sensitivity=dataclasses.replace(
        params.hj.sensitivity, budgets=(10,), replan_hz=(3.0,), human_noise_m=(), human_prediction_s=prediction_s)))


def test_table_vis_own_points_are_its_rows_and_are_not_run(tmp_path, monkeypatch):
    """The loop points at Table VI's own rate and noise are its paper rows (at its horizon) and its prediction
    variant rows (OBS never predicts): read from its report in the sweep's row order, never simulated."""
    params = _with_loop_points(load_params("smoke"), (0.0, 1.5))
    d = params.hj.dynamic
    own, ahead = (d.closed_loop.replan_hz, d.table6.human_noise_m), d.closed_loop.prediction_variant_s
    points = hj_sweeps.sweep_points(params)
    names = {p.name: hj_sweeps.table_rows(params, p) for p in points}
    assert names[Point("loop", (*own, 0.0)).name] == {"FI-BRT": "FI-BRT", "FS-BRT": "FS-BRT", "OBS": "OBS"}
    assert names[Point("loop", (*own, ahead)).name] == {
        "FI-BRT": f"FI-BRT ({ahead:g} s prediction, ours)", "FS-BRT": f"FS-BRT ({ahead:g} s prediction, ours)",
        "OBS": "OBS"}
    assert names[Point("loop", (3.0, own[1], 0.0)).name] is None and names["budget-10"] is None
    assert [p.name for p in hj_sweeps.points_to_run(params)] == ["budget-10", Point("loop", (3.0, own[1], 0.0)).name]

    (tmp_path / "hj").mkdir()
    (tmp_path / "hj_margins").mkdir()
    ran = []
    monkeypatch.setattr(hj_sweeps, "run_point", lambda p, point, a: ran.append(point.name) or
                        {"kind": point.kind, "value": point.value, "rows": []})
    assert [r["value"] for r in run_sweep(params, tmp_path, progress=False)] == [10, [3.0, own[1], 0.0]]
    report = tmp_path / "table6_dynamic.json"
    with pytest.raises(DataError, match="table6_dynamic.json is missing.*dvc repro hj_dynamic"):
        run_sweep(params, tmp_path, progress=False, table6=report)
    rows = [{"method": m, "scenario": s, "runs": d.table6.runs, "success": i}
            for i, (m, s) in enumerate((m, s) for s in hj_sweeps.SCENARIOS for m in (
                "OBS", "FI-BRT", "FS-BRT", f"FI-BRT ({ahead:g} s prediction, ours)", f"FS-BRT ({ahead:g} s prediction, ours)"))]
    report.write_text(json.dumps({"profile": "smoke", "rows": rows}))
    results = run_sweep(params, tmp_path, progress=False, table6=report)
    assert ran == ["budget-10", Point("loop", (3.0, own[1], 0.0)).name]  # cached since; Table VI's never run
    assert [r["value"] for r in results] == [json.loads(json.dumps(p.value)) for p in points]  # point order
    predicted = next(r for r in results if r["value"] == [*own, ahead])
    assert [(r["method"], r["scenario"], r["success"]) for r in predicted["rows"]] == [
        ("FI-BRT", "Face-to-Face", 3), ("FS-BRT", "Face-to-Face", 4), ("OBS", "Face-to-Face", 0),
        ("FI-BRT", "Zig-Zag", 8), ("FS-BRT", "Zig-Zag", 9), ("OBS", "Zig-Zag", 5)]
    report.write_text(json.dumps({"profile": "default", "rows": rows}))
    with pytest.raises(DataError, match="not this profile's Table VI"):
        run_sweep(params, tmp_path, progress=False, table6=report)
