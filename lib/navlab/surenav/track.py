"""SuReNav's manifest: its paper, stages, figures, headline rows, claims registry and profile checks
(``navlab.core.track``; the pipeline reads it through ``navlab.tracks``)."""

from navlab.core.track import Figure, Paper, Track, artifact_stage, notebook_stage

_RUN = ("surenav.graph", "surenav.benchmark", "surenav.model", "surenav.train", "surenav.planner")
_GPS = ("artifacts/surenav/gps", "artifacts/surenav/mpnn")
_CONTEXT_DEMOS = "artifacts/surenav/context_demos"  # issue 25's context benchmark (navlab.surenav.context)
_CONTEXT_GPS = ("artifacts/surenav/context_estimators",)
_CONTEXT_DRAW = tuple(f"surenav.demos.context.{k}"
                      for k in ("seed", "test_pairs_per_map", "train_pairs_per_map", "val_tiles", "max_train_tiles"))
_CONTEXT_TRAIN = ("surenav.demos.context.node_features", "surenav.demos.context.estimator")
_FIGURES = "reports/surenav/figures/"

_CONTEXT = (_CONTEXT_DEMOS, *_CONTEXT_GPS)
_CONTEXT_MAIN_LOG = "artifacts/surenav/context_estimators/context_straight_through_fp-closed/seed0/log.tsv"  # main_run's
# folder on default (training.main_run; tests/test_surenav_context_benchmark.py checks it)

TRACK = Track(
    name="surenav",
    paper=Paper("SuReNav", "Superpixel Graph-based Constraint Relaxation for Navigation in Over-constrained "
                "Environments", "https://arxiv.org/abs/2602.06807"),
    stages=(
        artifact_stage("surenav_estimator", ("surenav.graph", "surenav.model", "surenav.train"), ("data",), _GPS,
                       persist=True),
        artifact_stage("surenav_episodes", ("surenav.graph", "surenav.benchmark.seed", "surenav.benchmark.episodes",
                                            "surenav.benchmark.executor.window_margin_m"), ("data",),
                       ("artifacts/surenav/episodes",)),
        notebook_stage("surenav_dataset", "notebooks/surenav/00_dataset.ipynb", ("surenav.graph",), ("data",),
                       tuple(_FIGURES + f"dataset_{n}.png"
                             for n in ("maps", "region_graphs", "demonstrations", "statistics"))),
        artifact_stage("surenav_context_demos", ("data.maps", "data.demos", "surenav.graph", *_CONTEXT_DRAW), ("data",),
                       (_CONTEXT_DEMOS,)),
        artifact_stage("surenav_context_estimator", ("surenav.graph", "surenav.model", "surenav.train",
                                                     *_CONTEXT_TRAIN), (_CONTEXT_DEMOS,), _CONTEXT_GPS,
                       persist=True),
        notebook_stage("surenav_01_human_likeness", "notebooks/surenav/01_human_likeness.ipynb",
                       (*_RUN, *_CONTEXT_TRAIN), _CONTEXT,
                       metrics=("reports/surenav/table1_human_likeness.json",
                                "reports/surenav/table1_cities_held_out.json")),
        notebook_stage("surenav_02_safety_efficiency", "notebooks/surenav/02_safety_efficiency.ipynb",
                       (*_RUN, *_CONTEXT_TRAIN), ("data", *_CONTEXT, "artifacts/surenav/episodes"),
                       (_FIGURES + "fig4_safety_efficiency.png",), ("reports/surenav/fig4_safety_efficiency.json",)),
        notebook_stage("surenav_03_behaviours", "notebooks/surenav/03_behaviours.ipynb", (*_RUN, *_CONTEXT_TRAIN),
                       ("data", *_CONTEXT, "artifacts/surenav/episodes"), (_FIGURES + "fig5_behaviours.png",)),
        notebook_stage("surenav_04_learned_costs", "notebooks/surenav/04_learned_costs.ipynb",
                       ("surenav.graph", "surenav.model", "surenav.train", "surenav.planner", *_CONTEXT_TRAIN),
                       _CONTEXT, (_FIGURES + "04_training_curves.png", _FIGURES + "fig6_learned_costs.png"),
                       ("reports/surenav/estimator_relaxation_iou.json",)),
        notebook_stage("surenav_05_per_label_control", "notebooks/surenav/05_per_label_control.ipynb", _RUN,
                       ("data", *_GPS), metrics=("reports/surenav/table1_per_label_control.json",)),
    ),
    steps="navlab.surenav.steps:artifact_steps",
    data_steps="navlab.surenav.steps:data_steps",
    claims="navlab.surenav.claims",
    figures=(Figure("surenav/figures/fig5_behaviours.png",
                    "Fig. 5: each method's executed path on one safety-efficiency episode per test city (every "
                    "method trained on context demonstrations)"),
             Figure("surenav/figures/fig4_safety_efficiency.png", "Fig. 4: SPL against total risk per test city",
                    "fig4_safety_efficiency"),
             Figure("surenav/figures/fig6_learned_costs.png",
                    "Fig. 6: learned relaxation costs on two context test scenarios (bright = cheap to relax)",
                    "estimator_relaxation_iou")),
    headline=(("table1_human_likeness", ("SuReNav",), ("frechet", "relaxation_iou")),
              ("fig4_safety_efficiency", ("SuReNav", "milan"), ("sr",))),
    shown=(("fig4_safety_efficiency", ("sr", "spl", "total_risk")),
           ("estimator_relaxation_iou", ("val_iou", "test_iou")),
           ("table1_cities_held_out", ("relaxation_iou_all_cities", "relaxation_iou_held_out", "relaxation_iou_delta",
                                       "frechet_delta"))),
    profile_checks=("navlab.surenav.profile_check:model_problems",),
    plots=((_CONTEXT_MAIN_LOG, "epoch", ("train_loss", "val_loss", "val_iou", "train_iou"),
            ("SuReNav context estimator (the paper's loss and gradient, seed 0) Eq. 13 loss and validation / train "
             "plan relaxation IoU per epoch")),
           ("artifacts/surenav/gps/seed0/log.tsv", "epoch", ("train_loss", "val_loss", "val_iou", "train_iou"),
            "SuReNav per-label control estimator (GPS, seed 0) per epoch")),
)
