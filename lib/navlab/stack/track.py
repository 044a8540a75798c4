"""The stack's manifest (issue 64): not a paper, the join of the three (``navlab.core.track``; the pipeline
reads it through ``navlab.tracks``). It holds no claims registry: no paper states what the stack should do."""

from navlab.core.track import Figure, Paper, Track, notebook_stage

TRACK = Track(
    name="stack",
    paper=Paper("navlab stack", "One navigation stack from the three papers: PACER's terrain costs, SuReNav's "
                "relaxation, HJ-search's planner among people, and its one-layer ablation (ours)",
                "../docs/design.md#layers-the-import-rule"),
    stages=(
        notebook_stage("stack_01_ablation", "notebooks/stack/01_ablation.ipynb",
                       ("stack", "pacer", "surenav", "hj.grids", "hj.planner", "data.maps"),
                       ("data", "terrain_photos", "artifacts/pacer/phase3", "artifacts/surenav/context_demos",
                        "artifacts/surenav/context_estimators", "artifacts/hj"),
                       ("reports/stack/figures",),
                       ("reports/stack/stack_ablation.json", "reports/stack/stack_layer_effects.json")),
    ),
    figures=(Figure("stack/figures/episode.png",
                    "One episode: the route and the regions it relaxed, PACER's costs, each row's robot track and "
                    "the pedestrians' tracks", "stack_ablation"),),
    headline=(("stack_ablation", ("stack (PACER + SuReNav + HJ-search)",), ("success", "low_tier", "spl")),),
)
