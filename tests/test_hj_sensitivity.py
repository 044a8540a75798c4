"""Issue 26's sensitivity sweeps: the points asked for, their cache keys and reuse, and the claims' verdicts
as the range of settings where they hold."""

from __future__ import annotations

import dataclasses

import pytest

from navlab.core.params import load_params
from navlab.hj import sensitivity as hs
from navlab.hj import sweeps as hj_sweeps
from navlab.hj.sweeps import Point, point_key, run_sweep, sweep_points


def test_holding_range_names_prefix_suffix_all_none_and_scattered_points():
    v = [1500, 3000, 6000, 12000]
    assert hs.holding_range(v, [True] * 4, "exp").startswith("holds at every point")
    assert hs.holding_range(v, [False] * 4, "exp").startswith("holds at none")
    assert hs.holding_range(v, [True, True, False, False], "exp").startswith("holds at <= 3,000 exp, not from 6,000")
    assert hs.holding_range(v, [False, False, True, True], "exp").startswith("holds at >= 6,000 exp")
    assert hs.holding_range(v, [True, False, True, False], "exp").startswith("holds at 1,500, 6,000 exp only")
    assert hs.holding_range([12.0, 3.0], [False, True], "Hz").startswith("holds at <= 3 Hz")  # sorted first


def _room_rows(successes: dict[int, dict[str, int]], room: str, trips: int) -> list[dict]:
    return [{"method": m, "room": room, "budget": b, "success": k, "trips": trips}
            for b, cell in successes.items() for m, k in cell.items()]


def test_budget_claims_hold_only_where_every_point_does():
    hallway = {1500: {"Dist + OBS": 2, "Dist + BRT": 3, "TTR + OBS": 9, "TTR + BRT": 9},
               6000: {"Dist + OBS": 9, "Dist + BRT": 9, "TTR + OBS": 9, "TTR + BRT": 9}}
    dense = {1500: {"Dist + OBS": 0, "Dist + BRT": 1, "TTR + OBS": 0, "TTR + BRT": 6},
             6000: {"Dist + OBS": 0, "Dist + BRT": 2, "TTR + OBS": 4, "TTR + BRT": 6}}
    claims = hs.budget_claims(_room_rows(hallway, "Long Hallway", 9) + _room_rows(dense, "Dense Room", 6))
    assert claims[0].claim == "in the Long Hallway TTR succeeds more often than Dist under both pruners"
    assert claims[0].verdict == "inconclusive" and claims[0].ours.startswith("holds at <= 1,500")
    assert claims[1].claim == "in the Dense Room only TTR + BRT succeeds on every trip"
    assert claims[1].verdict == "holds" and claims[1].ours.startswith("holds at every")


def test_loop_claims_follow_each_axis_with_the_others_at_the_tables_own():
    own = (12.0, 0.0, 1.5)
    rows = []
    for hz, noise, ahead, fs in ((12.0, 0.0, 1.5, 5), (3.0, 0.0, 1.5, 5), (12.0, 0.0, 0.0, 2)):
        for scenario in ("Face-to-Face", "Zig-Zag"):
            for method, k in (("FI-BRT", 5), ("FS-BRT", fs if scenario == "Face-to-Face" else 5), ("OBS", 0)):
                rows.append({"method": method, "scenario": scenario, "replan_hz": hz, "human_noise_m": noise,
                             "human_prediction_s": ahead, "success": k, "runs": 5})
    claims = hs.loop_claims(rows, own)
    face = [c for c in claims if c.claim.startswith("FI-BRT clears every Face-to-Face")]
    assert len(face) == 2  # the rate and the prediction axes have two points each; noise has one
    assert face[0].claim.endswith("along Hz re-planning") and face[0].verdict == "does not hold"
    assert face[1].claim.endswith("along s of human prediction") and face[1].verdict == "inconclusive"
    assert face[1].ours.startswith("holds at <= 0 s")
    zig = [c for c in claims if c.claim.startswith("FI-BRT and FS-BRT clear every Zig-Zag")]
    assert zig and all(c.verdict == "holds" for c in zig)


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
