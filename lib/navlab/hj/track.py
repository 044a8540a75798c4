"""HJ-search's manifest: its paper, stages, figures, headline rows, claims registry and profile checks
(``navlab.core.track``; the pipeline reads it through ``navlab.tracks``)."""

from navlab.core.track import Figure, Paper, Track, artifact_stage, notebook_stage

_SEARCH = ("hj.seed", "hj.grids", "hj.planner")
_LOOP = ("hj.grids", "hj.planner", "hj.dynamic")
_MARGINS = "artifacts/hj_margins"  # static-BRT margins (hj_margins), read by the stages that search
_SWEEP = "artifacts/hj_sensitivity"  # issue 26's sensitivity points (hj_sweep), one JSON per point
_FIGURES = "reports/hj/figures/"

TRACK = Track(
    name="hj",
    paper=Paper("HJ-search", "A Hamilton-Jacobi Reachability-Guided Search Framework for Efficient and Safe Indoor "
                "Planar Robot Navigation", "https://arxiv.org/abs/2604.17679"),
    stages=(
        artifact_stage("hj_grids", ("hj.grids",), (), ("artifacts/hj",), persist=True),
        artifact_stage("hj_margins", ("hj.grids", "hj.planner.brt_margin_refine"), ("artifacts/hj",), (_MARGINS,),
                       persist=True),
        notebook_stage("hj_value_functions", "notebooks/hj/00_value_functions.ipynb", ("hj.grids",), ("artifacts/hj",),
                       (_FIGURES + "value_functions", "reports/hj/value_functions_scene.html"),
                       ("reports/hj/fig2_heuristic_values.json", "reports/hj/fig3_brt_growth.json")),
        notebook_stage("hj_heuristics", "notebooks/hj/01_heuristics.ipynb", _SEARCH, ("artifacts/hj", _MARGINS),
                       (_FIGURES + "fig6_anastar_ttr.png",),
                       ("reports/hj/table1_heuristics_astar.json", "reports/hj/table2_heuristics_anastar.json")),
        notebook_stage("hj_pruning", "notebooks/hj/02_pruning.ipynb", _SEARCH, ("artifacts/hj", _MARGINS),
                       (_FIGURES + "fig7_obs_vs_brt.png",),
                       ("reports/hj/table3_pruning_astar.json", "reports/hj/table4_pruning_anastar.json",
                        "reports/hj/table5_static_general.json")),
        notebook_stage("hj_dynamic", "notebooks/hj/03_dynamic.ipynb", _LOOP, ("artifacts/hj", _MARGINS),
                       (_FIGURES + "fig8_face_to_face.png",), ("reports/hj/table6_dynamic.json",)),
        notebook_stage("hj_rooms", "notebooks/hj/04_rooms.ipynb", _LOOP, ("artifacts/hj", _MARGINS),
                       (_FIGURES + "fig10_dense_snapshots.png", _FIGURES + "patrol_fi_brt.gif",
                        "reports/hj/patrol_fi_brt_scene.html"),
                       ("reports/hj/table8_rooms.json", "reports/hj/table9_humans.json")),
        notebook_stage("hj_compute", "notebooks/hj/05_compute.ipynb", _SEARCH, ("artifacts/hj", _MARGINS),
                       metrics=("reports/hj/table7_compute.json",)),
        # issue 26's curves: each point cached (resumable) under artifacts/hj_sensitivity by hj_sweep, which a
        # queued DVC experiment runs for one point (navlab.pipeline.experiments); the notebook assembles them
        artifact_stage("hj_sweep", (*_LOOP, "hj.seed", "hj.sensitivity"), ("artifacts/hj", _MARGINS),
                       (_SWEEP,), persist=True),
        notebook_stage("hj_sensitivity", "notebooks/hj/06_sensitivity.ipynb", (*_LOOP, "hj.seed", "hj.sensitivity"),
                       ("artifacts/hj", _MARGINS, _SWEEP, "reports/hj/table6_dynamic.json"),  # Table VI's own points
                       tuple(_FIGURES + f"sensitivity_{k}.png"
                             for k in ("budget", "replan_hz", "human_noise_m", "human_prediction_s")),
                       ("reports/hj/sensitivity_budget.json", "reports/hj/sensitivity_loop.json")),
    ),
    steps="navlab.hj.artifacts:artifact_steps",
    claims="navlab.hj.claims",
    figures=(Figure("hj/figures/fig10_dense_snapshots.png", "Fig. 10: TTR + OBS against TTR + BRT in the Dense Room",
                    "table8_rooms"),
             Figure("hj/figures/fig8_face_to_face.png", "Fig. 8: FI-BRT, FS-BRT and OBS meeting a human head-on",
                    "table6_dynamic"),
             Figure("hj/figures/value_functions/fig2_heuristics.png",
                    "Fig. 2: map TTR, general TTR, map Dist and general Dist at one robot, heading up and reversed",
                    "fig2_heuristic_values"),
             Figure("hj/figures/value_functions/fig3_brt_slices.png",
                    "Fig. 3: the static BRT at four speeds (heading 0): it grows with speed", "fig3_brt_growth"),
             Figure("hj/figures/value_functions/human_brt.png",
                    "The human-robot BRT in the robot's frame at three robot speeds (the pruner of Sec. VII-D)",
                    "fig3_brt_growth"),
             Figure("hj/value_functions_scene.html",
                    "The static BRT's zero level set over the room in 3D, (x, y, θ) at 0.6 m/s (meshcat, offline HTML)",
                    "fig3_brt_growth"),
             Figure("hj/figures/fig6_anastar_ttr.png",
                    "Fig. 6: ANA* with TTR from the most misaligned start: a slight reversal, then the turn",
                    "table2_heuristics_anastar"),
             Figure("hj/figures/fig7_obs_vs_brt.png", "Fig. 7: OBS against BRT pruning from the 30° start",
                    "table4_pruning_anastar"),
             Figure("hj/figures/patrol_fi_brt.gif",
                    "Fig. 11 style: the FI-BRT car's patrol among one human (5x real time; orange: the human positions "
                    "inside the BRT at the car's speed)", "table9_humans"),
             Figure("hj/figures/sensitivity_budget.png", "Table VIII against ANA*'s expansions per re-plan (ours)",
                    "sensitivity_budget"),
             *(Figure(f"hj/figures/sensitivity_{axis}.png", f"Table VI against the {what} (ours)", "sensitivity_loop")
               for axis, what in (("replan_hz", "re-planning rate"), ("human_noise_m", "human-position noise"),
                                  ("human_prediction_s", "prediction horizon")))),
    headline=(("table5_static_general", ("TTR + BRT",), ("success", "nodes_common")),
              ("table6_dynamic", ("FI-BRT", "Face-to-Face"), ("success",)),
              ("table8_rooms", ("TTR + BRT", "Dense Room"), ("success",))),
    before=("fig2_heuristic_values", "fig3_brt_growth"),  # Sec. VI's figures come before its Table I
    profile_checks=("navlab.hj.profile_check:grid_problems",),
)
