"""PACER's manifest: its paper, stages, figures, headline rows, claims registry and profile checks
(``navlab.core.track``; the pipeline reads it through ``navlab.tracks``)."""

from navlab.core.track import Figure, Paper, Track, artifact_stage, notebook_stage

_TRAIN = ("pacer.seed", "pacer.data", "pacer.model", "pacer.train.examples_per_epoch",
          "pacer.train.val_examples", "pacer.train.batch_size", "pacer.train.lr", "pacer.train.lr_final_fraction",
          "pacer.train.patience", "pacer.train.device", "pacer.train.threads", "pacer.train.select_on",
          "pacer.train.select_windows", "pacer.evaluation.cost_scale",  # results follow the device and threads
          # the losses beside Eq. 3
          "pacer.train.match_loss_weight", "pacer.train.contrast_loss_weight", "pacer.train.contrast_margin")
_VARIANT = (*_TRAIN, "pacer.train.epochs")
# the variant stages' outputs (navlab.pacer.variants): the other seeds' phases, the paper architecture's, the
# from-scratch matcher's; the notebooks that read them depend on them
_VARIANT_OUTS = ("artifacts/pacer/variants/seeds", "artifacts/pacer/variants/paper_architecture",
                 "artifacts/pacer/variants/scratch_matcher")
_NOTEBOOK = ("pacer",)
_PHOTOS = "terrain_photos"  # your own photographs (pacer.terrain.OWN_PHOTOS): every stage that reads the bank
_FIGURES = "reports/pacer/figures/"

TRACK = Track(
    name="pacer",
    paper=Paper("PACER", "Preference-conditioned All-terrain Costmap Generation", "https://arxiv.org/abs/2410.23488"),
    stages=(
        artifact_stage("pacer_phase1", (*_TRAIN, "pacer.train.epochs.phase1"), ("data", _PHOTOS),
                       ("artifacts/pacer/phase1",), persist=True),
        artifact_stage("pacer_phase2", (*_TRAIN, "pacer.train.epochs.phase2"),
                       ("data", _PHOTOS, "artifacts/pacer/phase1"), ("artifacts/pacer/phase2",), persist=True),
        artifact_stage("pacer_phase3", (*_TRAIN, "pacer.train.epochs.phase3"),
                       ("data", _PHOTOS, "artifacts/pacer/phase2"), ("artifacts/pacer/phase3",), persist=True),
        artifact_stage("pacer_sterling", ("pacer.seed", "pacer.data", "pacer.train.device",
                                          "pacer.baselines.patch_size", "pacer.baselines.sterling"),
                       ("data", _PHOTOS), ("artifacts/pacer/sterling",)),
        artifact_stage("pacer_classifier", ("pacer.seed", "pacer.data", "pacer.train.device",
                                            "pacer.baselines.patch_size", "pacer.baselines.classifier"),
                       ("data", _PHOTOS), ("artifacts/pacer/classifier",)),
        artifact_stage("pacer_seeds", (*_VARIANT, "pacer.variants.seeds"), ("data", _PHOTOS), _VARIANT_OUTS[:1],
                       persist=True),
        artifact_stage("pacer_paper_architecture", _VARIANT, ("data", _PHOTOS), _VARIANT_OUTS[1:2], persist=True),
        artifact_stage("pacer_scratch_matcher", _VARIANT, ("data", _PHOTOS), _VARIANT_OUTS[2:], persist=True),
        notebook_stage("pacer_01_costmaps", "notebooks/pacer/01_costmaps.ipynb", _NOTEBOOK,
                       ("data", _PHOTOS, "artifacts/pacer/phase3"), (_FIGURES + "01_costmaps",)),
        notebook_stage("pacer_02_navigation", "notebooks/pacer/02_navigation.ipynb", _NOTEBOOK,
                       ("data", _PHOTOS, "artifacts/pacer/phase3", *_VARIANT_OUTS, "artifacts/pacer/sterling",
                        "artifacts/pacer/classifier"),
                       (_FIGURES + "02_navigation",),
                       ("reports/pacer/table1_seen.json", "reports/pacer/table2_unseen.json")),
        notebook_stage("pacer_03_phase_ablation", "notebooks/pacer/03_phase_ablation.ipynb", _NOTEBOOK,
                       ("data", _PHOTOS, "artifacts/pacer/phase1", "artifacts/pacer/phase2", "artifacts/pacer/phase3",
                        *_VARIANT_OUTS),
                       (_FIGURES + "03_phase_ablation",),
                       ("reports/pacer/table3_phases_seen.json", "reports/pacer/table4_phases_unseen.json",
                        "reports/pacer/table5_margin_ranking.json", "reports/pacer/context_following.json")),
    ),
    steps="navlab.pacer.variants:artifact_steps",
    claims="navlab.pacer.claims",
    figures=(Figure("pacer/figures/01_costmaps/fig1_fig4_paths.png",
                    "Figs. 1 and 4: one aerial map, two preference contexts, two costmaps and their paths"),
             Figure("pacer/figures/01_costmaps/fig3_bev_contexts.png",
                    "Fig. 3 style: one BEV image, two contexts, PACER's costmaps beside their targets"),
             Figure("pacer/figures/02_navigation/paths_unseen.png",
                    "Table II: every method's path on the first unseen aerial maps", "table2_unseen"),
             Figure("pacer/figures/01_costmaps/fig5_unseen_paths.png",
                    "Fig. 5: PACER's paths on an unseen aerial map under four preference contexts", "table2_unseen"),
             Figure("pacer/figures/03_phase_ablation/preference_agreement.png",
                    "Held-out preference agreement per training phase", "context_following")),
    headline=(("table1_seen", ("PACER",), ("low",)),
              ("table2_unseen", ("PACER",), ("low",)),
              ("table5_margin_ranking", ("D_synthetic",), ("test_synthetic",))),
    shown=(("context_following", ("agreement",)),),
    profile_checks=("navlab.pacer.profile_check:data_problems", "navlab.pacer.profile_check:model_problems",
                    "navlab.pacer.profile_check:baseline_problems", "navlab.pacer.profile_check:variant_problems"),
    plots=tuple((f"artifacts/pacer/phase{k}/val_loss.tsv", "epoch", ("train_loss", "val_loss", "select_score"),
                 f"PACER phase {k} ({what}) loss and map-window selection score (pixel-pair AUC) per epoch")
                for k, what in ((1, "D_real"), (2, "D_real + D_shuffled"), (3, "+ D_synthetic"))),
)
